"""Joint-space mass matrix by composite rigid bodies (CRBA), in CGA.

Backward pass (j = n..1): the composite inertia of the subtree at j is carried to the
parent with the motor transformation of eq. (16), ``I^c_λ += M_j * I^c_j``; composite
inertias are rigid, so eq. (16)'s closed form for rigid bodies applies
(``rigid_inertia_transform``). Then for each joint j the wrench ``F = I^c_j[B_j]``
(eq. 15) is moved down the path to the root (``F ← M_i F ~M_i``), and each supporting
joint i reads its entry by the power pairing ``H_ij = H_ji = -B_i · F`` (eq. 9). The full
symmetric matrix is returned.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..kernels import (
    adjoint_apply,
    dot,
    inertia_apply,
    joint_motor,
    motor_mul,
    wrench_adjoint,
)
from ..kernels.rigid import rigid_inertia_transform
from ..multibody.packed import njoints, unpack
from . import _workspace as ws


@njit(cache=True, nogil=True, fastmath={"contract"})
def crba_core(packed, q, H, work):
    """One sample into ``H``; ``work`` a buffer of ``workspace_size(n)`` floats (a pointer
    or an array)."""
    parents, types, placements, axes, inertias, _ = unpack(packed)
    n = parents.shape[0]
    Ad, Ic, F, joint, M, It = _workspace(ws.pointer(work), n)
    for j in range(n):
        joint_motor(axes[j], types[j] == 1, q[j], joint)
        motor_mul(placements[j], joint, M[j])  # M_j = X_j exp(q_j B_j / 2)
        wrench_adjoint(M[j], Ad[j])  # M_j (·) ~M_j as a matrix
        for k in range(6):
            for l in range(6):
                Ic[j, k, l] = inertias[j, k, l]
    for j in range(n - 1, -1, -1):
        p = parents[j]
        if p >= 0:
            rigid_inertia_transform(M[j], Ic[j], It)  # M_j * I^c_j
            for k in range(6):
                for l in range(6):
                    Ic[p, k, l] += It[k, l]
    for i in range(n):  # entries of joints on different branches stay zero
        for j in range(n):
            H[i, j] = 0.0
    for j in range(n):
        inertia_apply(Ic[j], axes[j], F)  # F = I^c_j[B_j]
        H[j, j] = -dot(axes[j], F)
        i = j
        while parents[i] >= 0:
            adjoint_apply(Ad[i], F, F)  # F <- M_i F ~M_i (kernels may write over their input)
            i = parents[i]
            H[i, j] = -dot(axes[i], F)
            H[j, i] = H[i, j]


@njit(cache=True, nogil=True)
def workspace_size(n):
    return 80 * n + 50


@njit(cache=True, nogil=True, inline="always")
def _workspace(buf, n):
    """Ad, Ic (n,6,6), F (6), joint (8), M (n,8), It (6,6), carved from ``buf``."""
    Ad, o = ws.carve(buf, 0, (n, 6, 6))
    Ic, o = ws.carve(buf, o, (n, 6, 6))
    F, o = ws.carve(buf, o, (6,))
    joint, o = ws.carve(buf, o, (8,))
    M, o = ws.carve(buf, o, (n, 8))
    It, o = ws.carve(buf, o, (6, 6))
    return Ad, Ic, F, joint, M, It


@njit(cache=True)
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


@njit(cache=True, nogil=True, parallel=True)
def crba_batch(packed, q, threads):
    """(B, n) samples in parallel, one heap workspace per thread."""
    n = njoints(packed)
    batch = q.shape[0]
    H = np.empty((batch, n, n))
    starts, stops = ws.chunks(batch, threads)
    for c in prange(starts.shape[0]):
        work = np.empty(workspace_size(n))
        for b in range(starts[c], stops[c]):
            crba_core(packed, q[b], H[b], work)
    return H
