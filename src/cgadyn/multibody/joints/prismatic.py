"""The prismatic joint: a translation along a direction.

``M_J(q) = exp(q B / 2) = 1 + (q/2) B`` (eq. 6), B the unit direction of the axis (its
e1∞, e2∞, e3∞ part); ``S = B``, one linear velocity coordinate (a slide inside the robot).
"""

from __future__ import annotations

import numpy as np

from ..._jit import inline
from ...kernels import motor_mul_translator
from .record import JointType

PRISMATIC = 2


@inline
def prismatic_motor(X, S, k, q, tmp, out):
    """``out = X (1 + (q/2) B)``, B the direction twist ``S[k]`` (its e1∞, e2∞, e3∞
    part): the product with a translator, 12 multiplications where a motor's takes 48."""
    h = 0.5 * q
    tmp[4], tmp[5], tmp[6] = h * S[k, 3], h * S[k, 4], h * S[k, 5]
    motor_mul_translator(X, tmp, out)


def _axis(B: np.ndarray) -> np.ndarray:
    return np.array(B, dtype=float).reshape(1, 6)  # S = B, one column


TYPES = (
    JointType(code=PRISMATIC, name="prismatic", kind="prismatic", label="prismatic", nq=1,
              nv=1, speeds=("linear",), actuated=True, floating=False, additive=True,
              neutral=(0.0,), subspace=_axis, axis="prismatic", mujoco="slide",
              pinocchio=("JointModelPX", "JointModelPY", "JointModelPZ",
                         "JointModelPrismaticUnaligned")),
)
"""The prismatic type's record (``record.JointType``)."""
