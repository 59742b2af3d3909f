"""4x4 rigid matrices as motors, checked rigid, then ``M = T R`` (eq. 4), compiled: the one
conversion of a matrix (or a rotation and a translation) to a motor, used by
``conventions.motor_from_matrix`` and ``motor_from_rt`` and by the task targets.

The rotor of a rotation matrix comes from its quaternion by Shepperd's method (the largest
of ``w², x², y², z²`` first, so that no division is by a small number), the rotor
coefficients from the quaternion by the map of ``kernels.layout``, and the translator
``T = 1 - ½ t e∞`` multiplied on the left (``translator_rotor``).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import serial
from ..kernels import translator_rotor
from ..kernels.layout import rotor

__all__ = ["motors_from_matrices"]

RIGID_TOL = 1e-8
"""The largest entry of ``R Rᵀ - 1`` (and of the last row's error) a rigid matrix may have."""


NOT_FINITE, NOT_RIGID = 1, 2


@serial
def _convert(T, out):
    """``out[b]`` = the motor of ``T[b]``; ``(b, NOT_FINITE or NOT_RIGID)`` of the first
    matrix that is not a rigid transform, else ``(-1, 0)``."""
    for b in range(T.shape[0]):
        A = T[b]
        finite = True
        for i in range(4):
            for j in range(4):
                finite &= math.isfinite(A[i, j])
        if not finite:
            return b, NOT_FINITE
        err = abs(A[3, 0]) + abs(A[3, 1]) + abs(A[3, 2]) + abs(A[3, 3] - 1.0)
        for i in range(3):
            for j in range(3):
                d = A[i, 0] * A[j, 0] + A[i, 1] * A[j, 1] + A[i, 2] * A[j, 2]
                err = max(err, abs(d - (1.0 if i == j else 0.0)))
        det = (A[0, 0] * (A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1])
               - A[0, 1] * (A[1, 0] * A[2, 2] - A[1, 2] * A[2, 0])
               + A[0, 2] * (A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]))
        if not (err <= RIGID_TOL and det > 0.0):
            return b, NOT_RIGID
        r00, r11, r22 = A[0, 0], A[1, 1], A[2, 2]
        tr = r00 + r11 + r22
        if tr >= r00 and tr >= r11 and tr >= r22:
            w = 0.5 * math.sqrt(max(1.0 + tr, 0.0))
            f = 0.25 / w
            x, y, z = (A[2, 1] - A[1, 2]) * f, (A[0, 2] - A[2, 0]) * f, (A[1, 0] - A[0, 1]) * f
        elif r00 >= r11 and r00 >= r22:
            x = 0.5 * math.sqrt(max(1.0 + r00 - r11 - r22, 0.0))
            f = 0.25 / x
            w, y, z = (A[2, 1] - A[1, 2]) * f, (A[0, 1] + A[1, 0]) * f, (A[0, 2] + A[2, 0]) * f
        elif r11 >= r22:
            y = 0.5 * math.sqrt(max(1.0 - r00 + r11 - r22, 0.0))
            f = 0.25 / y
            w, x, z = (A[0, 2] - A[2, 0]) * f, (A[0, 1] + A[1, 0]) * f, (A[1, 2] + A[2, 1]) * f
        else:
            z = 0.5 * math.sqrt(max(1.0 - r00 - r11 + r22, 0.0))
            f = 0.25 / z
            w, x, y = (A[1, 0] - A[0, 1]) * f, (A[0, 2] + A[2, 0]) * f, (A[1, 2] + A[2, 1]) * f
        r0, r1, r2, r3 = rotor((w, x, y, z))
        translator_rotor(A[0, 3], A[1, 3], A[2, 3], r0, r1, r2, r3, out[b])
    return -1, 0


def motors_from_matrices(T, what: str = "target pose") -> np.ndarray:
    """Motor coefficients (B, 8) of rigid 4x4 matrices (B, 4, 4); ``ValueError`` naming the
    first matrix (``what``) that is not finite or not rigid."""
    T = np.ascontiguousarray(T, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise ValueError(f"expected 4x4 matrices (B, 4, 4), got shape {T.shape}")
    out = np.empty((T.shape[0], 8))
    bad, reason = _convert(T, out)
    if bad >= 0:
        which = f"the {what}" if T.shape[0] == 1 else f"{what} {bad}"
        if reason == NOT_FINITE:
            raise ValueError(f"{which} contains NaN or inf:\n{T[bad]}")
        raise ValueError(f"{which} is not a rigid transform: the 3x3 block must be a rotation "
                         f"(R Rᵀ = 1 within {RIGID_TOL:g}, det R > 0) and the last row "
                         f"[0, 0, 0, 1]; got\n{T[bad]}")
    return out
