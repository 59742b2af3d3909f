"""Forward kinematics: the motor of every joint frame in the world, eq. (5) on trees.

``M^w_j = M^w_λ(j) X_j exp(q_j B_j / 2)``: the product of eq. (5) taken along the path from
the root, each factor the joint's placement times its joint motor (eq. 6).
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import parallel, serial
from ..kernels import joint_motor, motor_mul
from . import _workspace as ws


@serial
def kinematics_core(parents, types, placements, axes, q, Mw, joint, local):
    """World motors of the joint frames into ``Mw`` (n, 8)."""
    for j in range(parents.shape[0]):
        joint_motor(axes[j], types[j] == 1, q[j], joint)
        p = parents[j]
        if p < 0:
            motor_mul(placements[j], joint, Mw[j])
        else:
            motor_mul(placements[j], joint, local)
            motor_mul(Mw[p], local, Mw[j])


@serial
def frames_core(Mw, link_joint, link_placements, out):
    """World motors of link frames: ``M^w_link = M^w_j P_link`` (P: link in its joint frame)."""
    for i in range(link_joint.shape[0]):
        j = link_joint[i]
        if j < 0:
            out[i] = link_placements[i]
        else:
            motor_mul(Mw[j], link_placements[i], out[i])


@serial
def link_motors_single(parents, types, placements, axes, link_joint, link_placements, q):
    n = parents.shape[0]
    Mw = ws.motors(n)
    kinematics_core(parents, types, placements, axes, q, Mw, np.empty(8), np.empty(8))
    out = ws.motors(link_joint.shape[0])
    frames_core(Mw, link_joint, link_placements, out)
    return Mw, out


@parallel
def link_motors_batch(parents, types, placements, axes, link_joint, link_placements, q, threads):
    n = parents.shape[0]
    batch = q.shape[0]
    joints = np.empty((batch, n, 8))
    links = np.empty((batch, link_joint.shape[0], 8))
    starts, stops = ws.chunks(batch, threads)
    for c in prange(starts.shape[0]):
        joint, local = np.empty(8), np.empty(8)
        for b in range(starts[c], stops[c]):
            kinematics_core(parents, types, placements, axes, q[b], joints[b], joint, local)
            frames_core(joints[b], link_joint, link_placements, links[b])
    return joints, links
