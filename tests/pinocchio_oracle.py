"""Pinocchio as the oracle: the same URDF loaded in Pinocchio, and q converted to its nq."""

from __future__ import annotations

from functools import cache

import numpy as np
import pinocchio as pin

import cgadyn
from cgadyn.multibody import robot_path


@cache
def pin_model(name: str):
    model = pin.buildModelFromUrdf(str(robot_path(name)))
    return model, model.createData()


def pin_q(pm, q: np.ndarray) -> np.ndarray:
    """Pinocchio's configuration: a continuous joint takes (cos, sin)."""
    parts = []
    for j in range(pm.njoints - 1):
        if pm.joints[j + 1].nq == 2:
            parts += [np.cos(q[j]), np.sin(q[j])]
        else:
            parts.append(q[j])
    return np.array(parts)


def random_state(model, rng: np.random.Generator, batch: int | None = None):
    """q within the joint limits ([-π, π] where unbounded), and normal v, a."""
    shape = (model.nv,) if batch is None else (batch, model.nv)
    lo = np.where(np.isfinite(model.lower), model.lower, -np.pi)
    hi = np.where(np.isfinite(model.upper), model.upper, np.pi)
    q = rng.uniform(lo, hi, size=shape)
    return q, rng.normal(size=shape), rng.normal(size=shape)


def forces(f_ext: np.ndarray):
    return [pin.Force.Zero()] + [pin.Force(f) for f in f_ext]


def rel(x, y) -> float:
    """max |x - y| / max(1, max |y|)."""
    return float(np.abs(np.asarray(x) - y).max() / max(1.0, np.abs(y).max()))


__all__ = ["cgadyn", "forces", "pin_model", "pin_q", "random_state", "rel"]
