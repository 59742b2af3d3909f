"""The rows of a constraint (C1, C2) and its drift (C3-C5), from the world motion of its two
ends (``docs/constraints.md``).

Every quantity of an end is in the world, as Pinocchio's arrays ``[v, ω]`` of a twist at the
world origin: the geometric Jacobian ``J`` of the body that carries the end
(``cgadyn.jacobian(..., "world")``), its twist ``V = J v`` and its acceleration at ``q̈ = 0``
without gravity, ``A = J̇ v`` (Pinocchio's ``data.oa`` in ``constraintDynamics``; C3). A
twist seen at a point p is ``shift(X, p) = [v - p × ω, ω]``: its first three rows are the
velocity of the point p carried by the body, the Euclidean part of the commutator ``V × X``
of the twist with the conformal point ``X = up(p)`` (C1). A world end has ``J = 0``, ``V = A = 0``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..algorithms.api import jacobian, link_placements
from ..cga.conventions import motion_from_twist, motor_from_matrix
from ..kernels.motors import motor_log, motor_normalize
from .model import Constraint


@dataclass(frozen=True)
class End:
    """One end of a constraint in the world: its frame ``T`` (4x4), the Jacobian ``J``
    (6, nv) of the body carrying it, its twist ``V`` and drift acceleration ``A`` (6,)."""

    T: np.ndarray
    J: np.ndarray
    V: np.ndarray
    A: np.ndarray


def skew(p: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def shift(X: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Twists ``[v, ω]`` at the world origin (6,) or (6, k), seen at the point p:
    ``[v - p × ω, ω]``; the first three rows are the velocity of p (C1)."""
    return np.concatenate([X[:3] - skew(p) @ X[3:], X[3:]])


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` of 3-vectors (3,) or (3, k) (numpy's ``cross`` costs more on small arrays)."""
    return np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The bracket of twists ``[v, ω]`` (6,) or (6, k): Featherstone's ``a × b`` (eq. 11)."""
    return np.concatenate([cross3(a[3:], b[:3]) + cross3(a[:3], b[3:]), cross3(a[3:], b[3:])])


def drift_acceleration(model, J: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``A = J̇ v`` of a body from its world Jacobian: ``A_j = A_λ + V_λ × S_j q̇_j`` along
    its path (D2 of docs/derivatives.md at q̈ = 0), i.e. ``Σ_j V_λ(j) × (S_j q̇_j)`` with
    ``V_λ(j)`` the sum of ``S_i q̇_i`` over the joints i above j."""
    cols = np.flatnonzero(np.any(J != 0.0, axis=0))
    if len(cols) == 0:
        return np.zeros(6)
    joints, first = np.unique(model.dof_joint[cols], return_index=True)
    own = np.add.reduceat(J[:, cols] * v[cols], first, axis=1)  # S_j q̇_j, root first
    above = np.cumsum(own, axis=1) - own  # V_λ(j)
    return cross(above, own).sum(axis=1)


def log6(T: np.ndarray) -> np.ndarray:
    """The twist ``[v, ω]`` with ``exp = T``, rotation angle in [0, π]: the motor's log
    (``kernels.motors.motor_log``, angle in [0, 2π)), of ``-M`` where the angle passes π (the
    same motion)."""
    m = np.empty(8)
    motor_normalize(motor_from_matrix(T), m)
    twist = np.empty(6)
    motor_log(m, twist)
    x = motion_from_twist(twist)
    if x[3:] @ x[3:] > np.pi * np.pi:
        motor_log(-m, twist)
        x = motion_from_twist(twist)
    return x


def placements(model, q: np.ndarray, constraints: tuple[Constraint, ...]):
    """The compiled calls the ends need, once for one configuration (nq,) or a batch
    (B, nq): the world placements of every link and the world Jacobian of each constrained
    link, ``(T, {link: J})``."""
    links = {c.link for c in constraints} | {c.other for c in constraints} - {None}
    return link_placements(model, q), {i: jacobian(model, q, i, "world") for i in links}


def ends(model, T: np.ndarray, jacobians: dict, constraints: tuple[Constraint, ...],
         v: np.ndarray | None = None) -> list[tuple[End, End]]:
    """Both ends of each constraint at one state, from its ``placements`` (and velocity v,
    else V = A = 0)."""
    zero6, zeroJ = np.zeros(6), np.zeros((6, model.nv))
    motion: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def end(link: int | None, P: np.ndarray) -> End:
        if link is None:
            return End(P, zeroJ, zero6, zero6)
        J = jacobians[link]
        if link not in motion:
            motion[link] = ((zero6, zero6) if v is None else
                            (J @ v, drift_acceleration(model, J, v)))
        return End(T[link] @ P, J, *motion[link])

    return [(end(c.link, c.placement), end(c.other, c.other_placement)) for c in constraints]


def _rotate(c: Constraint, R: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Rows (3 or 6, ...) from world axes to the constraint's frame: ``Rᵀ`` on each block of
    three in ``"local"``, unchanged in ``"local_world_aligned"``."""
    if c.frame == "local_world_aligned":
        return x
    return np.concatenate([R.T @ x[i:i + 3] for i in range(0, len(x), 3)])


def rows(c: Constraint, e1: End, e2: End) -> np.ndarray:
    """The rows of one constraint, (3 or 6, nv): C1 for a point, C2 for a frame."""
    p1, p2 = e1.T[:3, 3], e2.T[:3, 3]
    if c.kind == "point":  # C1: ṗ₁ - ṗ₂
        D = shift(e1.J, p1)[:3] - shift(e2.J, p2)[:3]
    else:  # C2: the relative twist V₁ - V₂ seen at the origin of frame 1
        D = shift(e1.J - e2.J, p1)
    return _rotate(c, e1.T[:3, :3], D)


def drift(c: Constraint, e1: End, e2: End) -> np.ndarray:
    """``γ`` of one constraint (3 or 6,): the acceleration of its rows at ``q̈ = 0`` (C3 for a
    point, C4 for a frame) plus the Baumgarte terms (C5)."""
    kp, kd = c.corrector
    R1, p1, p2 = e1.T[:3, :3], e1.T[:3, 3], e2.T[:3, 3]
    if c.kind == "point":
        def acceleration(e: End, p: np.ndarray) -> np.ndarray:  # classical, of the point p
            return shift(e.A, p)[:3] + cross3(e.V[3:], shift(e.V, p)[:3])

        g = acceleration(e1, p1) - acceleration(e2, p2)  # C3
        g = g + kp * (p1 - p2) + kd * (shift(e1.V, p1)[:3] - shift(e2.V, p2)[:3])  # C5
        return _rotate(c, R1, g)
    if c.frame == "local":  # C4
        g = _rotate(c, R1, shift(e1.A - e2.A + cross(e1.V - e2.V, e2.V), p1))
    else:
        g = shift(e1.A - e2.A, p1)
    error = -log6(np.linalg.inv(e1.T) @ e2.T)  # frame 1 from frame 2, in frame 1
    if c.frame == "local_world_aligned":
        error = np.concatenate([R1 @ error[:3], R1 @ error[3:]])
    return g + kp * error + kd * _rotate(c, R1, shift(e1.V - e2.V, p1))  # C5
