"""Every joint type in one place: its motor, its motion subspace, its configuration space.

As in Featherstone's ``jcalc``, adding a joint type means adding a case here. A joint j
moves its body relative to the body of its parent λ(j) by the motor (eqs. 5-6)

    M_j = X_j M_J(q_j)

with ``X_j`` its constant placement and ``M_J`` the joint motor of its configuration
``q_j``; its velocity ``v_j`` moves the body with the twist ``S_j v_j``, the columns of
``S_j`` being the joint's motion subspace, constant twists in the joint frame. The joint
types:

======================  ====  ====  ====================================================
type                    nq_j  nv_j  M_J(q_j) and S_j
======================  ====  ====  ====================================================
``REVOLUTE``            1     1     ``exp(q B / 2) = cos(q/2) + sin(q/2) B``: B a unit line
``REVOLUTE_UNBOUNDED``  1     1     the same, for an angle without limits
``PRISMATIC``           1     1     ``exp(q B / 2) = 1 + (q/2) B``: B a unit direction
``FREE_FLYER``          7     6     the motor ``T(p) R(x, y, z, w)`` of
                                    ``q_j = (p1, p2, p3, x, y, z, w)``; ``S_j`` the six
                                    unit twists, so ``S_j v_j`` is the body twist ``(v, ω)``
======================  ====  ====  ====================================================

An unbounded revolute joint (URDF's ``continuous``) takes one angle, where Pinocchio takes
its cos and sin; it differs from a revolute joint only on the configuration manifold, where
``difference`` wraps its angle to (-π, π]. The free flyer follows Pinocchio's
``JointModelFreeFlyer``: the translation in the parent frame, the unit quaternion in the
order x, y, z, w, and the velocity ``[v, ω]`` of the body in its own frame.

The compiled functions read a model unpacked by ``cgadyn.multibody.packed.unpack``: per joint
``types``, ``iq``/``iv`` (the first index of the joint in q and in v, with a final entry
nq/nv, so that joint j's coordinates are ``q[iq[j]:iq[j+1]]``), ``placements`` and ``S``,
the motion subspace of every velocity coordinate as a twist, one row each.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import inline
from ..kernels import (
    dot,
    motor_log,
    motor_mul,
    motor_mul_rotor,
    motor_mul_translator,
    motor_reverse,
    motor_translation,
    translator_rotor,
    twist_exp,
)
from ..kernels.halfangle import LIBM_BEYOND, half_angle_sincos
from ..kernels.lane_arrays import sqrt
from ..kernels.layout import physical, quaternion, rotor

REVOLUTE = 0
REVOLUTE_UNBOUNDED = 1
PRISMATIC = 2
FREE_FLYER = 3

TYPE_NAMES = ("revolute", "revolute_unbounded", "prismatic", "free_flyer")
NQ = (1, 1, 1, 7)
"""Size of a joint's configuration, by type."""
NV = (1, 1, 1, 6)
"""Size of a joint's velocity, by type."""

ACTUATED = (True, True, True, False)
"""Whether a joint of this type has an actuator of its own, by type: a free flyer has none
(nothing pushes on a floating base but contact and other external forces), so controllers
leave its coordinates alone."""
SPEEDS = (("angular",), ("angular",), ("linear",), ("free",) * 3 + ("angular",) * 3)
"""What each velocity coordinate of a joint is, by type: an angular rate, the rate of a
slide inside the robot, or the linear velocity of a free body (which may fall as long as
it likes). ``simulate`` bounds each one by what one step can resolve."""

KIND_TYPE = {"revolute": REVOLUTE, "continuous": REVOLUTE_UNBOUNDED, "prismatic": PRISMATIC,
             "free_flyer": FREE_FLYER}
"""The joint kinds a model records (URDF's names, and ``free_flyer``) and their types."""

QUATERNION_TOLERANCE = 1e-3
"""A free flyer's quaternion whose norm differs from 1 by more than this is refused; a
smaller difference is normalised away (as after many steps of integration)."""

