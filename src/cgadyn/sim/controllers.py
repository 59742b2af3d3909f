"""Feedback laws that ``simulate`` evaluates inside its compiled loop, at every stage.

``PD``: joint-space proportional-derivative control around a reference, plus (by default)
gravity compensation,

    τ_ctrl = K_p (q_ref ⊖ q) + K_d (v_ref - v) + g(q),   g(q) = RNEA(q, 0, 0),

with ``q_ref ⊖ q`` the difference on the configuration manifold (``cgadyn.difference``:
an unbounded revolute joint's error wrapped to (-π, π], a free flyer's as a body twist).
``GravityCompensation``: ``τ_ctrl = g(q)`` alone.

Both act on the actuated coordinates only (``Model.actuated``): a free flyer has no
actuator, so its entries of ``τ_ctrl`` are zero (gravity compensation compensates the
joints, and a floating robot falls unless contact holds it). Gains are non-negative: one
number for every actuated coordinate, one per actuated coordinate, or one per velocity
coordinate (nv) with zeros on the free flyer's; their shapes are checked against the model
when ``simulate`` runs (``actuated_gains``).
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


def actuated_gains(model, gain: np.ndarray, name: str) -> np.ndarray:
    """``gain`` (a number, (n_actuated,) or (nv,)) as (nv,), zero on the coordinates no
    actuator drives; a ``ValueError`` for any other shape, or for a nonzero gain on such a
    coordinate."""
    act = model.actuated
    out = np.zeros(model.nv)
    if gain.shape == ():
        out[act] = gain
    elif gain.shape == (int(act.sum()),) and gain.shape != (model.nv,):
        out[act] = gain
    elif gain.shape == (model.nv,):
        if np.any(gain[~act] != 0.0):
            raise ValueError(f"PD gain {name} acts on the free flyer's coordinates "
                             f"{np.flatnonzero(~act).tolist()}, which no actuator drives; "
                             f"expected zeros there (or one gain per actuated coordinate)")
        out[:] = gain
    elif act.all():
        raise ValueError(f"PD gain {name} must be a number or have shape ({model.nv},), "
                         f"got {gain.shape}")
    else:
        raise ValueError(f"PD gain {name} must be a number, one per actuated coordinate "
                         f"({int(act.sum())},) or one per velocity coordinate "
                         f"({model.nv},), got shape {gain.shape}")
    return out


@dataclass(frozen=True, eq=False)
class PD:
    """``τ = K_p (q_ref ⊖ q) + K_d (v_ref - v) [+ g(q)]``.

    ``kp``, ``kd``: numbers or arrays (``actuated_gains``); ``q_ref`` (nq,): the
    configuration to hold (its actuated coordinates: a free base is not held), by
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
    """``τ = g(q) = RNEA(q, 0, 0)`` on the actuated coordinates: holds a fixed-base robot at
    rest wherever it is; a floating one still falls (its base wrench is not applied)."""

    def flags(self) -> int:
        return GRAVITY
