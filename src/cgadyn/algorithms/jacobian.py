"""Geometric Jacobian of a link: the world twist of each supporting joint's motion subspace.

Column k of the world-frame Jacobian is the twist of velocity coordinate k moved to the
world, ``M^w_i S_k ~M^w_i`` (eq. 4), for every joint i on the path from the root to the
link, and zero elsewhere; ``J q̇`` is then the link's twist. The link-frame Jacobian moves
each column into the link frame, ``~M^w_L (M^w_i S_k ~M^w_i) M^w_L``, and the
local-world-aligned one only by the link's translation. Columns are written in Pinocchio's
layout, rows ``[v, ω]``.
"""

from __future__ import annotations

from .._jit import core
from ..kernels import motor_translation, translator_rotor, twist_sandwich, twist_sandwich_rev
from ..kernels.layout import physical
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import link_motor, world_motors
from .status import OK
from .work.jacobian import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Mw": ("n", 8),  # the world motors
    "L": (8,),
    "F": (8,),
    "M": ("n", 8),  # the joint motors
    "tmp8": (8,),
    "tw": (6,),
    "tw2": (6,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


WORLD, LOCAL, LOCAL_WORLD_ALIGNED = 0, 1, 2


@core
def jacobian_core(m, q, J, link, frame, work):
    """The (6, nv) Jacobian of link ``link`` (an index of the model's links) in ``frame``
    (``WORLD``, ``LOCAL`` or ``LOCAL_WORLD_ALIGNED``)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    Mw, L, F, M, tmp8, tw, tw2, c, s = k_.Mw, k_.L, k_.F, k_.M, k_.tmp8, k_.tw, k_.tw2, k_.c, k_.s
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
