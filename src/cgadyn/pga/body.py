"""Rigid body state and the PGA law of motion in the body frame (Table 2.1, eqs. 2.28-2.29).

The state is the pair (M, B): the motor M taking body-frame elements to the world
(X_w = M X_b M~, section 2.5.4) and the body-frame rate bivector B = B_b (eq. 2.2). Then

    kinematics   dM/dt = -½ M B                         (2.29, 2.7)
    dynamics     I[dB/dt] = F + B × I[B]                  (2.28)

with F = F_b the total forque in the body frame, a (d-1)-vector.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .inertia import Inertia
from .model import PGA

__all__ = [
    "RigidBody",
    "check_state",
    "dynamics",
    "hypercube",
    "kinematics",
    "state_derivative",
]

Forque = Callable[[np.ndarray, np.ndarray, float], np.ndarray]


@dataclass(frozen=True)
class RigidBody:
    """A body: its inertia map (which fixes d) and, for contact, its vertices (k, d) in the
    body frame (a convex hull, section 2.6.1)."""

    inertia: Inertia
    vertices: np.ndarray | None = None

    @property
    def model(self) -> PGA:
        return self.inertia.model

    @property
    def d(self) -> int:
        return self.inertia.model.d


def hypercube(d_or_model, mass: float = 1.0, edges=None) -> RigidBody:
    """The d-dimensional box of section 2.5.3 centred at the body origin: 2^d vertices from
    the bits of their index (bit k -> coordinate k, ±a_k/2) and inertia i_ij =
    m (a_i^2 + a_j^2)/12."""
    from .model import pga

    model = d_or_model if isinstance(d_or_model, PGA) else pga(d_or_model)
    inertia = Inertia.hypercube(model, mass, edges)
    a = np.ones(model.d) if edges is None else np.asarray(edges, dtype=float)
    bits = (np.arange(2**model.d)[:, None] >> np.arange(model.d)) & 1
    return RigidBody(inertia, (bits - 0.5) * a)


def check_state(model: PGA, m, b) -> tuple[np.ndarray, np.ndarray]:
    """Validate a state (M, B): finite, of the model's size; ValueError otherwise."""
    m = np.asarray(m, dtype=float)
    b = np.asarray(b, dtype=float)
    for name, x in (("motor M", m), ("rate bivector B", b)):
        if x.shape[-1:] != (model.n,):
            raise ValueError(f"{name} must have last axis {model.n} for d={model.d}, got {x.shape}")
        if not np.all(np.isfinite(x)):
            raise ValueError(f"{name} must be finite, got non-finite coefficients")
    return m, b


def kinematics(model: PGA, m, b) -> np.ndarray:
    """dM/dt = -½ M B (eq. 2.29), B in the body frame."""
    return -0.5 * model.gp(m, b)


def dynamics(inertia: Inertia, b, f) -> np.ndarray:
    """dB/dt = I^-1[F + B × I[B]] (eq. 2.28), all in the body frame."""
    model = inertia.model
    return inertia.inverse(f + model.commutator(b, inertia.apply(b)))


def state_derivative(
    body: RigidBody, forque: Forque | None, m, b, t: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """(dM/dt, dB/dt) for the total body-frame forque ``forque(M, B, t)`` (Table 2.1)."""
    f = body.model.zeros() if forque is None else forque(m, b, t)
    return kinematics(body.model, m, b), dynamics(body.inertia, b, f)
