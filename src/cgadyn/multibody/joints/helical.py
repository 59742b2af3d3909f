"""The helical joint: a screw, rotation θ about a line through the joint frame's origin
with translation ``h θ`` along it (h the pitch, in length per radian).

``q_j = θ``, as Pinocchio's ``JointModelHX``, ``HY``, ``HZ`` and ``HelicalUnaligned``.
Its axis twist is the screw ``B = L + h d`` (L the unit line of the axis, d its direction:
``cga.conventions.twist_from_axis("helical", axis, pitch)``), ``S = B``, and the joint
motor is its exponential (eq. 6),

    M_J(q) = exp(θ B / 2) = (cos(θ/2) + sin(θ/2) L) (1 + (h θ / 2) d),

the rotor and the translator along the same axis commuting. ``q ⊕ v = q + v``. The pitch
lives in ``Model.axes`` (the twist's e∞ part), nowhere else. MuJoCo has no helical joint.
"""

from __future__ import annotations

import numpy as np

from ..._jit import inline
from ...kernels import motor_mul_rotor, motor_mul_translator
from .record import JointType

HELICAL = 7


@inline
def helical_motor(X, S, k, q, c, s, tmp, out):
    """``out = X exp(θ B / 2) = X R T``, B the screw ``S[k]`` (its line part, e23, e13,
    e12, and its pitch times the direction, e1∞, e2∞, e3∞), ``R = c + s L`` with
    ``c, s = cos(θ/2), sin(θ/2)`` (``dispatch.joint_scalars``) and ``T = 1 + (θ/2) h d``:
    the products with a rotor and with a translator (each reads only its part of
    ``tmp``; the translator's product may be taken in place)."""
    tmp[0], tmp[1], tmp[2], tmp[3] = c, s * S[k, 2], s * S[k, 1], s * S[k, 0]
    h = 0.5 * q
    tmp[4], tmp[5], tmp[6] = h * S[k, 3], h * S[k, 4], h * S[k, 5]
    motor_mul_rotor(X, tmp, out)
    motor_mul_translator(out, tmp, out)


def _screw(B: np.ndarray) -> np.ndarray:
    return np.array(B, dtype=float).reshape(1, 6)  # S = B, one column


TYPES = (
    JointType(code=HELICAL, name="helical", kind="helical", label="helical", nq=1, nv=1,
              speeds=("angular",), actuated=True, floating=False, additive=True,
              neutral=(0.0,), subspace=_screw, axis="helical", mujoco=None,
              pinocchio=("JointModelHX", "JointModelHY", "JointModelHZ",
                         "JointModelHelicalUnaligned")),
)
"""The helical type's record (``record.JointType``)."""
