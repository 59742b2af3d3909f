"""Passive joint torques: damping and springs (MuJoCo's ``qfrc_passive`` without fluid
forces, gravity compensation or tendons).

    τ_passive = -damping ∘ v - stiffness ∘ (q - spring_reference)

per velocity coordinate (``Model.damping``, ``Model.stiffness``, ``Model.spring_reference``;
springs only on joints whose coordinates add, ``joints.table.spring_deflection``). They are
not part of ``rnea`` or ``aba``, which are the rigid-body dynamics that Pinocchio computes:
add them to the applied torques, as ``cgadyn.simulate`` does by default. Plain numpy: a
product per coordinate, no recursion.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints.table import spring_deflection


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
    """``-damping ∘ v - stiffness ∘ (q - spring_reference)``, (nv,) or (B, nv): the joint
    dampers' and springs' torques at the state ``(q, v)`` (MuJoCo's ``qfrc_passive`` of
    hinges and slides, without fluid forces)."""
    q = _state(model, q, model.nq, "q")
    v = _state(model, v, model.nv, "v")
    if q.ndim != v.ndim or q.shape[:-1] != v.shape[:-1]:
        raise ValueError(f"q {q.shape} and v {v.shape} must hold the same samples")
    return -model.damping * v - model.stiffness * spring_deflection(model, q)