@inline
def joint_scalars(q, c, s):
    """``c[k], s[k] = cos(q_k / 2), sin(q_k / 2)`` for every coordinate of q: the scalars of
    the revolute joint motors ``exp(q_j B_j / 2) = c_j + s_j B_j`` (eq. 6), in one
    branch-free loop that LLVM vectorises (other coordinates' values go unused). ``q``
    finite."""
    any_far = False
    for k in range(q.shape[0]):
        x = q[k]
        far = abs(x) > 2.0 * LIBM_BEYOND  # half angles beyond: redone below with libm
        any_far |= far
        c[k], s[k] = half_angle_sincos(0.0 if far else x)
    if any_far:
        for k in range(q.shape[0]):
            if abs(q[k]) > 2.0 * LIBM_BEYOND:
                c[k] = math.cos(0.5 * q[k])
                s[k] = math.sin(0.5 * q[k])


@inline
def joint_motors(m, q, c, s, tmp, out):
    """``out[j] = M_j = X_j M_J(q_j)`` for every joint: the pose of body j in the frame of its
    parent (eqs. 5-6); ``c, s`` from ``joint_scalars``, ``tmp`` 8 floats.

    A revolute joint takes its scalars from ``c, s`` (indexed by q coordinate), a prismatic
    one ``(1, q_j/2)``. Joint axes pass through the joint frame's origin (URDF's convention,
    checked by ``Model``), so a revolute joint's motor is a rotor and a prismatic joint's a
    translator, and the product with ``X_j`` is the cheaper one each allows (32 and 12
    multiplications, where the general motor product takes 48). Free flyers take a second
    loop: as a third branch of the first, their code more than doubles its time.
    """
    for j in range(m.n):
        t = m.types[j]
        k = m.iv[j]
        i = m.iq[j]
        if t <= REVOLUTE_UNBOUNDED:  # cos(q/2) + sin(q/2) B, B the (e23, e13, e12) part
            sk = s[i]
            tmp[0], tmp[1], tmp[2], tmp[3] = c[i], sk * m.S[k, 2], sk * m.S[k, 1], sk * m.S[k, 0]
            motor_mul_rotor(m.placements[j], tmp, out[j])
        elif t == PRISMATIC:  # 1 + (q/2) B, B = (e1∞, e2∞, e3∞) part of the direction
            h = 0.5 * q[i]
            tmp[4], tmp[5], tmp[6] = h * m.S[k, 3], h * m.S[k, 4], h * m.S[k, 5]
            motor_mul_translator(m.placements[j], tmp, out[j])
    for j in range(m.n):
        if m.types[j] == FREE_FLYER:
            free_flyer_motor(q, m.iq[j], tmp)
            motor_mul(m.placements[j], tmp, out[j])


@inline
def free_flyer_motor(q, i, out):
    """The motor ``T(p) R(x, y, z, w)`` of a free flyer's configuration
    ``q[i:i+7] = (p1, p2, p3, x, y, z, w)``, the quaternion normalised."""
    x, y, z, w = q[i + 3], q[i + 4], q[i + 5], q[i + 6]
    r = 1.0 / sqrt(x * x + y * y + z * z + w * w)  # of a number, or of each lane
    r0, r1, r2, r3 = rotor((w * r, x * r, y * r, z * r))
    translator_rotor(q[i], q[i + 1], q[i + 2], r0, r1, r2, r3, out)


@inline
def free_flyer_configuration(M, out, i):
    """``out[i:i+7] = (p, x, y, z, w)`` of a motor, the quaternion normalised: the inverse
    of ``free_flyer_motor``."""
    w, x, y, z = quaternion(M)
    r = 1.0 / sqrt(x * x + y * y + z * z + w * w)  # of a number, or of each lane
    out[i], out[i + 1], out[i + 2] = motor_translation(M)
    out[i + 3], out[i + 4], out[i + 5], out[i + 6] = x * r, y * r, z * r, w * r


@inline
def joint_twist(m, j, x, out):
    """``out = S_j x_j``: the twist of the joint's velocity (``x = v``) or the acceleration
    it contributes (``x = a``), in the joint frame."""
    k0 = m.iv[j]
    for i in range(6):
        out[i] = x[k0] * m.S[k0, i]
    for k in range(k0 + 1, m.iv[j + 1]):
        for i in range(6):
            out[i] += x[k] * m.S[k, i]


