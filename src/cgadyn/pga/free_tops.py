"""Closed-form free motions of Appendix B, to check the integrated law of motion against.

All in the body frame at the centroid, principal axes, without forques; B0 = **B**0 + eps v0
is the initial body rate, M0 the initial motor.
"""

from __future__ import annotations

import numpy as np

from .model import PGA

__all__ = [
    "euler_top_coefficients",
    "spherical_top",
    "split_free_derivative",
    "symmetric_top_motor",
]


def _euclidean(model: PGA, b) -> np.ndarray:
    out = np.zeros(np.shape(b))
    out[..., model.eij] = np.asarray(b)[..., model.eij]
    return out


def split_free_derivative(model: PGA, moments, b) -> np.ndarray:
    """Eq. (B.1)-(B.2): dB/dt = eps(-v . **B**) + I_C^-1[**B** × I_C[**B**]] for B = **B** +
    eps v, with the classical bivector inertia I_C = i_ij on e_ij (no mass: it drops out)."""
    b = np.asarray(b, dtype=float)
    bold = _euclidean(model, b)
    v = model.zeros(b.shape[:-1])
    v[..., model.ei] = b[..., model.e0i]  # eps ∧ v = v_i e0i
    moments = np.asarray(moments, dtype=float)
    ic = np.zeros(b.shape)
    ic[..., model.eij] = bold[..., model.eij] * moments
    rot = model.commutator(bold, ic)
    rot[..., model.eij] = rot[..., model.eij] / moments
    lin = model.lc(v, bold)  # the vector v . **B**
    out = _euclidean(model, rot)
    out[..., model.e0i] = -lin[..., model.ei]
    return out


def _ideal(model: PGA, b) -> np.ndarray:
    out = np.zeros(np.shape(b))
    out[..., model.e0i] = np.asarray(b)[..., model.e0i]
    return out


def spherical_top(model: PGA, m0, b0, t: float) -> tuple[np.ndarray, np.ndarray]:
    """B.2, eqs. (B.5)-(B.6): equal principal moments.

    B_b(t) = **B**0 + M~_B0 (eps v0) M_B0 and M(t) = exp(-(eps p/m) t/2) M0 exp(-**B**0 t/2),
    with M_B0 = exp(-**B**0 t/2) and eps p/m = M0 (eps v0) M0~ (world velocity).
    """
    bold, ev = _euclidean(model, b0), _ideal(model, b0)
    mb = model.exp(-0.5 * t * bold)
    rate = bold + model.sandwich(model.reverse(mb), ev)
    ep = model.sandwich(m0, ev)
    motor = model.gp(model.gp(model.exp(-0.5 * t * ep), m0), mb)
    return motor, rate


def symmetric_top_motor(model: PGA, i: float, i3: float, m0, b0, t: float) -> np.ndarray:
    """B.3, eq. (B.15): 3D top with i1 = i2 = i about e23, e13 and i3 about E3 = e12.

    A = (1 - i3/i)[**B**0]_3 E3 (B.9, B.14), L_b/i = **B**0 - A (B.12),
    M = M_p M0 M_Lb M_A with M_X = exp(-X t/2) and eps p/m = M0 (eps v0) M0~.
    """
    if model.d != 3:
        raise ValueError(f"the symmetric top of eq. (B.15) is 3D, got d={model.d}")
    e3 = model.algebra.blade("e12")
    bold, ev = _euclidean(model, b0), _ideal(model, b0)
    a = model.zeros()
    a[e3] = (1.0 - i3 / i) * bold[e3]  # [B]_3 = -<B E3> = coefficient of e12
    lb = bold - a
    ep = model.sandwich(m0, ev)
    mp, ml, ma = (model.exp(-0.5 * t * x) for x in (ep, lb, a))
    return model.gp(model.gp(model.gp(mp, m0), ml), ma)


def euler_top_coefficients(moments_123) -> np.ndarray:
    """Eq. (B.18): omega_k = (i_(k+1) - i_(k+2)) / i_k (cyclic), for principal moments
    (i1, i2, i3) about E1 = e23, E2 = e31, E3 = e12."""
    i1, i2, i3 = (float(x) for x in moments_123)
    return np.array([(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3])
