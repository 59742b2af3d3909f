"""Pose targets as motors, many at once: 4x4 matrices checked rigid, then ``M = T R`` (eq. 4).

The rotor of a rotation matrix comes from its quaternion by Shepperd's method (the largest
of ``w², x², y², z²`` taken first, so that no division is by a small number), the rotor
coefficients from the quaternion by ``cga.conventions``' map, and the translator
``T = 1 - ½ t e∞`` multiplied on the left.
"""

from __future__ import annotations

import numpy as np

from ..cga import conventions as C
from ..cga.objects import Motor
from ..kernels.batch import motor_mul_batch

__all__ = ["motors_from_matrices"]


def _check_rigid(T: np.ndarray) -> None:
    if not np.all(np.isfinite(T)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(T), axis=(1, 2)))[0])
        raise ValueError(f"target pose {bad} holds NaN or inf")
    last = np.abs(T[:, 3] - [0.0, 0.0, 0.0, 1.0]).max(axis=1) > 1e-9
    R = T[:, :3, :3]
    orth = np.abs(R @ np.swapaxes(R, 1, 2) - np.eye(3)).max(axis=(1, 2)) > 1e-8
    bad = np.flatnonzero(last | orth | (np.linalg.det(R) < 0.0))
    if bad.size:
        raise ValueError(f"target pose {int(bad[0])} is not a rigid transform: the 3x3 block "
                         f"must be a rotation (R Rᵀ = 1, det R = 1) and the last row "
                         f"[0, 0, 0, 1]; got\n{T[bad[0]]}")


def motors_from_matrices(T) -> np.ndarray:
    """Motor coefficients (B, 8) of rigid 4x4 matrices (B, 4, 4); ``ValueError`` naming the
    first matrix that is not rigid."""
    T = np.asarray(T, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise ValueError(f"expected 4x4 poses (B, 4, 4), got shape {T.shape}")
    _check_rigid(T)
    R = T[:, :3, :3]
    d = np.stack([R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2], R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]], 1)
    k = np.argmax(d, axis=1)
    a = np.stack([1.0 + d[:, 0], 1.0 + R[:, 0, 0] - R[:, 1, 1] - R[:, 2, 2],
                  1.0 - R[:, 0, 0] + R[:, 1, 1] - R[:, 2, 2],
                  1.0 - R[:, 0, 0] - R[:, 1, 1] + R[:, 2, 2]], 1)
    big = 0.5 * np.sqrt(np.maximum(a[np.arange(len(k)), k], 1e-300))  # the largest |component|
    f = 0.25 / big
    s10, s01 = R[:, 1, 0], R[:, 0, 1]
    s21, s12 = R[:, 2, 1], R[:, 1, 2]
    s02, s20 = R[:, 0, 2], R[:, 2, 0]
    quat = np.select(
        [k[:, None] == 0, k[:, None] == 1, k[:, None] == 2],
        [np.stack([big, (s21 - s12) * f, (s02 - s20) * f, (s10 - s01) * f], 1),
         np.stack([(s21 - s12) * f, big, (s01 + s10) * f, (s02 + s20) * f], 1),
         np.stack([(s02 - s20) * f, (s01 + s10) * f, big, (s12 + s21) * f], 1)],
        np.stack([(s10 - s01) * f, (s02 + s20) * f, (s12 + s21) * f, big], 1))
    rotor = np.zeros((len(k), 8))
    rotor[:, :4] = C._quaternion_of(quat)  # the map is its own inverse
    out = np.empty_like(rotor)
    motor_mul_batch(np.ascontiguousarray(Motor.translator(T[:, :3, 3]).values), rotor, out)
    return out