def unit_axes(S: np.ndarray, joint_types: np.ndarray) -> np.ndarray:
    """int64 (nv,): for each velocity coordinate of a one-dof joint whose motion subspace
    column ``S[k]`` is ``±e_i`` (one coefficient ±1, the others 0: an axis along a
    coordinate axis of its frame, as URDFs mostly write them), ``i``; -1 for any other
    (and for the coordinates of a free flyer). Products with such a column read one
    coefficient, exactly; the packed model stores these so that compiled code need not
    look for them on every call."""
    one_dof = np.repeat([NV[t] == 1 for t in joint_types], [NV[t] for t in joint_types])
    out = np.full(len(S), -1, dtype=np.int64)
    for k, column in enumerate(np.asarray(S, dtype=np.float64)):
        nonzero = np.flatnonzero(column)
        if one_dof[k] and len(nonzero) == 1 and abs(column[nonzero[0]]) == 1.0:
            out[k] = nonzero[0]
    return out


@inline
def joint_power(m, j, w, tau):
    """``τ_j = -S_jᵀ · W``: the generalised force of a wrench W on the joint's velocity
    coordinates, by the power pairing (eq. 9)."""
    for k in range(m.iv[j], m.iv[j + 1]):
        tau[k] = -dot(m.S[k], w)


@inline
def has_free_flyer(m):
    """Whether the model has a free flyer: the only joint type whose nq_j (7) differs from
    its nv_j (6), so ``nq != nv`` says it without a scan of the joints."""
    return m.nq != m.nv


@inline
def quaternion_error(m, q):
    """The first free-flyer joint whose quaternion's norm is not within
    ``QUATERNION_TOLERANCE`` of 1, or -1."""
    if not has_free_flyer(m):
        return -1
    for j in range(m.types.shape[0]):
        if m.types[j] == FREE_FLYER:
            i = m.iq[j] + 3
            norm = math.sqrt(q[i] ** 2 + q[i + 1] ** 2 + q[i + 2] ** 2 + q[i + 3] ** 2)
            if not abs(norm - 1.0) <= QUATERNION_TOLERANCE:
                return j
    return -1


@inline
def joint_integrate(m, j, q, v, tmp, out):
    """``out_j = q_j ⊕ v_j``, moving joint j's configuration along its velocity for unit
    time: ``q + v`` for one-dof joints; ``M exp(V / 2)`` for a free flyer (eq. 6), the body
    twist V applied in the body's frame (Pinocchio's ``integrate``). ``tmp``: (3, 8)."""
    i = m.iq[j]
    if m.types[j] != FREE_FLYER:
        out[i] = q[i] + v[m.iv[j]]
        return
    joint_twist(m, j, v, tmp[2])  # V = S v, the body twist
    twist_exp(tmp[2], tmp[1])  # exp(V / 2)
    free_flyer_motor(q, i, tmp[0])  # M
    motor_mul(tmp[0], tmp[1], tmp[2])  # M exp(V / 2)
    free_flyer_configuration(tmp[2], out, i)
    dot = 0.0
    for c in range(3, 7):
        dot += out[i + c] * q[i + c]
    if dot < 0.0:
        for c in range(3, 7):
            out[i + c] = -out[i + c]


@inline
def joint_difference(m, j, q0, q1, tmp, out):
    """``out_j = q1_j ⊖ q0_j``, the velocity that moves q0 to q1 in unit time (the inverse of
    ``joint_integrate``): ``q1 - q0``, wrapped to (-π, π] for an unbounded revolute joint;
    for a free flyer the body twist ``V = log(~M0 M1)`` with ``exp(V / 2) = ~M0 M1``, the
    motor taken with a non-negative scalar part so that the rotation is at most π
    (Pinocchio's ``log6``). ``tmp``: (3, 8)."""
    i, k, t = m.iq[j], m.iv[j], m.types[j]
    if t != FREE_FLYER:
        d = q1[i] - q0[i]
        out[k] = math.atan2(math.sin(d), math.cos(d)) if t == REVOLUTE_UNBOUNDED else d
        return
    free_flyer_motor(q0, i, tmp[0])
    free_flyer_motor(q1, i, tmp[1])
    motor_reverse(tmp[0], tmp[2])
    motor_mul(tmp[2], tmp[1], tmp[0])  # ~M0 M1
    if tmp[0, 0] < 0.0:  # -M is the same motion: the rotation angle in [0, π]
        for c in range(8):
            tmp[0, c] = -tmp[0, c]
    motor_log(tmp[0], tmp[1])  # the twist V, exp(V / 2) = ~M0 M1
    w1, w2, w3, v1, v2, v3 = physical(tmp[1])
    out[k], out[k + 1], out[k + 2], out[k + 3], out[k + 4], out[k + 5] = v1, v2, v3, w1, w2, w3
