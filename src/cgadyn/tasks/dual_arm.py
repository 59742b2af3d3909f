"""The cooperative dual-task space of two end-effectors (Adorno's, in motors).

With ``M_1``, ``M_2`` the world motors of the two hands (eq. 5), the relative motor and the
absolute motor are

    M_r = ~M_1 M_2                (the second hand seen from the first)
    M_a = M_1 M_r^½ = M_1 exp(ξ_r / 4)     (halfway between the hands; ``M_r = exp(ξ_r / 2)``,
                                             ξ_r = log M_r, eq. 6)

and their body velocities follow from the hands' local Jacobians ``J_1, J_2`` (rows
``[v, ω]``):

    J_r = J_2 - Ad(~M_r) J_1,
    J_a = Ad(M_r^-½) J_1 + ½ J_r(ξ_r / 2) Jlog6(ξ_r) J_r

(``J_r(·)`` the right Jacobian of the exponential and ``Jlog6`` its inverse, ``_lie``). A
``CooperativeTask`` asks ``log6(~M_target M)`` of either motor to vanish, with the Jacobian
``Jlog6 · J``; ``solve_cooperative`` minimises a weighted stack of them by damped least
squares within the joint limits (keep the relative pose of the hands while the absolute pose
moves).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..algorithms import _inputs
from ..algorithms.api import forward_kinematics, jacobian
from ..algorithms.configuration import integrate
from ..cga.conventions import matrix_from_motor, motion_from_twist, twist_from_motion
from ..cga.objects import Motor, Twist
from ._lie import jexp6, jlog6
from .ik import IKResult, middle_configuration
from .task import as_motor

__all__ = ["CooperativeTask", "cooperative_space", "solve_cooperative"]


def _log6(M: Motor) -> np.ndarray:
    """``(v, ω)`` of ``log M``, the rotation at most π (Pinocchio's ``log6``)."""
    v = M.normalized().values
    return motion_from_twist(Motor(v if v[0] >= 0.0 else -v).log().values)


def _exp6(xi: np.ndarray) -> Motor:
    return Motor.exp(Twist(twist_from_motion(xi)))


def _adjoint(M: Motor) -> np.ndarray:
    """``Ad(M)`` (6x6) on ``[v, ω]``."""
    T = matrix_from_motor(M.values)
    R, p = T[:3, :3], T[:3, 3]
    P = np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])
    return np.block([[R, P @ R], [np.zeros((3, 3)), R]])


def _jlog6(xi: np.ndarray) -> np.ndarray:
    out, t = np.empty((6, 6)), np.empty((6, 3, 3))
    jlog6(np.ascontiguousarray(xi), out, t)
    return out


def _jexp6(xi: np.ndarray) -> np.ndarray:
    out, t = np.empty((6, 6)), np.empty((6, 3, 3))
    jexp6(np.ascontiguousarray(xi), out, t)
    return out


def cooperative_space(model, q, first, second) -> tuple[Motor, np.ndarray, Motor, np.ndarray]:
    """``(M_a, J_a, M_r, J_r)``: the absolute and relative motors of two links and their
    body Jacobians (6, nv), rows ``[v, ω]`` (module docstring)."""
    i, j = _inputs.link_index(model, first), _inputs.link_index(model, second)
    q = _inputs.state(model, q, "q", model.nq)
    if q.ndim != 1:
        raise ValueError(f"expected one configuration ({model.nq},), got {q.shape}")
    links = forward_kinematics(model, q)[1]
    M1, M2 = Motor(links[i]), Motor(links[j])
    J1, J2 = jacobian(model, q, i, "local"), jacobian(model, q, j, "local")
    Mr = M1.reverse() * M2
    Jr = J2 - _adjoint(Mr.reverse()) @ J1
    xi = _log6(Mr)
    H = _exp6(0.5 * xi)  # M_r^½
    Ja = _adjoint(H.reverse()) @ J1 + 0.5 * _jexp6(0.5 * xi) @ _jlog6(xi) @ Jr
    return M1 * H, Ja, Mr, Jr


@dataclass(frozen=True)
class CooperativeTask:
    """The absolute (``which='absolute'``) or relative motor of two links onto ``target``
    (a Motor or a rigid 4x4 matrix), weighted."""

    first: str | int
    second: str | int
    which: str
    target: object
    weight: float = 1.0

    def rows(self, model, q) -> tuple[np.ndarray, np.ndarray]:
        """The residual ``w log6(~M_target M)`` (6,) and its Jacobian (6, nv)."""
        if self.which not in ("absolute", "relative"):
            raise ValueError(f"which must be 'absolute' or 'relative', got {self.which!r}")
        if not (np.isfinite(self.weight) and self.weight > 0):
            raise ValueError(f"weight must be finite and positive, got {self.weight}")
        Ma, Ja, Mr, Jr = cooperative_space(model, q, self.first, self.second)
        M, J = (Ma, Ja) if self.which == "absolute" else (Mr, Jr)
        err = _log6(Motor(as_motor(self.target, "target")).reverse() * M)
        return self.weight * err, self.weight * _jlog6(err) @ J


def solve_cooperative(model, tasks: Sequence[CooperativeTask], q0=None, *, tol: float = 1e-10,
                      max_iter: int = 200, damping: float = 1e-3) -> IKResult:
    """Levenberg-Marquardt on a stack of cooperative tasks within the joint limits (no
    restarts: start near the answer, as when the absolute pose moves a little)."""
    q = middle_configuration(model) if q0 is None else _inputs.state(model, q0, "q0", model.nq)
    if q.ndim != 1:
        raise ValueError(f"q0 must be one configuration ({model.nq},), got {q.shape}")
    lower, upper = model.lower, model.upper

    def stack(x):
        parts = [t.rows(model, x) for t in tasks]
        return np.concatenate([p[0] for p in parts]), np.vstack([p[1] for p in parts])

    q = np.clip(q, lower, upper)
    r, J = stack(q)
    f, lam, its = r @ r, damping, 0
    while its < max_iter and f > tol * tol:
        its += 1
        d = -np.linalg.solve(J.T @ J + lam * np.eye(model.nv), J.T @ r)
        qt = np.clip(integrate(model, q, d), lower, upper)
        rt, Jt = stack(qt)
        if rt @ rt < f:
            q, r, J, f, lam = qt, rt, Jt, rt @ rt, max(lam / 3.0, 1e-12)
        else:
            lam *= 10.0
            if lam > 1e10:
                break
    return IKResult(q, bool(f <= tol * tol), r, float(np.sqrt(f)), its, 0)
