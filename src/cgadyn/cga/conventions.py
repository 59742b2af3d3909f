"""How CGA motors, twists, wrenches and inertias map to matrices and to Pinocchio.

Signs (fixed once here, pinned against Pinocchio by the tests):

- A rotation by θ about the unit axis u is the rotor ``R = exp(-θ/2 (u1 e23 + u2 e31 + u3 e12))``
  and a translation by t the translator ``T = 1 - ½ t e∞``; the motor of a pose is ``M = T R``
  and moves points by the sandwich ``M X ~M`` (eq. 4), exactly as the 4x4 matrix
  ``[[R, t], [0, 1]]`` moves them.
- A twist with angular velocity ω and linear velocity v (Pinocchio's ``Motion`` [v, ω]) is
  the bivector ``V = -(ω1 e23 + ω2 e31 + ω3 e12) - (v1 e1∞ + v2 e2∞ + v3 e3∞)`` (eq. 7),
  coefficients ``(-ω1, ω2, -ω3, -v1, -v2, -v3)``. With this sign the commutator of eq. (11)
  is the Lie bracket of twists (Featherstone's ``v1 × v2``), and moving with V for unit
  time is the motor ``exp(V / 2)``.
- A wrench with torque n and force f (Pinocchio's ``Force`` [f, n]) is
  ``W = -(n1 e23 + n2 e31 + n3 e12) - (f1 e01 + f2 e02 + f3 e03)`` (eq. 8), coefficients
  ``(-n1, n2, -n3, -f1, -f2, -f3)``, so that the power is ``p = -V · W = v·f + ω·n`` (eq. 9).
- The frame of a twist or wrench is the frame its coefficients are expressed in; the
  sandwich ``M V ~M`` re-expresses a twist given in frame B in frame A when M is the pose
  of B in A, which is Pinocchio's ``aMb.act(motion)`` (likewise for wrenches and forces).
- An inertia tensor is six elements ``I^{e_k}`` (eqs. 12-14), stored as ``I[k, j]``, the
  coefficient of element k on wrench blade j; ``I[V] = I @ V`` on coefficients (eq. 15).
  With the signs above, eq. (18) holds exactly as printed in the paper.
"""

from __future__ import annotations

import numpy as np

from .. import kernels as K
from .._threads import PARALLEL_LOCK
from ..kernels.layout import BIVECTOR_SIGN, QUATERNION_OF_ROTOR
from .poses import motors_from_matrices

SIGN = np.array(BIVECTOR_SIGN)
"""Coefficient = SIGN * physical component, physical order (ω or n, then v or f)."""
_Q_INDEX = [i for i, _ in QUATERNION_OF_ROTOR]
_Q_SIGN = np.array([s for _, s in QUATERNION_OF_ROTOR])


def _quaternion_of(rotor: np.ndarray) -> np.ndarray:
    """``(w, x, y, z)`` of rotor coefficients ``(..., 1/e12/e13/e23)`` (and back: the map is
    its own inverse)."""
    return rotor[..., _Q_INDEX] * _Q_SIGN


