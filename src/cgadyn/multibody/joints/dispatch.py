"""The compiled joint functions: a branch on each joint's type code, per joint.

As in Featherstone's ``jcalc``, every function that depends on a joint's type switches on
it here and calls the type's own code (``revolute``, ``prismatic``, ``free_flyer``,
``spherical``, ``planar``, ``translation``, ``helical``); the
algorithms call these and nothing else about joints. A joint j moves its body relative to
the body of its parent λ(j) by the motor (eqs. 5-6)

    M_j = X_j M_J(q_j)

with ``X_j`` its constant placement and ``M_J`` the joint motor of its configuration
``q_j``; its velocity ``v_j`` moves the body with the twist ``S_j v_j``, the columns of
``S_j`` being the joint's motion subspace, constant twists in the joint frame.

The functions read a model unpacked by ``cgadyn.multibody.packed.unpack``: per joint
``types``, ``iq``/``iv`` (the first index of the joint in q and in v, with a final entry
nq/nv, so that joint j's coordinates are ``q[iq[j]:iq[j+1]]``), ``placements`` and ``S``,
the motion subspace of every velocity coordinate as a twist, one row each; ``flat`` says
that every joint is additive (``table.flat``).
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import core, inline
from ...kernels import dot, motor_mul
from ...kernels.halfangle import LIBM_BEYOND, half_angle_sincos
from .free_flyer import (
    FREE_FLYER,
    free_flyer_difference,
    free_flyer_frame_rate,
    free_flyer_integrate,
    free_flyer_motor,
    free_flyer_step,
    free_flyer_transport,
    quaternion_difference,
    quaternion_integrate,
)
from .helical import HELICAL, helical_motor
from .planar import (
    PLANAR,
    planar_difference,
    planar_frame_rate,
    planar_integrate,
    planar_motor,
    planar_step,
    planar_transport,
)
from .prismatic import PRISMATIC, prismatic_motor
from .revolute import REVOLUTE_UNBOUNDED, revolute_motor
from .spherical import SPHERICAL, spherical_motor
from .table import NV, TYPES
from .translation import TRANSLATION, translation_motor

ADDITIVE = tuple(r.additive for r in TYPES)
"""Whether ``q ⊕ v = q + v`` coordinate by coordinate, by type (the records' column, a
constant in compiled code)."""
QUATERNION_AT = tuple(r.quaternion for r in TYPES)
"""The offset of a unit quaternion in a joint's configuration, -1 for none, by type."""
UNIT_LENGTH = tuple(r.unit_length for r in TYPES)
"""How many coordinates that unit block has (4 for a quaternion, 2 for ``(cos θ, sin θ)``),
by type."""
QUATERNION_TOLERANCE = 1e-3
"""A quaternion whose norm differs from 1 by more than this is refused; a smaller difference
is normalised away (as after many steps of integration)."""


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

    Joint axes pass through the joint frame's origin (URDF's convention, checked by
    ``Model``), so a revolute joint's motor is a rotor and a prismatic joint's a
    translator, and the product with ``X_j`` is the cheaper one each allows. Free flyers
    take a second loop: as a third branch of the first, their code more than doubles its
    time. The rarer types (spherical, helical, planar, translation) are ``rare_joint_motors``,
    called rather than inlined.
    """
    for j in range(m.n):
        t = m.types[j]
        k = m.iv[j]
        i = m.iq[j]
        if t <= REVOLUTE_UNBOUNDED:
            revolute_motor(m.placements[j], m.S, k, c[i], s[i], tmp, out[j])
        elif t == PRISMATIC:
            prismatic_motor(m.placements[j], m.S, k, q[i], tmp, out[j])
    rare = False
    for j in range(m.n):
        t = m.types[j]
        if t == FREE_FLYER:
            free_flyer_motor(q, m.iq[j], tmp)
            motor_mul(m.placements[j], tmp, out[j])
        elif t > PRISMATIC:
            rare = True
    if rare:
        rare_joint_motors(m.types, m.iq, m.iv, m.placements, m.S, q, c, s, tmp, out)


@core
def rare_joint_motors(types, iq, iv, placements, S, q, c, s, tmp, out):
    """``out[j] = M_j`` for every spherical, helical, planar and translation joint
    (``joint_motors``). Compiled once and called, not inlined into every recursion: inlined,
    these types' code was a tenth of each recursion's compilation, and the joints are rare."""
    for j in range(types.shape[0]):
        t = types[j]
        if t == SPHERICAL:
            spherical_motor(placements[j], q, iq[j], tmp, out[j])
        elif t == HELICAL:
            i = iq[j]
            helical_motor(placements[j], S, iv[j], q[i], c[i], s[i], tmp, out[j])
        elif t == PLANAR:
            planar_motor(placements[j], q, iq[j], tmp, out[j])
        elif t == TRANSLATION:
            translation_motor(placements[j], q, iq[j], tmp, out[j])


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
def joint_integrate(m, j, q, v, tmp, out):
    """``out_j = q_j ⊕ v_j``, moving joint j's configuration along its velocity for unit
    time: ``q + v`` for a one-dof joint; ``M exp(V / 2)`` for a free flyer (eq. 6), the
    body twist V applied in the body's frame (Pinocchio's ``integrate``), and ``R exp(V / 2)``
    for a spherical joint, V its rotation, and ``M exp(V / 2)`` of SE(2) for a planar joint;
    ``q + v`` coordinate by coordinate for an additive joint. ``tmp``: (3, 8)."""
    i, t = m.iq[j], m.types[j]
    if t == FREE_FLYER:
        joint_twist(m, j, v, tmp[2])  # V = S v, the body twist
        free_flyer_integrate(q, i, tmp, out)
    elif t == SPHERICAL:
        joint_twist(m, j, v, tmp[2])  # V = S v, the rotation in the child's frame
        quaternion_integrate(q, i, 0, tmp, out)
    elif t == PLANAR:
        joint_twist(m, j, v, tmp[2])  # V = S v, the planar twist in the child's frame
        planar_integrate(q, i, tmp, out)
    else:
        k = m.iv[j]
        for c in range(m.iv[j + 1] - k):
            out[i + c] = q[i + c] + v[k + c]


@inline
def joint_step(m, j, q, v, tmp, out):
    """``out_j``: joint j moved by an Euler step's displacement ``v_j`` (the step's velocity
    times dt; K24a): ``joint_integrate``, but a free flyer's or planar joint's origin goes
    straight along the world vector of its linear part, ``p + R v``, while the body turns
    by ``R exp(ω)`` about it. The Euler steps hold that linear velocity in the world through
    the step (``joint_frame_rate``, ``joint_transport``, K24); ``joint_integrate``'s screw
    motion (Pinocchio's ``integrate``) carried the origin on an arc instead, off the line
    by ``|v| |ω| dt / 2`` a unit of time: a free body spinning at 10 rad/s drifted 5 mm a
    second sideways at dt = 1e-3, and a ball rolling at 1 m/s sat 25 µm in the ground.
    ``tmp``: (3, 8)."""
    t, i, k = m.types[j], m.iq[j], m.iv[j]
    if t == FREE_FLYER:
        for c in range(6):  # the rotation alone: S's columns 3..5, ω
            tmp[2, c] = v[k + 3] * m.S[k + 3, c] + v[k + 4] * m.S[k + 4, c] \
                + v[k + 5] * m.S[k + 5, c]
        free_flyer_step(q, i, v[k], v[k + 1], v[k + 2], tmp, out)
    elif t == PLANAR:
        for c in range(6):  # the rotation alone: S's column 2, ω
            tmp[2, c] = v[k + 2] * m.S[k + 2, c]
        planar_step(q, i, v[k], v[k + 1], tmp, out)
    else:
        joint_integrate(m, j, q, v, tmp, out)


@inline
def joint_difference(m, j, q0, q1, tmp, out):
    """``out_j = q1_j ⊖ q0_j``, the velocity that moves q0 to q1 in unit time (the inverse of
    ``joint_integrate``): ``q1 - q0``, wrapped to (-π, π] for an unbounded revolute joint;
    for a free flyer the logarithm of ``~M0 M1`` (``free_flyer_difference``), for a spherical
    joint that of ``~R0 R1`` (its ω), for a planar joint that of SE(2)
    (``planar_difference``); ``q1 - q0`` coordinate by coordinate for another additive
    joint. ``tmp``: (3, 8)."""
    i, k, t = m.iq[j], m.iv[j], m.types[j]
    if t == FREE_FLYER:
        free_flyer_difference(q0, q1, i, k, tmp, out)
    elif t == SPHERICAL:
        quaternion_difference(q0, q1, i, 0, k, tmp, out)
    elif t == PLANAR:
        planar_difference(q0, q1, i, k, tmp, out)
    elif t == REVOLUTE_UNBOUNDED:
        d = q1[i] - q0[i]
        out[k] = math.atan2(math.sin(d), math.cos(d))
    else:
        for c in range(m.iv[j + 1] - k):
            out[k + c] = q1[i + c] - q0[i + c]


@inline
def joint_frame_rate(m, j, v, h, out):
    """``out_j += h ω × v_j`` where joint j's velocity ``v_j`` holds a linear velocity in a
    frame that the joint itself turns (a free flyer's ``[v, ω]``, a planar joint's ``(vx,
    vy, ω)``); nothing for another joint. With ``joint_transport`` after the position
    moves, an Euler step integrates that velocity in the frame it started from, where a
    body that nothing pushes keeps it (K24); read in the turning frame, ``v + h v̇`` would
    grow it by ``h² |ω × v|²`` a step."""
    t, k = m.types[j], m.iv[j]
    if t == FREE_FLYER:
        free_flyer_frame_rate(v, k, h, out)
    elif t == PLANAR:
        planar_frame_rate(v, k, h, out)


@inline
def joint_transport(m, j, w, h, x):
    """``x_j``'s linear velocity moved from the joint's frame at the start of a step into
    its frame after the turn ``exp(h ω̂)`` of the step's velocity ``w`` (ω of ``w_j``):
    ``exp(-h ω̂) v`` (``joint_frame_rate``'s other half, K24); nothing for a joint whose
    velocity holds no linear part in a turning frame."""
    t, k = m.types[j], m.iv[j]
    if t == FREE_FLYER:
        free_flyer_transport(w, k, h, x)
    elif t == PLANAR:
        planar_transport(w, k, h, x)


@inline
def is_additive(t):
    """Whether a joint of type t has ``q ⊕ v = q + v``, coordinate by coordinate (its
    coordinates may be clamped into box limits, drawn uniformly within them)."""
    return ADDITIVE[t]


@inline
def free_root(parent, joint_type):
    """True for a floating joint (one that moves its body by any rigid motion) at the root
    of its tree: ``frame_motors`` with ``free_roots_at_rest`` puts its tree in the root
    body's own frame (M5, D14). It takes numbers, not the model: inlined with the model as
    its argument and called per joint, this test made ``minverse`` 1.5 times slower on the
    panda."""
    return parent < 0 and joint_type == FREE_FLYER


@inline
def quaternion_error(m, q):
    """The first joint whose unit quaternion (``QUATERNION_AT``, ``UNIT_LENGTH`` long: a
    planar joint's ``(cos θ, sin θ)`` too) has a norm not within
    ``QUATERNION_TOLERANCE`` of 1, or -1."""
    if m.flat:
        return -1
    for j in range(m.types.shape[0]):
        o = QUATERNION_AT[m.types[j]]
        if o >= 0:
            i = m.iq[j] + o
            norm2 = 0.0
            for c in range(UNIT_LENGTH[m.types[j]]):
                norm2 += q[i + c] ** 2
            norm = math.sqrt(norm2)
            if not abs(norm - 1.0) <= QUATERNION_TOLERANCE:
                return j
    return -1


def unit_axes(S: np.ndarray, joint_types: np.ndarray) -> np.ndarray:
    """int64 (nv,): for each velocity coordinate of a joint whose motion subspace columns
    ``S[k]`` are each ``±e_i`` (one coefficient ±1, the others 0: an axis along a
    coordinate axis of its frame, as URDFs mostly write them; every column of a spherical,
    translation, planar or free-flyer joint), ``i``; -1 for every coordinate of any other
    joint. Products with such a column read one coefficient, exactly; the packed model
    stores these so that compiled code need not look for them on every call, and reads
    the first coordinate's to know the joint's."""
    S = np.asarray(S, dtype=np.float64)
    out = np.full(len(S), -1, dtype=np.int64)
    k0 = 0
    for t in joint_types:
        k1 = k0 + NV[t]
        axes = []
        for column in S[k0:k1]:
            nonzero = np.flatnonzero(column)
            if len(nonzero) == 1 and abs(column[nonzero[0]]) == 1.0:
                axes.append(nonzero[0])
        if len(axes) == k1 - k0:
            out[k0:k1] = axes
        k0 = k1
    return out
