"""The free flyer: a body moved by any rigid motion (a floating base).

``q_j = (p1, p2, p3, x, y, z, w)``: the translation in the parent frame and a unit
quaternion, as Pinocchio's ``JointModelFreeFlyer``; ``M_J(q) = T(p) R(x, y, z, w)``. Its
motion subspace is the six unit twists, so ``v_j`` is the body twist ``[v, ω]`` in the
body's own frame. The configuration is a manifold, not a vector space:
``q ⊕ v = M exp(V / 2)`` (eq. 6, V = S v the body twist, applied in the body's frame) and
``q1 ⊖ q0 = log(~M0 M1)``. MuJoCo's free joint holds ``[x, y, z, qw, qx, qy, qz]`` and its
linear velocity in the parent (world) frame: ``qvel = (R v, ω)``.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import inline
from ...cga.conventions import twist_from_motion
from ...kernels import (
    motor_log,
    motor_mul,
    motor_reverse,
    motor_translation,
    translator_rotor,
    twist_exp,
)
from ...kernels.lane_arrays import sqrt
from ...kernels.layout import physical, quaternion, rotor
from ...kernels.rigid import rigid_frame, rigid_rotate
from .record import JointType, unit_limits

FREE_FLYER = 3


@inline
def quaternion_rotor(q, i):
    """The rotor coefficients ``(1, e12, e13, e23)`` of the unit quaternion
    ``q[i:i+4] = (x, y, z, w)``, normalised: the rotation of a free flyer and of a spherical
    joint."""
    x, y, z, w = q[i], q[i + 1], q[i + 2], q[i + 3]
    r = 1.0 / sqrt(x * x + y * y + z * z + w * w)  # of a number, or of each lane
    return rotor((w * r, x * r, y * r, z * r))


@inline
def free_flyer_motor(q, i, out):
    """The motor ``T(p) R(x, y, z, w)`` of a free flyer's configuration
    ``q[i:i+7] = (p1, p2, p3, x, y, z, w)``, the quaternion normalised."""
    r0, r1, r2, r3 = quaternion_rotor(q, i + 3)
    translator_rotor(q[i], q[i + 1], q[i + 2], r0, r1, r2, r3, out)


@inline
def _quaternion_motor(q, i, o, out):
    """``T(p) R`` of ``q[i:i+7]`` for ``o = 3`` (a free flyer), ``R`` of ``q[i:i+4]`` for
    ``o = 0`` (a spherical joint): the quaternion at ``i + o``."""
    r0, r1, r2, r3 = quaternion_rotor(q, i + o)
    if o == 0:
        translator_rotor(0.0, 0.0, 0.0, r0, r1, r2, r3, out)
    else:
        translator_rotor(q[i], q[i + 1], q[i + 2], r0, r1, r2, r3, out)


@inline
def _quaternion_configuration(M, out, i, o):
    """``out[i:i+o+4]``: the translation (``o = 3``) and the quaternion ``(x, y, z, w)`` of a
    motor, normalised; the inverse of ``_quaternion_motor``."""
    w, x, y, z = quaternion(M)
    r = 1.0 / sqrt(x * x + y * y + z * z + w * w)  # of a number, or of each lane
    if o != 0:
        out[i], out[i + 1], out[i + 2] = motor_translation(M)
    out[i + o], out[i + o + 1], out[i + o + 2], out[i + o + 3] = x * r, y * r, z * r, w * r


@inline
def quaternion_integrate(q, i, o, tmp, out):
    """``out[i:i+o+4] = q ⊕ v = M exp(V / 2)`` (eq. 6), the body twist ``V = S v`` given in
    ``tmp[2]`` (``tmp``: (3, 8)), M the motor of a free flyer (``o = 3``) or the rotor of a
    spherical joint (``o = 0``, V a rotation); the quaternion's sign kept on q's side."""
    twist_exp(tmp[2], tmp[1])  # exp(V / 2)
    _quaternion_motor(q, i, o, tmp[0])  # M
    motor_mul(tmp[0], tmp[1], tmp[2])  # M exp(V / 2)
    _quaternion_configuration(tmp[2], out, i, o)
    dot = 0.0
    for c in range(o, o + 4):
        dot += out[i + c] * q[i + c]
    if dot < 0.0:
        for c in range(o, o + 4):
            out[i + c] = -out[i + c]


@inline
def free_flyer_integrate(q, i, tmp, out):
    """``out[i:i+7] = q ⊕ v = M exp(V / 2)``, the body twist ``V = S v`` given in
    ``tmp[2]`` (``tmp``: (3, 8)); the quaternion's sign kept on q's side."""
    quaternion_integrate(q, i, 3, tmp, out)


@inline
def free_flyer_step(q, i, d0, d1, d2, tmp, out):
    """``out[i:i+7]``: the origin moved along the world vector ``R d`` of the step's
    linear displacement ``d = (d0, d1, d2)`` (given in the body's frame at the start of
    the step), the rotation by ``R exp(ω)``, its twist given in ``tmp[2]`` (a pure rotation
    about the origin, which ``quaternion_integrate`` leaves where it is): K24a, the Euler
    steps' move of a free flyer (``dispatch.joint_step``)."""
    _quaternion_motor(q, i, 3, tmp[0])
    r, p = rigid_frame(tmp[0])
    w0, w1, w2 = rigid_rotate(r, d0, d1, d2)
    p0, p1, p2 = p[0] + w0, p[1] + w1, p[2] + w2
    quaternion_integrate(q, i, 3, tmp, out)
    out[i], out[i + 1], out[i + 2] = p0, p1, p2


