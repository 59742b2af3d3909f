"""Euler and RK4 steps of the state (M, B) with motor renormalisation (sections 2.5.2, 2.5.8).

After every step the motor is projected back onto the motor manifold (M M~ = 1) and B onto
grade 2 ("state[0] = state[0].Normalized; state[1] = state[1].Grade(2)", section 2.6.1).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .body import RigidBody, check_state, state_derivative
from .model import PGA

__all__ = ["INTEGRATORS", "euler_step", "normalize_motor", "rk4_step", "step"]

_BINOMIAL = [1.0, -0.5, 0.375, -0.3125, 0.2734375, -0.24609375]  # C(-1/2, k)


def normalize_motor(model: PGA, m) -> np.ndarray:
    """M / sqrt(M M~): the nearest motor (section 2.5.8 'Renormalizing a Motor').

    d = 3: the paper's closed form with the Study number M M~ = a + b e0123,
    M' = s M - s^3 (b/2) M e0123, s = 1/sqrt(a). Other d: N = M M~ is self-reverse with grades
    0 and 4; M' = N^(-1/2) M with N^(-1/2) from the binomial series in N/a - 1 (which is
    nilpotent for d <= 3, where this reduces to the closed form; small in 4D).
    """
    m = model.grade(m, 0) + sum(model.grade(m, k) for k in range(2, model.d + 2, 2))
    if model.d == 3:
        return _normalize_motor_3d(model, m)
    return _normalize_motor_series(model, m)


def _normalize_motor_series(model: PGA, m) -> np.ndarray:
    """N^(-1/2) M with N = M M~, for any d (the general path of ``normalize_motor``)."""
    n = model.gp(m, model.reverse(m))
    a = n[..., :1]
    if np.any(a <= 0):
        raise ValueError("cannot normalise a motor with zero Euclidean norm")
    m = m / np.sqrt(a)
    delta = n / a - model.scalar()
    y, power = model.scalar(np.ones(n.shape[:-1])), model.scalar(np.ones(n.shape[:-1]))
    for c in _BINOMIAL[1:]:
        power = model.gp(power, delta)
        if not np.any(power):
            break
        y = y + c * power
    return model.gp(y, m)


def _normalize_motor_3d(model: PGA, m) -> np.ndarray:
    """Closed form of section 2.5.8 (basis names e13 = -e31 of the paper)."""
    ix = model.algebra.blade
    s0, m12, m13, m23 = (m[..., ix(k)] for k in ("1", "e12", "e13", "e23"))
    m01, m02, m03, i4 = (m[..., ix(k)] for k in ("e01", "e02", "e03", "e0123"))
    a = s0**2 + m12**2 + m13**2 + m23**2
    if np.any(a <= 0):
        raise ValueError("cannot normalise a motor with zero Euclidean norm")
    s = 1.0 / np.sqrt(a)
    d = s**2 * (s0 * i4 - m01 * m23 + m02 * m13 - m03 * m12)  # b/2 s^2
    mi = np.zeros(m.shape)  # M e0123 = s0 e0123 - m12 e03 + m13 e02 - m23 e01
    mi[..., ix("e0123")], mi[..., ix("e03")] = s0, -m12
    mi[..., ix("e02")], mi[..., ix("e01")] = m13, -m23
    return s[..., None] * (m - d[..., None] * mi)


Forque = Callable[[np.ndarray, np.ndarray, float], np.ndarray]


def euler_step(body: RigidBody, forque: Forque | None, m, b, h: float, t: float = 0.0):
    """S_{t+h} = S_t + h dS/dt (section 2.5.2)."""
    dm, db = state_derivative(body, forque, m, b, t)
    return m + h * dm, b + h * db


def rk4_step(body: RigidBody, forque: Forque | None, m, b, h: float, t: float = 0.0):
    """Classical RK4 (section 2.5.8): y + h/6 (k1 + 2 k2 + 2 k3 + k4)."""
    k1 = state_derivative(body, forque, m, b, t)
    k2 = state_derivative(body, forque, m + 0.5 * h * k1[0], b + 0.5 * h * k1[1], t + 0.5 * h)
    k3 = state_derivative(body, forque, m + 0.5 * h * k2[0], b + 0.5 * h * k2[1], t + 0.5 * h)
    k4 = state_derivative(body, forque, m + h * k3[0], b + h * k3[1], t + h)
    m = m + (h / 6.0) * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
    b = b + (h / 6.0) * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return m, b


INTEGRATORS = {"euler": euler_step, "rk4": rk4_step}


def get_integrator(name: str):
    """The step function by name; ValueError naming the choices otherwise."""
    try:
        return INTEGRATORS[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown integrator {name!r}; expected one of {', '.join(sorted(INTEGRATORS))}"
        ) from None


def step(body: RigidBody, forque, m, b, h: float, t: float = 0.0, integrator: str = "rk4"):
    """One step of the named integrator, then M renormalised and B projected on grade 2."""
    fn = get_integrator(integrator)
    if not np.isfinite(h) or h <= 0:
        raise ValueError(f"step size h must be finite and > 0, got {h}")
    model = body.model
    m, b = check_state(model, m, b)
    m, b = fn(body, forque, m, b, h, t)
    return normalize_motor(model, m), model.grade(b, 2)
