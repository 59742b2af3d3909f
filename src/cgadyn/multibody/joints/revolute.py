"""The revolute joints: a rotation about a line through the joint frame's origin.

``M_J(q) = exp(q B / 2) = cos(q/2) + sin(q/2) B`` (eq. 6), B the unit line of the axis
(its e23, e13, e12 part; no moment: the axis passes through the origin); ``S = B``, one
angular velocity coordinate. ``REVOLUTE`` keeps the URDF's limits; ``REVOLUTE_UNBOUNDED``
(URDF's ``continuous``) has none, and ``q1 ⊖ q0`` wraps its angle to (-π, π]. Pinocchio
holds an unbounded angle as ``(cos q, sin q)``; cgadyn as one angle.
"""

from __future__ import annotations

import numpy as np

from ..._jit import inline
from ...kernels import motor_mul_rotor
from .record import JointType

REVOLUTE = 0
REVOLUTE_UNBOUNDED = 1


@inline
def revolute_motor(X, S, k, c, s, tmp, out):
    """``out = X exp(q B / 2)``, ``exp(q B / 2) = c + s B`` with ``c, s = cos(q/2),
    sin(q/2)`` (``dispatch.joint_scalars``) and B the axis twist ``S[k]`` (its e23, e13,
    e12 part; S and k, not a row view, which costs in compiled loops): the product with a
    rotor, 32 multiplications where a motor's takes 48."""
    tmp[0], tmp[1], tmp[2], tmp[3] = c, s * S[k, 2], s * S[k, 1], s * S[k, 0]
    motor_mul_rotor(X, tmp, out)


def _axis(B: np.ndarray) -> np.ndarray:
    return np.array(B, dtype=float).reshape(1, 6)  # S = B, one column


def _unbounded(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.full_like(lower, -np.inf), np.full_like(upper, np.inf)


def _to_cos_sin(q: np.ndarray) -> np.ndarray:
    return np.concatenate([np.cos(q), np.sin(q)], axis=-1)


def _from_cos_sin(qp: np.ndarray) -> np.ndarray:
    return np.arctan2(qp[..., 1:2], qp[..., 0:1])


_REVOLUTE = dict(nq=1, nv=1, speeds=("angular",), actuated=True, floating=False,
                 additive=True, neutral=(0.0,), subspace=_axis, axis="revolute",
                 mujoco="hinge")

TYPES = (
    JointType(code=REVOLUTE, name="revolute", kind="revolute", label="revolute",
              pinocchio=("JointModelRX", "JointModelRY", "JointModelRZ",
                         "JointModelRevoluteUnaligned"), **_REVOLUTE),
    JointType(code=REVOLUTE_UNBOUNDED, name="revolute_unbounded", kind="continuous",
              label="unbounded revolute", limits=_unbounded,
              pinocchio=("JointModelRUBX", "JointModelRUBY", "JointModelRUBZ",
                         "JointModelRevoluteUnboundedUnaligned"), pinocchio_nq=2,
              to_pinocchio=_to_cos_sin, from_pinocchio=_from_cos_sin, **_REVOLUTE),
)
"""The records of the two revolute types (``record.JointType``)."""
