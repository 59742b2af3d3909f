"""Geometric Jacobian of a link: the world twist of each supporting joint's screw axis.

Column i of the world-frame Jacobian is the joint's unit screw moved to the world,
``M^w_i B_i ~M^w_i`` (eq. 4), for every joint i on the path from the root to the link,
and zero elsewhere; ``J q̇`` is then the link's twist. The link-frame Jacobian moves each
column into the link frame, ``~M^w_L (M^w_i B_i ~M^w_i) M^w_L``, and the
local-world-aligned one only by the link's translation.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import parallel, serial
from ..kernels import motor_translation, translator_rotor, twist_sandwich, twist_sandwich_rev
from . import _workspace as ws
from .kinematics import frames_core, kinematics_core

WORLD, LOCAL, LOCAL_WORLD_ALIGNED = 0, 1, 2


@serial
def jacobian_core(parents, types, placements, axes, link_joint, link_placements, q, link, frame,
                  J, Mw, links, joint, local, tmp, frame_motor):
    """Jacobian columns (n, 6) of link ``link`` into ``J`` (twist coefficients)."""
    kinematics_core(parents, types, placements, axes, q, Mw, joint, local)
    frames_core(Mw, link_joint, link_placements, links)
    J[:, :] = 0.0
    if frame == LOCAL_WORLD_ALIGNED:
        p1, p2, p3 = motor_translation(links[link])
        translator_rotor(p1, p2, p3, 1.0, 0.0, 0.0, 0.0, frame_motor)
    else:
        frame_motor[:] = links[link]
    j = link_joint[link]
    while j >= 0:
        twist_sandwich(Mw[j], axes[j], tmp)
        if frame == WORLD:
            J[j] = tmp
        else:
            twist_sandwich_rev(frame_motor, tmp, J[j])
        j = parents[j]


@serial
def jacobian_single(parents, types, placements, axes, link_joint, link_placements, q, link,
                    frame):
    n = parents.shape[0]
    J = ws.bivectors(n)
    jacobian_core(parents, types, placements, axes, link_joint, link_placements, q, link, frame,
                  J, ws.motors(n), ws.motors(link_joint.shape[0]), np.empty(8), np.empty(8),
                  np.empty(6), np.empty(8))
    return J


@parallel
def jacobian_batch(parents, types, placements, axes, link_joint, link_placements, q, link, frame,
                threads):
    n = parents.shape[0]
    batch = q.shape[0]
    J = np.empty((batch, n, 6))
    starts, stops = ws.chunks(batch, threads)
    for c in prange(starts.shape[0]):
        Mw, links = ws.motors(n), ws.motors(link_joint.shape[0])
        joint, local, tmp, fm = np.empty(8), np.empty(8), np.empty(6), np.empty(8)
        for b in range(starts[c], stops[c]):
            jacobian_core(parents, types, placements, axes, link_joint, link_placements, q[b],
                          link, frame, J[b], Mw, links, joint, local, tmp, fm)
    return J
