"""Geometric Jacobian of a link: the world twist of each supporting joint's motion subspace.

Column k of the world-frame Jacobian is the twist of velocity coordinate k moved to the
world, ``M^w_i S_k ~M^w_i`` (eq. 4), for every joint i on the path from the root to the
link, and zero elsewhere; ``J q̇`` is then the link's twist. The link-frame Jacobian moves
each column into the link frame, ``~M^w_L (M^w_i S_k ~M^w_i) M^w_L``, and the
local-world-aligned one only by the link's translation. Columns are written in Pinocchio's
layout, rows ``[v, ω]``.
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import motor_translation, translator_rotor, twist_sandwich, twist_sandwich_rev
from ..kernels.layout import physical
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import link_motor, world_motors
from .status import OK

WORLD, LOCAL, LOCAL_WORLD_ALIGNED = 0, 1, 2


@core
def jacobian_core(m, q, J, link, frame, work):
    """The (6, nv) Jacobian of link ``link`` (an index of the model's links) in ``frame``
    (``WORLD``, ``LOCAL`` or ``LOCAL_WORLD_ALIGNED``)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    Mw, L, F, M, tmp8, tw, tw2, c, s = _workspace(ws.data_pointer(work), m)
    world_motors(m, q, c, s, tmp8, M, Mw)
    link_motor(m, Mw, link, L)  # M^w_L
    if frame == LOCAL_WORLD_ALIGNED:  # the link's translation only
        p1, p2, p3 = motor_translation(L)
        translator_rotor(p1, p2, p3, 1.0, 0.0, 0.0, 0.0, F)
    else:
        for k in range(8):
            F[k] = L[k]
    for i in range(6):
        for k in range(m.nv):
            J[i, k] = 0.0
    j = m.link_joint[link]
    while j >= 0:
        for k in range(m.iv[j], m.iv[j + 1]):
            twist_sandwich(Mw[j], m.S[k], tw)  # M^w_j S_k ~M^w_j
            if frame != WORLD:
                twist_sandwich_rev(F, tw, tw2)  # ~F (·) F
                for i in range(6):
                    tw[i] = tw2[i]
            w1, w2, w3, v1, v2, v3 = physical(tw)
            J[0, k], J[1, k], J[2, k], J[3, k], J[4, k], J[5, k] = v1, v2, v3, w1, w2, w3
        j = m.parents[j]
    return check_result(J)


@inline
def workspace_size(n, nq, nv, nl):
    return 16 * n + 2 * nq + 36


@inline
def _workspace(buf, m):
    """Mw (m.n, 8), L, F, M, tmp8 (8), tw, tw2 (6), the joint motors' scalars c, s (nq)."""
    Mw, o = ws.carve(buf, 0, (m.n, 8))
    L, o = ws.carve(buf, o, (8,))
    F, o = ws.carve(buf, o, (8,))
    M, o = ws.carve(buf, o, (m.n, 8))
    tmp8, o = ws.carve(buf, o, (8,))
    tw, o = ws.carve(buf, o, (6,))
    tw2, o = ws.carve(buf, o, (6,))
    c, o = ws.carve(buf, o, (m.nq,))
    s, o = ws.carve(buf, o, (m.nq,))
    return Mw, L, F, M, tmp8, tw, tw2, c, s