def _vec(x, n: int, what: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape[-1:] != (n,):
        raise ValueError(f"{what} must have last axis of length {n}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what} contains NaN or inf")
    return a


# --- twists and wrenches ------------------------------------------------------------------


def twist_from_motion(motion) -> np.ndarray:
    """Twist coefficients from Pinocchio's motion vector ``[v, ω]`` (..., 6)."""
    m = _vec(motion, 6, "motion vector [v, ω]")
    return np.concatenate([m[..., 3:], m[..., :3]], axis=-1) * SIGN


def motion_from_twist(twist) -> np.ndarray:
    """Pinocchio's motion vector ``[v, ω]`` from twist coefficients (..., 6)."""
    t = _vec(twist, 6, "twist") * SIGN
    return np.concatenate([t[..., 3:], t[..., :3]], axis=-1)


def wrench_from_force(force) -> np.ndarray:
    """Wrench coefficients from Pinocchio's force vector ``[f, n]`` (..., 6)."""
    return twist_from_motion(force)


def force_from_wrench(wrench) -> np.ndarray:
    """Pinocchio's force vector ``[f, n]`` from wrench coefficients (..., 6)."""
    return motion_from_twist(wrench)


def twist_from_axis(kind: str, axis, pitch: float = 0.0) -> np.ndarray:
    """Unit screw axis ``B`` of a joint whose axis passes through the frame origin.

    ``kind`` is ``'revolute'`` (or ``'continuous'``: a line), ``'prismatic'`` (a direction)
    or ``'helical'`` (the screw ``L + pitch d`` of the line L and its direction d: the
    motion ``[pitch a, a]``).
    """
    a = _vec(axis, 3, "joint axis")
    n = float(np.linalg.norm(a))
    if n < 1e-12:
        raise ValueError(f"joint axis {a.tolist()} has zero length")
    a = a / n
    if kind in ("revolute", "continuous"):
        return twist_from_motion(np.concatenate([np.zeros(3), a]))
    if kind == "prismatic":
        return twist_from_motion(np.concatenate([a, np.zeros(3)]))
    if kind == "helical":
        return twist_from_motion(np.concatenate([float(pitch) * a, a]))
    raise ValueError(f"unknown joint kind {kind!r}; expected revolute, continuous, prismatic "
                     f"or helical")


# --- motors --------------------------------------------------------------------------------


def rotor_from_rotation(rot) -> np.ndarray:
    """Rotor coefficients ``(1, e12, e13, e23)`` of a rotation matrix."""
    return motor_from_rt(rot, np.zeros(3))[:4]


def motor_from_rt(rot, trans) -> np.ndarray:
    """Motor ``T R`` of the pose with rotation matrix ``rot`` and translation ``trans``."""
    R = np.asarray(rot, dtype=float)
    if R.shape != (3, 3):
        raise ValueError(f"rotation matrix must have shape (3, 3), got {R.shape}")
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, _vec(trans, 3, "translation")
    return motors_from_matrices(T[None], "pose")[0]


def motor_from_matrix(T) -> np.ndarray:
    """Motor of a rigid 4x4 homogeneous matrix; raises ``ValueError`` if it is not rigid."""
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4):
        raise ValueError(f"homogeneous matrix must have shape (4, 4), got {T.shape}")
    return motors_from_matrices(T[None], "homogeneous matrix")[0]


def matrix_from_motor(M) -> np.ndarray:
    """4x4 homogeneous matrix of a motor (normalised first); (..., 8) gives (..., 4, 4)."""
    from ..kernels.batch import motor_normalize_batch, motor_translation_batch

    m = _vec(M, 8, "motor")
    flat = np.ascontiguousarray(m.reshape(-1, 8))
    with PARALLEL_LOCK:
        n = motor_normalize_batch(flat, np.empty_like(flat))
        translation = motor_translation_batch(n, np.empty((len(n), 3)))
    w, x, y, z = _quaternion_of(n[:, :4]).T
    out = np.zeros((len(n), 4, 4))
    out[:, :3, :3] = np.moveaxis(_rotation(w, x, y, z), (0, 1), (-2, -1))
    out[:, :3, 3] = translation
    out[:, 3, 3] = 1.0
    return out.reshape(m.shape[:-1] + (4, 4))


def motor_from_quaternion(quat, trans=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Motor from a unit quaternion ``(w, x, y, z)`` and a translation."""
    q = _vec(quat, 4, "quaternion (w, x, y, z)")
    q = q / np.linalg.norm(q)
    return motor_from_rt(_rotation(*q), trans)


def quaternion_from_motor(M) -> np.ndarray:
    """Unit quaternion ``(w, x, y, z)`` of a motor's rotation (sign as the rotor's)."""
    m = _vec(M, 8, "motor")
    q = _quaternion_of(m[:4])
    return q / np.linalg.norm(q)


def motor_from_axis_angle(axis, angle: float, trans=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Motor rotating by ``angle`` about ``axis`` (through the origin), then translating."""
    a = _vec(axis, 3, "rotation axis")
    n = np.linalg.norm(a)
    if n < 1e-12:
        raise ValueError("rotation axis has zero length")
    a = a / n
    h = 0.5 * float(angle)
    return motor_from_quaternion(np.concatenate([[np.cos(h)], np.sin(h) * a]), trans)


