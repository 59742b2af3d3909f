"""Passive joint torques: damping and springs of the joints and of fixed tendons (MuJoCo's
``qfrc_passive`` without fluid forces or gravity compensation; ``docs/joints.md``, P1, P2).

    τ_passive = -damping ∘ v - stiffness ∘ (q - spring_reference)                    (P1)
              + Σ_t c_t (-k_t dev_t(c_t · q) - b_t c_t · v)                          (P2)

per velocity coordinate (``Model.damping``, ``Model.stiffness``, ``Model.spring_reference``;
springs only on joints whose coordinates add, ``joints.table.spring_deflection``), and per
fixed tendon t of length ``L = c_t · q`` (``Model.tendon_coefficients``, ``tendon_stiffness``,
``tendon_damping``): ``dev_t(L)`` is how far L lies outside the relaxed lengths
``[L_lo, L_hi]`` (``tendon_spring_length``, MuJoCo's dead band), 0 inside. They are
not part of ``rnea`` or ``aba``, which are the rigid-body dynamics that Pinocchio computes:
add them to the applied torques, as ``cgadyn.simulate`` does by default. Plain numpy: a
product per coordinate, no recursion.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints.table import additive_values, spring_deflection


def _state(model, x, size: int, name: str) -> np.ndarray:
    try:
        out = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of numbers, got {type(x).__name__}") \
            from None
    if out.ndim not in (1, 2) or out.shape[-1] != size:
        raise ValueError(f"{name} must have shape ({size},) or (B, {size}) for "
                         f"{model.name!r}, got {out.shape}")
    return out


def passive_torques(model, q, v) -> np.ndarray:
    """``-damping ∘ v - stiffness ∘ (q - spring_reference)`` plus the fixed tendons' spring
    and damper forces (P1, P2), (nv,) or (B, nv): the passive torques at the state
    ``(q, v)`` (MuJoCo's ``qfrc_passive``, without fluid forces)."""
    q = _state(model, q, model.nq, "q")
    v = _state(model, v, model.nv, "v")
    if q.ndim != v.ndim or q.shape[:-1] != v.shape[:-1]:
        raise ValueError(f"q {q.shape} and v {v.shape} must hold the same samples")
    tau = -model.damping * v - model.stiffness * spring_deflection(model, q)
    if model.tendon_names:
        tau = tau + tendon_forces(model, q, v)
    return tau


def tendon_forces(model, q, v) -> np.ndarray:
    """The fixed tendons' spring and damper torques (P2), (..., nv)."""
    C = model.tendon_coefficients
    length, rate = additive_values(model, q) @ C.T, np.asarray(v) @ C.T
    lo, hi = model.tendon_spring_length[:, 0], model.tendon_spring_length[:, 1]
    dev = np.where(length > hi, length - hi, np.where(length < lo, length - lo, 0.0))
    return (-model.tendon_stiffness * dev - model.tendon_damping * rate) @ C
