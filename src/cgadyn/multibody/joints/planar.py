"""The planar joint: any rigid motion in the joint frame's XY plane (SE(2)).

``q_j = (x, y, cos θ, sin θ)``, as Pinocchio's ``JointModelPlanar``: a translation in the
plane and a rotation θ about z, whose ``(cos θ, sin θ)`` is a unit vector (checked and
normalised as a quaternion is: ``record.JointType.unit_length``). The joint motor is
``M_J(q) = T(x, y, 0) R_z(θ)`` (eq. 6), the rotor ``R_z(θ) = cos(θ/2) - sin(θ/2) e12``.
Its motion subspace is the unit twists of ``vx``, ``vy`` and ``ωz``, constant in the child
frame, so ``v_j = (vx, vy, ω)`` is the body's planar twist in its own frame (Pinocchio's).
The configuration space is SE(2): ``q ⊕ v = M exp(V / 2)`` and ``q1 ⊖ q0 = log(~M0 M1)``
(``V = S v``), the exponential and logarithm of SE(3) restricted to the plane, which are
SE(2)'s (Pinocchio's ``SpecialEuclideanOperationTpl<2>``). MuJoCo has no planar joint.
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
from ...kernels.lane_arrays import select_nonnegative, sqrt
from ...kernels.layout import physical, quaternion
from .record import JointType, unit_limits

PLANAR = 5


@inline
def planar_rotor(c, s):
    """``cos(θ/2), sin(θ/2)`` (up to a common sign, the same rotation) of the direction
    ``(c, s) ∝ (cos θ, sin θ)``, normalised: ``cos(θ/2) = √((1 + cos θ)/2)`` where
    ``cos θ ≥ 0``, ``sin(θ/2) = √((1 - cos θ)/2)`` elsewhere, the other from
    ``sin θ = 2 cos(θ/2) sin(θ/2)``: each exact on its half (the larger factor ≥ 1/√2),
    picked lane by lane in a batch (``select_nonnegative``; no half angle is continuous on
    the whole circle)."""
    r = 1.0 / sqrt(c * c + s * s)  # of a number, or of each lane
    c, s = c * r, s * r
    big = select_nonnegative(c, sqrt(0.5 * (1.0 + c)), sqrt(0.5 * (1.0 - c)))
    other = s / (2.0 * big)
    return select_nonnegative(c, big, other), select_nonnegative(c, other, big)


@inline
def planar_joint_motor(q, i, out):
    """``out = T(x, y, 0) R_z(θ)`` of ``q[i:i+4] = (x, y, cos θ, sin θ)``."""
    ch, sh = planar_rotor(q[i + 2], q[i + 3])
    translator_rotor(q[i], q[i + 1], 0.0, ch, -sh, 0.0, 0.0, out)


@inline
def planar_motor(X, q, i, tmp, out):
    """``out = X T(x, y, 0) R_z(θ)`` (eq. 5); ``tmp`` 8 floats."""
    planar_joint_motor(q, i, tmp)
    motor_mul(X, tmp, out)


@inline
def _planar_configuration(M, out, i):
    """``out[i:i+4] = (x, y, cos θ, sin θ)`` of a motor of the plane: its translation and
    ``cos θ = w² - z²``, ``sin θ = 2 w z`` of its quaternion ``(w, 0, 0, z)``, normalised."""
    x, y, _ = motor_translation(M)
    w, _, _, z = quaternion(M)
    n = w * w + z * z
    out[i], out[i + 1] = x, y
    out[i + 2], out[i + 3] = (w * w - z * z) / n, 2.0 * w * z / n


@inline
def planar_integrate(q, i, tmp, out):
    """``out[i:i+4] = q ⊕ v = M exp(V / 2)`` (eq. 6), the planar twist ``V = S v`` given in
    ``tmp[2]`` (``tmp``: (3, 8))."""
    twist_exp(tmp[2], tmp[1])  # exp(V / 2)
    planar_joint_motor(q, i, tmp[0])  # M
    motor_mul(tmp[0], tmp[1], tmp[2])  # M exp(V / 2)
    _planar_configuration(tmp[2], out, i)


@inline
def planar_step(q, i, d0, d1, tmp, out):
    """``out[i:i+4]``: the origin moved along the plane's vector ``R(θ) (d0, d1)`` of the
    step's linear displacement (in the child's frame at the start of the step), the angle
    by the rotation whose twist ``tmp[2]`` gives (about the origin): K24a in the plane
    (``free_flyer_step``)."""
    c, s = q[i + 2], q[i + 3]
    n = 1.0 / math.sqrt(c * c + s * s)
    x, y = q[i] + n * (c * d0 - s * d1), q[i + 1] + n * (s * d0 + c * d1)
    planar_integrate(q, i, tmp, out)
    out[i], out[i + 1] = x, y


@inline
def planar_difference(q0, q1, i, k, tmp, out):
    """``out[k:k+3] = q1 ⊖ q0 = (vx, vy, ω)`` of ``V = log(~M0 M1)``, the motor taken with a
    non-negative scalar part (the angle in [-π, π], Pinocchio's SE(2) ``log``). ``tmp``:
    (3, 8)."""
    planar_joint_motor(q0, i, tmp[0])
    planar_joint_motor(q1, i, tmp[1])
    motor_reverse(tmp[0], tmp[2])
    motor_mul(tmp[2], tmp[1], tmp[0])  # ~M0 M1
    if tmp[0, 0] < 0.0:  # -M is the same motion
        for c in range(8):
            tmp[0, c] = -tmp[0, c]
    motor_log(tmp[0], tmp[1])
    _, _, w3, v1, v2, _ = physical(tmp[1])
    out[k], out[k + 1], out[k + 2] = v1, v2, w3


@inline
def planar_frame_rate(v, k, h, out):
    """``out[k:k+2] += h ω × (vx, vy)`` of ``v[k:k+3] = (vx, vy, ω)``: the turning frame's
    share of the change of the planar velocity it expresses (``free_flyer_frame_rate`` in
    the plane, K24)."""
    out[k] -= h * v[k + 2] * v[k + 1]
    out[k + 1] += h * v[k + 2] * v[k]


@inline
def planar_transport(w, k, h, x):
    """``(x[k], x[k+1])`` turned by ``-h ω``, ω = ``w[k+2]``: a planar velocity moved into
    the frame after the step's turn (``free_flyer_transport`` in the plane, K24)."""
    c, s = math.cos(h * w[k + 2]), math.sin(h * w[k + 2])
    x0, x1 = x[k], x[k + 1]
    x[k], x[k + 1] = c * x0 + s * x1, c * x1 - s * x0


def _plane(B: np.ndarray) -> np.ndarray:
    return twist_from_motion(np.eye(6)[[0, 1, 5]])  # vx, vy, ωz of the child body


def _random(rng: np.random.Generator, q: np.ndarray, box: float) -> None:
    """The position as drawn within the limits, a uniformly random angle."""
    theta = rng.uniform(-np.pi, np.pi)
    q[2:4] = np.cos(theta), np.sin(theta)


TYPES = (
    JointType(code=PLANAR, name="planar", kind="planar", label="planar", nq=4, nv=3,
              q_names=("x", "y", "cos", "sin"), v_names=("vx", "vy", "wz"),
              speeds=("linear", "linear", "angular"), actuated=True, floating=False,
              additive=False, quaternion=2, unit_length=2, neutral=(0.0, 0.0, 1.0, 0.0),
              subspace=_plane, limits=unit_limits(2, 4), random=_random,
              pinocchio=("JointModelPlanar",), mujoco=None),
)
"""The planar type's record (``record.JointType``): actuated (a gantry's two slides and
turn; MuJoCo has no planar joint, so no MuJoCo layout)."""