def motor_product(a, b) -> np.ndarray:
    """Composition ``a b``: like the matrix product of the poses ``A @ B``."""
    out = np.empty(8)
    K.motor_mul(_vec(a, 8, "motor"), _vec(b, 8, "motor"), out)
    return out


def _rotation(w, x, y, z) -> np.ndarray:
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


# --- inertia --------------------------------------------------------------------------------


def inertia_at_com(mass: float, rotational_inertia, check: bool = True) -> np.ndarray:
    """The six inertia elements of eq. (18): rotational part and mass, about the com.

    ``check=False`` accepts a rotational inertia that is not positive semi-definite (not a
    physical body), as Pinocchio does."""
    m = float(mass)
    if not np.isfinite(m) or m < 0:
        raise ValueError(f"mass must be finite and non-negative, got {mass}")
    I3 = np.asarray(rotational_inertia, dtype=float)
    if I3.shape != (3, 3):
        raise ValueError(f"rotational inertia must have shape (3, 3), got {I3.shape}")
    if not np.all(np.isfinite(I3)):
        raise ValueError("rotational inertia contains NaN or inf")
    if not np.allclose(I3, I3.T, atol=1e-12 * max(1.0, np.abs(I3).max())):
        raise ValueError("rotational inertia must be symmetric")
    if check and np.linalg.eigvalsh(I3).min() < -1e-12 * max(1.0, np.abs(I3).max()):
        raise ValueError("rotational inertia must be positive semi-definite")
    d = SIGN[:3]
    out = np.zeros((6, 6))
    out[:3, :3] = d[:, None] * I3 * d[None, :]
    out[3:, 3:] = m * np.eye(3)
    return out


def inertia_from_parameters(mass: float, com, rotational_inertia,
                            check: bool = True) -> np.ndarray:
    """Spatial inertia ``I^CoM = M^CoM * I`` (eq. 19) of a body about the frame origin.

    ``rotational_inertia`` is about the centre of mass ``com``, in the frame's axes.
    """
    c = _vec(com, 3, "centre of mass")
    out = np.empty((6, 6))
    K.inertia_transform(motor_from_rt(np.eye(3), c),
                        inertia_at_com(mass, rotational_inertia, check), out)
    return out


def inertia_transform(M, inertia) -> np.ndarray:
    """``M * I`` (eq. 16): an inertia given in frame B, expressed in frame A (M = pose of B)."""
    out = np.empty((6, 6))
    K.inertia_transform(_vec(M, 8, "motor"), np.asarray(inertia, dtype=float), out)
    return out


def inertia_to_pinocchio(inertia) -> np.ndarray:
    """Pinocchio's 6x6 spatial inertia matrix (order [v, ω]) of a CGA inertia tensor."""
    I = np.asarray(inertia, dtype=float)
    if I.shape[-2:] != (6, 6):
        raise ValueError(f"inertia must have shape (..., 6, 6), got {I.shape}")
    phys = SIGN[:, None] * I * SIGN[None, :]
    order = [3, 4, 5, 0, 1, 2]
    return phys[..., order, :][..., :, order]


def inertia_from_pinocchio(matrix) -> np.ndarray:
    """CGA inertia tensor of Pinocchio's 6x6 spatial inertia matrix (order [v, ω])."""
    P = np.asarray(matrix, dtype=float)
    if P.shape[-2:] != (6, 6):
        raise ValueError(f"spatial inertia must have shape (..., 6, 6), got {P.shape}")
    order = [3, 4, 5, 0, 1, 2]
    phys = P[..., order, :][..., :, order]
    return SIGN[:, None] * phys * SIGN[None, :]
