"""Recursive inverse dynamics (RNEA) in CGA: Algorithm 2 of the CGA paper, on trees.

Every body j has the frame of its joint; ``λ(j) = parents[j]`` is its parent (-1: the world).
Forward pass (j = 1..n)::

    M_j  = X_j exp(q_j B_j / 2)                         pose of j in λ(j) (eqs. 5-6)
    V_j  = ~M_j V_λ M_j + q̇_j B_j                       twist
    V̇_j  = ~M_j V̇_λ M_j + q̇_j (V_j × B_j) + q̈_j B_j     its derivative, eqs. (10-11)
    W_j  = I_j[V̇_j] + V_j × I_j[V_j] - W_ext,j         eq. (15)

Backward pass (j = n..1)::

    τ_j  = -B_j · W_j                                    power pairing, eq. (9)
    W_λ += M_j W_j ~M_j

Gravity enters as the base acceleration ``V̇_0 = -g`` (Featherstone's fictitious base
acceleration). The paper writes the bracket as ``B_j × V_j`` and the gyroscopic term with
a minus sign: with the sign conventions of ``cgadyn.cga.conventions`` (where ``×`` is the
Lie bracket of twists) these are the same quantities.

Each joint's sandwich ``M_j (·) ~M_j`` is applied three times, so it is expanded once into
its matrix ``Ad_j`` (``wrench_adjoint``, generated from eq. 4): ``M_j W ~M_j = Ad_j W`` and,
by the invariance of the power pairing, ``~M_j V M_j = Ad_jᵀ V``.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import core, inline, parallel, serial
from ..kernels import (
    adjoint_apply,
    adjoint_apply_transpose,
    dot,
    inertia_apply,
    joint_frame_motor,
    joint_scalars,
    screw_motor,
    twist_cross,
    twist_cross_wrench,
    wrench_adjoint,
)
from ..multibody.packed import njoints, unpack
from . import _workspace as ws


@core
def rnea_core(packed, q, qd, qdd, f_ext, tau, work):
    """One sample of Algorithm 2 into ``tau``; ``f_ext`` (n, 6) or None; ``work`` a buffer
    of ``workspace_size(n)`` floats (on the caller's stack or heap)."""
    parents, types, placements, axes, inertias, gravity = unpack(packed)
    n = parents.shape[0]
    Ad, V, A, W, tmp, joint, M, c, s = _workspace(ws.data_pointer(work), n)
    joint_scalars(types, q, c, s)  # the scalars of every joint motor (eq. 6)
    for j in range(n):
        p = parents[j]
        screw_motor(axes[j], c[j], s[j], joint)  # exp(q_j B_j / 2) = c_j + s_j B_j
        joint_frame_motor(placements[j], joint, types[j] == 1, M)  # M_j = X_j exp(q_j B_j / 2)
        wrench_adjoint(M, Ad[j])  # M_j (·) ~M_j as a matrix
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
            adjoint_apply_transpose(Ad[j], gravity, A[j])  # V̇_0 = -g
        else:
            adjoint_apply_transpose(Ad[j], V[p], V[j])  # ~M_j V_λ M_j
            adjoint_apply_transpose(Ad[j], A[p], A[j])  # ~M_j V̇_λ M_j
        for k in range(6):
            V[j, k] += qd[j] * axes[j, k]  # V_j = ~M_j V_λ M_j + q̇_j B_j
        twist_cross(V[j], axes[j], tmp)
        for k in range(6):  # V̇_j = ~M_j V̇_λ M_j + q̇_j (V_j × B_j) + q̈_j B_j
            A[j, k] += qd[j] * tmp[k] + qdd[j] * axes[j, k]
        inertia_apply(inertias[j], A[j], W[j])  # I_j[V̇_j]
        inertia_apply(inertias[j], V[j], tmp)
        twist_cross_wrench(V[j], tmp, tmp)  # V_j × I_j[V_j]
        for k in range(6):
            W[j, k] += tmp[k]
        if f_ext is not None:
            for k in range(6):
                W[j, k] -= f_ext[j, k]
    for j in range(n - 1, -1, -1):
        tau[j] = -dot(axes[j], W[j])  # τ_j = -B_j · W_j
        p = parents[j]
        if p >= 0:
            adjoint_apply(Ad[j], W[j], tmp)  # W_λ += M_j W_j ~M_j
            for k in range(6):
                W[p, k] += tmp[k]


@serial
def workspace_size(n):
    return 56 * n + 22


@inline
def _workspace(buf, n):
    """Ad (n,6,6), V, A, W (n,6), tmp (6), joint, M (8), the joint motors' scalars c, s (n),
    carved from ``buf``."""
    Ad, o = ws.carve(buf, 0, (n, 6, 6))
    V, o = ws.carve(buf, o, (n, 6))
    A, o = ws.carve(buf, o, (n, 6))
    W, o = ws.carve(buf, o, (n, 6))
    tmp, o = ws.carve(buf, o, (6,))
    joint, o = ws.carve(buf, o, (8,))
    M, o = ws.carve(buf, o, (8,))
    c, o = ws.carve(buf, o, (n,))
    s, o = ws.carve(buf, o, (n,))
    return Ad, V, A, W, tmp, joint, M, c, s


@serial
def rnea_single(packed, q, qd, qdd, tau):
    """One sample into ``tau`` (n,), without external forces."""
    rnea_single_ext(packed, q, qd, qdd, None, tau)


@serial
def rnea_single_ext(packed, q, qd, qdd, f_ext, tau):
    """One sample into ``tau`` (n,); ``f_ext`` (n, 6) or None. Checks the lengths and
    finiteness of the inputs; the workspace lives on this call's stack
    (on the heap for very large models)."""
    n = njoints(packed)
    ws.require_sample(n, q, qd, qdd, tau)
    size = workspace_size(n)
    if size <= ws.STACK_FLOATS:
        rnea_core(packed, q, qd, qdd, f_ext, tau, ws.stack_buffer(size))
    else:  # a long chain: on the heap, away from small thread stacks
        rnea_core(packed, q, qd, qdd, f_ext, tau, np.empty(size))


@parallel
def rnea_batch(packed, q, qd, qdd, f_ext, threads):
    """(B, n) samples in parallel, in chunks of at least ``MIN_CHUNK`` samples with one heap
    workspace each; ``f_ext`` (B, n, 6) or None. Checks the shapes and finiteness of the
    inputs."""
    ws.require_rows(njoints(packed), (q, qd, qdd))
    tau = np.empty(q.shape)
    starts, stops = ws.chunks(q.shape[0], threads)
    for c in prange(starts.shape[0]):
        work = np.empty(workspace_size(q.shape[1]))
        for b in range(starts[c], stops[c]):
            rnea_core(packed, q[b], qd[b], qdd[b], ws.row(f_ext, b), tau[b], work)
    return tau