@inline
def quaternion_difference(q0, q1, i, o, k, tmp, out):
    """``out = q1 ⊖ q0``: the body twist ``V = log(~M0 M1)`` with ``exp(V / 2) = ~M0 M1``,
    the motor taken with a non-negative scalar part so that the rotation is at most π
    (Pinocchio's ``log6``, ``log3``): ``[v, ω]`` in ``out[k:k+6]`` for a free flyer
    (``o = 3``), ``ω`` in ``out[k:k+3]`` for a spherical joint (``o = 0``). ``tmp``: (3, 8)."""
    _quaternion_motor(q0, i, o, tmp[0])
    _quaternion_motor(q1, i, o, tmp[1])
    motor_reverse(tmp[0], tmp[2])
    motor_mul(tmp[2], tmp[1], tmp[0])  # ~M0 M1
    if tmp[0, 0] < 0.0:  # -M is the same motion: the rotation angle in [0, π]
        for c in range(8):
            tmp[0, c] = -tmp[0, c]
    motor_log(tmp[0], tmp[1])  # the twist V, exp(V / 2) = ~M0 M1
    w1, w2, w3, v1, v2, v3 = physical(tmp[1])
    if o == 0:
        out[k], out[k + 1], out[k + 2] = w1, w2, w3
    else:
        out[k], out[k + 1], out[k + 2] = v1, v2, v3
        out[k + 3], out[k + 4], out[k + 5] = w1, w2, w3


@inline
def free_flyer_difference(q0, q1, i, k, tmp, out):
    """``out[k:k+6] = q1 ⊖ q0`` (``quaternion_difference``), as ``[v, ω]``. ``tmp``:
    (3, 8)."""
    quaternion_difference(q0, q1, i, 3, k, tmp, out)


@inline
def free_flyer_frame_rate(v, k, h, out):
    """``out[k:k+3] += h ω × v`` of ``v[k:k+6] = [v, ω]``: the rate at which the body's own
    turning changes the linear velocity it expresses in its frame (``d(R v)/dt = R (v̇ + ω
    × v)``, R the body's rotation), for a step that integrates the velocity of the body's
    origin in the frame it started from (``rollout``'s Euler methods, K24)."""
    v1, v2, v3, w1, w2, w3 = v[k], v[k + 1], v[k + 2], v[k + 3], v[k + 4], v[k + 5]
    out[k] += h * (w2 * v3 - w3 * v2)
    out[k + 1] += h * (w3 * v1 - w1 * v3)
    out[k + 2] += h * (w1 * v2 - w2 * v1)


