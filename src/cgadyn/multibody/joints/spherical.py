"""The spherical joint: a rotation about a point, the joint frame's origin (a ball joint).

``q_j = (x, y, z, w)``, a unit quaternion, as Pinocchio's ``JointModelSpherical``;
``M_J(q) = R(x, y, z, w)`` (eq. 6). Its motion subspace is the three unit rotation twists,
so ``v_j`` is the angular velocity ``ω`` of the child body in its own frame (Pinocchio's
convention, and MuJoCo's ``ball`` qvel). It is the free flyer's rotation without its
translation, and shares its code (``free_flyer.quaternion_rotor``,
``quaternion_integrate``, ``quaternion_difference``): ``q ⊕ v = R exp(V / 2)`` with
``V = S v``, and ``q1 ⊖ q0 = log(~R0 R1)`` taken with the rotation angle in [0, π].
MuJoCo's ball joint holds ``[qw, qx, qy, qz]``.
"""

from __future__ import annotations

import numpy as np

from ..._jit import inline
from ...cga.conventions import twist_from_motion
from ...kernels import motor_mul_rotor
from .free_flyer import quaternion_rotor
from .record import JointType, unit_limits

SPHERICAL = 4


@inline
def spherical_motor(X, q, i, tmp, out):
    """``out = X R(x, y, z, w)`` of ``q[i:i+4] = (x, y, z, w)``, the quaternion normalised:
    the product with a rotor, 32 multiplications where a motor's takes 48."""
    tmp[0], tmp[1], tmp[2], tmp[3] = quaternion_rotor(q, i)
    motor_mul_rotor(X, tmp, out)


def _rotations(B: np.ndarray) -> np.ndarray:
    return twist_from_motion(np.eye(6)[3:])  # ω of the child body, in its frame


def _random(rng: np.random.Generator, q: np.ndarray, box: float) -> None:
    """A uniformly random rotation."""
    quat = rng.normal(size=4)
    q[:] = quat / np.linalg.norm(quat)  # uniform on the unit sphere S³


def _to_mujoco(q: np.ndarray) -> np.ndarray:
    return np.concatenate([q[..., 3:4], q[..., 0:3]], axis=-1)


def _from_mujoco(qpos: np.ndarray) -> np.ndarray:
    return np.concatenate([qpos[..., 1:4], qpos[..., 0:1]], axis=-1)


TYPES = (
    JointType(code=SPHERICAL, name="spherical", kind="spherical", label="spherical",
              nq=4, nv=3, q_names=("qx", "qy", "qz", "qw"), v_names=("wx", "wy", "wz"),
              speeds=("angular",) * 3, actuated=True, floating=False, additive=False,
              quaternion=0, cone=True, neutral=(0.0, 0.0, 0.0, 1.0), subspace=_rotations,
              limits=unit_limits(0, 4), random=_random, pinocchio=("JointModelSpherical",),
              mujoco="ball", to_mujoco=_to_mujoco, from_mujoco=_from_mujoco),
)
"""The spherical type's record (``record.JointType``): actuated (a motor per axis, as
MuJoCo's ``ball`` joint takes a motor per degree of freedom)."""
