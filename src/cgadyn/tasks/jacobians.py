"""Jacobians of motors and of the geometric objects links carry, and the Jacobian's rate.

A link's motor is a product of joint motors (eq. 5), and a joint's motor moves along its
coordinate as ``∂(X_j exp(q_j B_j / 2))/∂q_j = X_j exp(q_j B_j / 2) ½ B_j``: the motor times
half its axis. Moved to the world, every velocity coordinate k of the path gives

    ∂M^w_L/∂q_k = ½ S^w_k M^w_L,        S^w_k = M^w_j S_k ~M^w_j   (eq. 4)

(for a free flyer's six coordinates, the tangent directions of ``integrate``). An object X
rigidly attached to the link is ``X(q) = M X ~M`` in the world (eq. 4), so

    ∂X/∂q_k = ½ (S^w_k X(q) - X(q) S^w_k) = S^w_k × X(q),

the commutator product with the world twist: a point, point pair, line, circle, plane or
sphere alike, as coefficients of the reference algebra's blades.

The time derivative of the geometric Jacobian (Pinocchio's
``getFrameJacobianTimeVariation``): in the world, column k changes as its twist is carried
along by the body that holds it, ``Ṡ^w_k = V^w_j × S^w_k`` with ``V^w_j`` the world twist of
joint j's body. The link frame's Jacobian ``Ad(F⁻¹) J`` then adds ``-V_F × J_F``, with
``V_F`` the frame's own velocity in that frame (for the local-world-aligned frame, F its
translation alone).
"""

from __future__ import annotations

import numpy as np

from ..algorithms import _inputs
from ..algorithms.api import forward_kinematics, jacobian
from ..cga.basis import twist_mv
from ..cga.objects import Geometric, Motor

__all__ = ["jacobian_time_variation", "motor_jacobian", "object_jacobian"]


def _one_q(model, q) -> np.ndarray:
    q = _inputs.state(model, q, "q", model.nq)
    if q.ndim != 1:
        raise ValueError(f"expected one configuration (nq,) = ({model.nq},), got {q.shape}")
    return q


def _as_motor(twists: np.ndarray) -> np.ndarray:
    """Twist coefficients (..., 6) on e23, e13, e12, e1∞, e2∞, e3∞ as motor coefficients
    (..., 8) on 1, e12, e13, e23, e1∞, e2∞, e3∞, e123∞."""
    out = np.zeros(twists.shape[:-1] + (8,))
    out[..., 1], out[..., 2], out[..., 3] = twists[..., 2], twists[..., 1], twists[..., 0]
    out[..., 4:7] = twists[..., 3:6]
    return out


def motor_jacobian(model, q, link) -> tuple[Motor, np.ndarray]:
    """The link's world motor ``M^w_L`` and ``∂M^w_L/∂q_k = ½ S^w_k M^w_L`` as motor
    coefficients, (nv, 8): one row per velocity coordinate."""
    i = _inputs.link_index(model, link)
    q = _one_q(model, q)
    M = Motor(forward_kinematics(model, q)[1][i])
    S = jacobian(model, q, i, "world", layout="twist")  # (nv, 6) world twists
    dM = 0.5 * (Motor(_as_motor(S)) * M).values
    return M, dM


def object_jacobian(model, q, link, obj: Geometric) -> tuple[Geometric, np.ndarray]:
    """``X(q) = M X ~M`` of an object given in the link frame, and ``∂X/∂q`` (nblades, nv):
    row b the coefficient of the reference algebra's blade b (``X.mv.coeffs`` order)."""
    if not isinstance(obj, Geometric):
        raise ValueError(f"obj must be a Point, Line, Plane, Circle or Sphere (or another "
                         f"Geometric blade), got {type(obj).__name__}")
    i = _inputs.link_index(model, link)
    q = _one_q(model, q)
    M = Motor(forward_kinematics(model, q)[1][i])
    X = M.apply(obj)
    S = twist_mv(jacobian(model, q, i, "world", layout="twist"))  # a batch of nv twists
    dX = (S * X.mv - X.mv * S) * 0.5
    return X, np.ascontiguousarray(np.asarray(dX.coeffs).T)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Motion cross product ``a × b`` of Pinocchio vectors ``[v, ω]``; b may be (6, k)."""
    v, w = a[:3, None], a[3:, None]
    bv, bw = b[:3], b[3:]
    return np.concatenate([np.cross(w, bv, axis=0) + np.cross(v, bw, axis=0),
                           np.cross(w, bw, axis=0)])


def jacobian_time_variation(model, q, v, link, frame: str = "world") -> np.ndarray:
    """``J̇`` (6, nv) of the link's geometric Jacobian in ``frame`` ('world', 'local',
    'local_world_aligned'), rows ``[v, ω]``: Pinocchio's ``getFrameJacobianTimeVariation``."""
    i = _inputs.link_index(model, link)
    q = _one_q(model, q)
    v = _inputs.state(model, v, "v", model.nv)
    if v.ndim != 1:
        raise ValueError(f"expected one velocity (nv,) = ({model.nv},), got {v.shape}")
    if frame not in ("world", "local", "local_world_aligned"):
        raise ValueError(f"frame must be 'world', 'local' or 'local_world_aligned', got "
                         f"{frame!r}")
    Jw = jacobian(model, q, i, "world")
    dJ = np.zeros_like(Jw)
    Vj = np.zeros(6)  # V^w of the body of the joints met so far, root first
    cols = np.flatnonzero(np.any(Jw != 0.0, axis=0))
    joints = model.dof_joint[cols]
    for j in np.unique(joints):
        k = cols[joints == j]
        Vj = Vj + Jw[:, k] @ v[k]
        dJ[:, k] = _cross(Vj, Jw[:, k])  # Ṡ^w_k = V^w_j × S^w_k
    if frame == "world":
        return dJ
    L = Motor(forward_kinematics(model, q)[1][i]).matrix()
    R, p = L[:3, :3], L[:3, 3]
    if frame == "local_world_aligned":
        R = np.eye(3)
    J = np.vstack([R.T @ (Jw[:3] - np.cross(p[:, None], Jw[3:], axis=0)), R.T @ Jw[3:]])
    A = np.vstack([R.T @ (dJ[:3] - np.cross(p[:, None], dJ[3:], axis=0)), R.T @ dJ[3:]])
    T = J @ v  # the frame's velocity in itself
    if frame == "local_world_aligned":
        T[3:] = 0.0  # the translation alone moves the frame
    return A - _cross(T, J)
