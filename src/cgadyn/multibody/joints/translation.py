"""The translation joint: any translation of the body, no rotation (three slides).

``q_j = (x, y, z)``, as Pinocchio's ``JointModelTranslation``; ``M_J(q) = T(q) =
1 - ½ q e∞`` (eq. 6). Its motion subspace is the three unit translation twists, constant in
the child frame (which does not turn relative to the joint frame), so ``v_j`` is the linear
velocity in the joint frame and ``q ⊕ v = q + v``: the joint is additive, its coordinates
boxes within their limits. MuJoCo has no such joint (three ``slide`` joints are its
equivalent).
"""

from __future__ import annotations

import numpy as np

from ..._jit import inline
from ...cga.conventions import twist_from_motion
from ...kernels import motor_mul_translator
from .record import JointType

TRANSLATION = 6


@inline
def translation_motor(X, q, i, tmp, out):
    """``out = X T(q)`` of ``q[i:i+3]``: the product with the translator
    ``1 - ½ q e∞`` (its e1∞, e2∞, e3∞ coefficients), 12 multiplications."""
    tmp[4], tmp[5], tmp[6] = -0.5 * q[i], -0.5 * q[i + 1], -0.5 * q[i + 2]
    motor_mul_translator(X, tmp, out)


def _translations(B: np.ndarray) -> np.ndarray:
    return twist_from_motion(np.eye(6)[:3])  # v of the child body, in its frame


TYPES = (
    JointType(code=TRANSLATION, name="translation", kind="translation", label="translation",
              nq=3, nv=3, q_names=("x", "y", "z"), v_names=("vx", "vy", "vz"),
              speeds=("linear",) * 3, actuated=True, floating=False, additive=True,
              neutral=(0.0, 0.0, 0.0), subspace=_translations,
              pinocchio=("JointModelTranslation",), mujoco=None),
)
"""The translation type's record (``record.JointType``): actuated, as three slides are."""
