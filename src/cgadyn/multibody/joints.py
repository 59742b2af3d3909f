"""Every joint type in one place: its motor, its motion subspace, its configuration space.

As in Featherstone's ``jcalc``, adding a joint type means adding a case here. A joint j
moves its body relative to the body of its parent λ(j) by the motor (eqs. 5-6)

    M_j = X_j M_J(q_j)

with ``X_j`` its constant placement and ``M_J`` the joint motor of its configuration
``q_j``; its velocity ``v_j`` moves the body with the twist ``S_j v_j``, the columns of
``S_j`` being the joint's motion subspace, constant twists in the joint frame. The joint
types:

================  ====  ====  ==========================================================
type              nq_j  nv_j  M_J(q_j) and S_j
================  ====  ====  ==========================================================
``REVOLUTE``      1     1     ``exp(q B / 2) = cos(q/2) + sin(q/2) B``: B a unit line
``PRISMATIC``     1     1     ``exp(q B / 2) = 1 + (q/2) B``: B a unit direction
``FREE_FLYER``    7     6     the motor ``T(p) R(x, y, z, w)`` of
                              ``q_j = (p1, p2, p3, x, y, z, w)``; ``S_j`` the six unit
                              twists, so ``S_j v_j`` is the body twist ``(v, ω)``
================  ====  ====  ==========================================================

A continuous joint is a revolute joint without limits and takes one angle (Pinocchio
takes its cos and sin). The free flyer follows Pinocchio's ``JointModelFreeFlyer``: the
translation in the parent frame, the unit quaternion in the order x, y, z, w, and the
velocity ``[v, ω]`` of the body in its own frame.

The compiled functions read a model unpacked by ``cgadyn.multibody.packed.unpack``: per joint
``types``, ``iq``/``iv`` (the first index of the joint in q and in v, with a final entry
nq/nv, so that joint j's coordinates are ``q[iq[j]:iq[j+1]]``), ``placements`` and ``S``,
the motion subspace of every velocity coordinate as a twist, one row each.
"""

from __future__ import annotations

import math

from .._jit import inline
from ..kernels import dot, motor_mul, motor_mul_rotor, motor_mul_translator, translator_rotor
from ..kernels.halfangle import LIBM_BEYOND, half_angle_sincos
from ..kernels.layout import rotor

REVOLUTE = 0
PRISMATIC = 1
FREE_FLYER = 2

TYPE_NAMES = ("revolute", "prismatic", "free_flyer")
NQ = (1, 1, 7)
"""Size of a joint's configuration, by type."""
NV = (1, 1, 6)
"""Size of a joint's velocity, by type."""

KIND_TYPE = {"revolute": REVOLUTE, "continuous": REVOLUTE, "prismatic": PRISMATIC,
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
        if t == REVOLUTE:  # cos(q/2) + sin(q/2) B, B = (e23, e13, e12) part of the line
            sk = s[i]
            tmp[0], tmp[1], tmp[2], tmp[3] = c[i], sk * m.S[k, 2], sk * m.S[k, 1], sk * m.S[k, 0]
            motor_mul_rotor(m.placements[j], tmp, out[j])
        elif t == PRISMATIC:  # 1 + (q/2) B, B = (e1∞, e2∞, e3∞) part of the direction
            h = 0.5 * q[i]
            tmp[4], tmp[5], tmp[6] = h * m.S[k, 3], h * m.S[k, 4], h * m.S[k, 5]
            motor_mul_translator(m.placements[j], tmp, out[j])
    for j in range(m.n):
        if m.types[j] == FREE_FLYER:  # T(p) R(x, y, z, w), the quaternion normalised
            i = m.iq[j]
            x, y, z, w = q[i + 3], q[i + 4], q[i + 5], q[i + 6]
            r = 1.0 / math.sqrt(x * x + y * y + z * z + w * w)
            r0, r1, r2, r3 = rotor((w * r, x * r, y * r, z * r))
            translator_rotor(q[i], q[i + 1], q[i + 2], r0, r1, r2, r3, tmp)
            motor_mul(m.placements[j], tmp, out[j])


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


@inline
def joint_power(m, j, w, tau):
    """``τ_j = -S_jᵀ · W``: the generalised force of a wrench W on the joint's velocity
    coordinates, by the power pairing (eq. 9)."""
    for k in range(m.iv[j], m.iv[j + 1]):
        tau[k] = -dot(m.S[k], w)


@inline
def quaternion_error(m, q):
    """The first free-flyer joint whose quaternion's norm is not within
    ``QUATERNION_TOLERANCE`` of 1, or -1."""
    for j in range(m.types.shape[0]):
        if m.types[j] == FREE_FLYER:
            i = m.iq[j] + 3
            norm = math.sqrt(q[i] ** 2 + q[i + 1] ** 2 + q[i + 2] ** 2 + q[i + 3] ** 2)
            if not abs(norm - 1.0) <= QUATERNION_TOLERANCE:
                return j
    return -1