@inline
def free_flyer_transport(w, k, h, x):
    """``x[k:k+3] ← exp(-h ω̂) x[k:k+3]``, ω = ``w[k+3:k+6]`` (Rodrigues' formula): a
    linear velocity expressed in the body's frame at the start of a step moved into its
    frame after the step's rotation ``exp(h ω̂)``, so that its world vector ``R v`` is
    unchanged (K24); the angular velocity, about which the body turned, stays."""
    p1, p2, p3 = -h * w[k + 3], -h * w[k + 4], -h * w[k + 5]  # φ = -h ω
    t2 = p1 * p1 + p2 * p2 + p3 * p3
    if t2 < 1e-8:  # sin θ / θ and (1 - cos θ) / θ² by their series, exact to rounding
        a, b = 1.0 - t2 / 6.0, 0.5 - t2 / 24.0
    else:
        t = math.sqrt(t2)
        a, b = math.sin(t) / t, (1.0 - math.cos(t)) / t2
    x1, x2, x3 = x[k], x[k + 1], x[k + 2]
    c1, c2, c3 = p2 * x3 - p3 * x2, p3 * x1 - p1 * x3, p1 * x2 - p2 * x1  # φ × x
    d1, d2, d3 = p2 * c3 - p3 * c2, p3 * c1 - p1 * c3, p1 * c2 - p2 * c1  # φ × (φ × x)
    x[k], x[k + 1], x[k + 2] = x1 + a * c1 + b * d1, x2 + a * c2 + b * d2, x3 + a * c3 + b * d3


def _every_twist(B: np.ndarray) -> np.ndarray:
    return twist_from_motion(np.eye(6))  # [v, ω] of the body


def _random(rng: np.random.Generator, q: np.ndarray, box: float) -> None:
    """A uniform position in ``[-box, box]³``, a uniformly random rotation."""
    q[0:3] = rng.uniform(-box, box, 3)
    quat = rng.normal(size=4)
    q[3:7] = quat / np.linalg.norm(quat)  # uniform on the unit sphere S³


def _rotation(q: np.ndarray) -> np.ndarray:
    """(..., 3, 3) the rotation matrix of the unit quaternion ``q[..., 3:7] = (x, y, z, w)``."""
    x, y, z, w = (q[..., c] for c in range(3, 7))
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def _to_mujoco(q: np.ndarray) -> np.ndarray:
    return np.concatenate([q[..., :3], q[..., 6:7], q[..., 3:6]], axis=-1)


def _from_mujoco(qpos: np.ndarray) -> np.ndarray:
    return np.concatenate([qpos[..., :3], qpos[..., 4:7], qpos[..., 3:4]], axis=-1)


def _mujoco_velocity(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    linear = np.einsum("...ab,...b->...a", _rotation(q), v[..., :3])
    return np.concatenate([linear, v[..., 3:]], axis=-1)


def _from_mujoco_velocity(q: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    linear = np.einsum("...ba,...b->...a", _rotation(q), qvel[..., :3])
    return np.concatenate([linear, qvel[..., 3:]], axis=-1)


def _mujoco_acceleration(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """qacc of ``qvel = (R v, ω)``: ``d/dt (R v) = R (v̇ + ω × v)``, the angular part as is."""
    linear = a[..., :3] + np.cross(v[..., 3:], v[..., :3])
    return np.concatenate([np.einsum("...ab,...b->...a", _rotation(q), linear), a[..., 3:]],
                          axis=-1)


def _from_mujoco_acceleration(q: np.ndarray, v: np.ndarray, qacc: np.ndarray) -> np.ndarray:
    """The inverse of ``_mujoco_acceleration``: ``v̇ = Rᵀ qacc - ω × v``."""
    linear = np.einsum("...ba,...b->...a", _rotation(q), qacc[..., :3])
    return np.concatenate([linear - np.cross(v[..., 3:], v[..., :3]), qacc[..., 3:]], axis=-1)


TYPES = (
    JointType(code=FREE_FLYER, name="free_flyer", kind="free_flyer", label="free-flyer",
              nq=7, nv=6, q_names=("x", "y", "z", "qx", "qy", "qz", "qw"),
              v_names=("vx", "vy", "vz", "wx", "wy", "wz"),
              speeds=("free",) * 3 + ("angular",) * 3, actuated=False, floating=True,
              additive=False, quaternion=3, neutral=(0.0,) * 6 + (1.0,),
              subspace=_every_twist, limits=unit_limits(3, 7), random=_random,
              pinocchio=("JointModelFreeFlyer",), mujoco="free", to_mujoco=_to_mujoco,
              from_mujoco=_from_mujoco, mujoco_velocity=_mujoco_velocity,
              from_mujoco_velocity=_from_mujoco_velocity,
              mujoco_acceleration=_mujoco_acceleration,
              from_mujoco_acceleration=_from_mujoco_acceleration),
)
"""The free flyer's record (``record.JointType``): no actuator (nothing pushes on a
floating base but contact and other external forces)."""
