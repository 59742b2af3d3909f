"""Impulse contact of a body against a fixed hyperplane (sections 2.6, 2.6.1).

Detection (2.6.1, SAT against a floor): a vertex A_i of the convex body penetrates the floor
f when its signed distance is negative. The paper writes A_i ∨ f < 0; with the complement
duality used here the sign of A ∨ f alternates with d, while f ∨ A (for a normalised point
and a unit normal) is the signed distance in every d, so ``signed_distance`` uses f ∨ A.

Response: the frictionless impulse against an infinitely heavy static plane (I_-^-1 = 0,
B_- = 0), eq. (2.32) for j and eq. (2.33) for the new rate.
"""

from __future__ import annotations

import numpy as np

from .body import RigidBody
from .model import PGA

__all__ = ["contact_impulse", "normal_velocity", "penetrations", "signed_distance"]


def signed_distance(model: PGA, plane, points) -> np.ndarray:
    """f ∨ X: distance of normalised points X above the hyperplane f (unit normal)."""
    return model.vee(plane, points)[..., 0]


def penetrations(body: RigidBody, m, plane) -> tuple[np.ndarray, np.ndarray]:
    """(indices, depths) of the body's vertices below the world hyperplane ``plane``
    (``is_colliding`` of section 2.6.1, all of them, deepest first)."""
    if body.vertices is None:
        return np.zeros(0, dtype=int), np.zeros(0)
    model = body.model
    world = model.sandwich(m, model.point(body.vertices))
    dist = signed_distance(model, plane, world)
    idx = np.flatnonzero(dist < 0)
    idx = idx[np.argsort(dist[idx])]
    return idx, dist[idx]


def normal_velocity(model: PGA, m, b, q_body, plane) -> float:
    """d/dt of the signed distance of the body point Q: f_b ∨ (Q × B) (eq. 2.8)."""
    plane_b = model.sandwich(model.reverse(m), plane)
    return float(model.vee(plane_b, model.commutator(q_body, b))[0])


def contact_impulse(
    body: RigidBody, m, b, vertex, plane, restitution: float = 0.5
) -> tuple[np.ndarray, float]:
    """New body rate B after a frictionless impulse at the body vertex against ``plane``.

    N = (M~ f M) ⌋ Q, the normal line at the contact point Q (in the body frame),
    j = -(1 + rho) (Q ∨ Q × B) . N~ / (Q ∨ Q × I^-1[N]) . N~          (2.32)
    B <- B + j I^-1[N]                                                  (2.33)
    Returns (B, j). The orientation of N cancels out of j I^-1[N].
    """
    if not 0.0 <= restitution <= 1.0:
        raise ValueError(f"restitution must be in [0, 1], got {restitution}")
    model = body.model
    q = model.point(np.asarray(vertex, dtype=float))
    plane_b = model.sandwich(model.reverse(m), plane)
    n = model.lc(plane_b, q)
    n_rev = model.reverse(n)
    inv_n = body.inertia.inverse(n)
    v = model.vee(q, model.commutator(q, b))
    num = model.gp(v, n_rev)[0]
    den = model.gp(model.vee(q, model.commutator(q, inv_n)), n_rev)[0]
    j = -(1.0 + restitution) * num / den
    return b + j * inv_n, float(j)
