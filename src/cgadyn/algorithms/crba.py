"""Joint-space mass matrix by composite rigid bodies (CRBA), in CGA, in world coordinates.

Forward pass: the world motor of each body ``M^w_j = M^w_λ M_j``; from its rotation and
translation, built once (``rigid_axis_transform``), the joint axis in world coordinates
``S_j = M^w_j B_j ~M^w_j`` (eq. 4) and the body's inertia moved to the world with eq. (16)'s
closed form for rigid bodies, kept as its ten parameters (mass, first moment, rotational
inertia). Backward pass (j = n..1): in one frame the composite inertias are plain sums,
``I^c_λ += I^c_j``, ten numbers each. Once ``I^c_j`` is complete (all its descendants are
added), the wrench ``F = I^c_j[S_j]`` (eq. 15) is already in the frame of every supporting
joint i, which reads its entry by the power pairing ``H_ij = H_ji = -S_i · F`` (eq. 9): 6
multiplications per pair, where moving F down the path took 27 more. The pairing is
invariant under motors, so the entries equal those of local frames. The full symmetric
matrix is returned.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import core, inline, parallel, serial
from ..kernels import dot, joint_frame_motor, joint_scalars, motor_mul, screw_motor
from ..kernels.rigid import rigid_apply, rigid_axis_transform
from ..multibody.packed import njoints, unpack
from . import _workspace as ws


@core
def crba_core(packed, q, H, work):
    """One sample into ``H``; ``work`` a buffer of ``workspace_size(n)`` floats (on the
    caller's stack or heap)."""
    parents, types, placements, axes, inertias, _ = unpack(packed)
    n = parents.shape[0]
    Ic, S, Mw, joint, M, c, s = _workspace(ws.data_pointer(work), n)
    joint_scalars(types, q, c, s)  # exp(q_j B_j / 2) = c_j + s_j B_j for all joints
    for j in range(n):
        p = parents[j]
        screw_motor(axes[j], c[j], s[j], joint)
        if p >= 0:
            joint_frame_motor(placements[j], joint, types[j] == 1, M)  # M_j = X_j exp(q_j B_j/2)
            motor_mul(Mw[p], M, Mw[j])  # M^w_j = M^w_λ M_j
        else:
            joint_frame_motor(placements[j], joint, types[j] == 1, Mw[j])  # M^w_j = M_j, root
        rigid_axis_transform(Mw[j], axes[j], inertias[j], S[j], Ic[j])  # S_j, M^w_j * I_j
    for i in range(n):  # entries of joints on different branches stay zero
        for j in range(n):
            H[i, j] = 0.0
    for j in range(n - 1, -1, -1):  # children come after their parents
        F = rigid_apply(Ic[j], S[j])  # F = I^c_j[S_j], I^c_j complete
        i = j
        while i >= 0:  # j itself, then every joint supporting it
            H[i, j] = H[j, i] = -dot(S[i], F)  # power of F along the axis S_i
            i = parents[i]
        p = parents[j]
        if p >= 0:
            for k in range(10):
                Ic[p, k] += Ic[j, k]  # I^c_λ += I^c_j, ten parameters in world coordinates


@serial
def workspace_size(n):
    return 26 * n + 16


@inline
def _workspace(buf, n):
    """Ic (n,10) (ten parameters of rigid inertias), S (n,6), Mw (n,8), joint (8), M (8),
    the joint motors' scalars c (n) and s (n), carved from ``buf``."""
    Ic, o = ws.carve(buf, 0, (n, 10))
    S, o = ws.carve(buf, o, (n, 6))
    Mw, o = ws.carve(buf, o, (n, 8))
    joint, o = ws.carve(buf, o, (8,))
    M, o = ws.carve(buf, o, (8,))
    c, o = ws.carve(buf, o, (n,))
    s, o = ws.carve(buf, o, (n,))
    return Ic, S, Mw, joint, M, c, s


@serial
def crba_single(packed, q, H):
    """One sample into ``H`` (n, n); checks the length and finiteness of ``q``; the
    workspace lives on this call's stack (on the heap for very large models)."""
    n = njoints(packed)
    ws.require_sample(n, q, q, q, H)
    size = workspace_size(n)
    if size <= ws.STACK_FLOATS:
        crba_core(packed, q, H, ws.stack_buffer(size))
    else:  # a long chain: on the heap, away from small thread stacks
        crba_core(packed, q, H, np.empty(size))


@parallel
def crba_batch(packed, q, threads):
    """(B, n) samples in parallel, in chunks of at least ``MIN_CHUNK`` samples with one heap
    workspace each. Checks the shapes and finiteness of the inputs."""
    ws.require_rows(njoints(packed), (q,))
    H = np.empty((q.shape[0], q.shape[1], q.shape[1]))
    starts, stops = ws.chunks(q.shape[0], threads)
    for c in prange(starts.shape[0]):
        work = np.empty(workspace_size(q.shape[1]))
        for b in range(starts[c], stops[c]):
            crba_core(packed, q[b], H[b], work)
    return H
