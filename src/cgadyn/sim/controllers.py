"""Feedback laws that ``simulate`` evaluates inside its compiled loop, at every stage.

``PD``: joint-space proportional-derivative control around a reference, plus (by default)
gravity compensation,

    τ_ctrl = K_p (q_ref ⊖ q) + K_d (v_ref - v) + g(q),   g(q) = RNEA(q, 0, 0),

with ``q_ref ⊖ q`` the difference on the configuration manifold (``cgadyn.difference``:
an unbounded revolute joint's error wrapped to (-π, π], a free flyer's as a body twist).
``GravityCompensation``: ``τ_ctrl = g(q)`` alone. Gains are non-negative, one number for
every joint or one per velocity coordinate (nv); their shapes are checked against the model
when ``simulate`` runs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .rollout import GRAVITY
from .rollout import PD as _PD_FLAG


def _gain(x, name: str) -> np.ndarray:
    try:
        g = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of numbers (one per velocity "
                         f"coordinate), got {x!r}") from None
    if g.ndim > 1:
        raise ValueError(f"{name} must be a number or a 1-d array (nv,), got shape {g.shape}")
    if not np.all(np.isfinite(g)):
        raise ValueError(f"{name} must be finite, got {x!r}")
    if np.any(g < 0):
        raise ValueError(f"{name} must be non-negative (a negative gain destabilises), "
                         f"got {x!r}")
    return g


@dataclass(frozen=True, eq=False)
class PD:
    """``τ = K_p (q_ref ⊖ q) + K_d (v_ref - v) [+ g(q)]``.

    ``kp``, ``kd``: numbers or arrays (nv,); ``q_ref`` (nq,): the configuration to hold, by
    default each rollout's initial one; ``v_ref`` (nv,): by default zero;
    ``gravity_compensation``: add ``g(q)`` (with the simulation's gravity).
    """

    kp: object
    kd: object
    q_ref: object = None
    v_ref: object = None
    gravity_compensation: bool = True

    def __post_init__(self):
        object.__setattr__(self, "kp", _gain(self.kp, "kp"))
        object.__setattr__(self, "kd", _gain(self.kd, "kd"))

    def flags(self) -> int:
        return _PD_FLAG | (GRAVITY if self.gravity_compensation else 0)


@dataclass(frozen=True)
class GravityCompensation:
    """``τ = g(q) = RNEA(q, 0, 0)``: holds a robot at rest wherever it is."""

    def flags(self) -> int:
        return GRAVITY
