"""Articulated-body forward dynamics (ABA) in CGA: Algorithms 1 and 3 of the CGA paper.

On trees, with ``λ(j) = parents[j]``. First forward pass (j = 1..n)::

    M_j  = X_j exp(q_j B_j / 2)
    V_j  = ~M_j V_λ M_j + q̇_j B_j
    c_j  = q̇_j (V_j × B_j)                      velocity-product acceleration
    Î_j  = I_j                                   articulated-body inertia, Algorithm 1
    Ŵ_j  = V_j × I_j[V_j] - W_ext,j              bias wrench

Backward pass (j = n..1), Algorithm 1 folded into Algorithm 3::

    W_Bj = Î_j[B_j]                             the paper's W_B, before the factor Ω
    Ω_j  = (-B_j · W_Bj)^-1
    τ̂_j  = τ_j + B_j · Ŵ_j
    Ĩ_j  = {Î_j^{e_k} - Ω_j (W_Bj)_k W_Bj}      Algorithm 1, second line
    W̄_j  = Ŵ_j + Ĩ_j[c_j] + Ω_j τ̂_j W_Bj
    Î_λ += M_j * Ĩ_j                            eq. (16)
    Ŵ_λ += M_j W̄_j ~M_j

Second forward pass (j = 1..n), with V̇_0 = -g::

    V̄_j  = ~M_j V̇_λ M_j + c_j
    q̈_j  = Ω_j (τ̂_j + V̄_j · W_Bj)
    V̇_j  = V̄_j + q̈_j B_j

As in ``rnea``, each joint's sandwich is expanded once into its matrix ``Ad_j``
(``M_j W ~M_j = Ad_j W``, ``~M_j V M_j = Ad_jᵀ V``, ``M_j * I = Ad_j I Ad_jᵀ``).
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
    inertia_congruence_add,
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
def aba_core(packed, q, qd, tau, f_ext, qdd, work):
    """One sample of Algorithm 3 into ``qdd``; ``f_ext`` (n, 6) or None; ``work`` a buffer
    of ``workspace_size(n)`` floats (on the caller's stack or heap)."""
    parents, types, placements, axes, inertias, gravity = unpack(packed)
    n = parents.shape[0]
    Ad, V, C, Wh, WB, Ih, Omega, u, tmp, tmp2, joint, It, M, c, s = _workspace(
        ws.data_pointer(work), n)
    joint_scalars(types, q, c, s)  # the scalars of every joint motor (eq. 6)
    for j in range(n):
        p = parents[j]
        screw_motor(axes[j], c[j], s[j], joint)  # exp(q_j B_j / 2) = c_j + s_j B_j
        joint_frame_motor(placements[j], joint, types[j] == 1, M)  # M_j = X_j exp(q_j B_j / 2)
        wrench_adjoint(M, Ad[j])  # M_j (·) ~M_j as a matrix
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
        else:
            adjoint_apply_transpose(Ad[j], V[p], V[j])  # ~M_j V_λ M_j
        for k in range(6):
            V[j, k] += qd[j] * axes[j, k]  # V_j = ~M_j V_λ M_j + q̇_j B_j
        twist_cross(V[j], axes[j], C[j])
        for k in range(6):
            C[j, k] *= qd[j]  # c_j = q̇_j (V_j × B_j)
        for k in range(6):  # Î_j = I_j
            for l in range(6):
                Ih[j, k, l] = inertias[j, k, l]
        inertia_apply(inertias[j], V[j], tmp)
        twist_cross_wrench(V[j], tmp, Wh[j])  # Ŵ_j = V_j × I_j[V_j]
        if f_ext is not None:
            for k in range(6):
                Wh[j, k] -= f_ext[j, k]
    for j in range(n - 1, -1, -1):
        inertia_apply(Ih[j], axes[j], WB[j])  # W_Bj = Î_j[B_j]
        Omega[j] = -1.0 / dot(axes[j], WB[j])  # Ω_j = (-B_j · W_Bj)^-1
        u[j] = tau[j] + dot(axes[j], Wh[j])  # τ̂_j = τ_j + B_j · Ŵ_j
        p = parents[j]
        if p >= 0:
            for k in range(6):
                w = Omega[j] * WB[j, k]
                for l in range(k, 6):  # Ĩ_j = {Î_j^{e_k} - Ω_j (W_Bj)_k W_Bj}, symmetric
                    It[k, l] = It[l, k] = Ih[j, k, l] - w * WB[j, l]
            inertia_apply(It, C[j], tmp)
            for k in range(6):  # W̄_j = Ŵ_j + Ĩ_j[c_j] + Ω_j τ̂_j W_Bj
                tmp[k] += Wh[j, k] + Omega[j] * u[j] * WB[j, k]
            adjoint_apply(Ad[j], tmp, tmp2)  # M_j W̄_j ~M_j
            inertia_congruence_add(Ad[j], It, Ih[p])  # Î_λ += M_j * Ĩ_j, eq. (16)
            for k in range(6):
                Wh[p, k] += tmp2[k]
    for j in range(n):  # V now holds the accelerations V̇_j, V̇_0 = -g
        p = parents[j]
        if p < 0:
            adjoint_apply_transpose(Ad[j], gravity, tmp)
        else:
            adjoint_apply_transpose(Ad[j], V[p], tmp)
        for k in range(6):
            tmp[k] += C[j, k]  # V̄_j = ~M_j V̇_λ M_j + c_j
        qdd[j] = Omega[j] * (u[j] + dot(tmp, WB[j]))  # q̈_j = Ω_j (τ̂_j + V̄_j · W_Bj)
        for k in range(6):
            V[j, k] = tmp[k] + qdd[j] * axes[j, k]  # V̇_j = V̄_j + q̈_j B_j


@serial
def workspace_size(n):
    return 100 * n + 64


@inline
def _workspace(buf, n):
    """Ad, Ih (n,6,6), V, C, Wh, WB (n,6), Ω, u (n), tmp, tmp2 (6), joint, M (8), It (6,6),
    the joint motors' scalars c, s (n)."""
    Ad, o = ws.carve(buf, 0, (n, 6, 6))
    V, o = ws.carve(buf, o, (n, 6))
    C, o = ws.carve(buf, o, (n, 6))
    Wh, o = ws.carve(buf, o, (n, 6))
    WB, o = ws.carve(buf, o, (n, 6))
    Ih, o = ws.carve(buf, o, (n, 6, 6))
    Omega, o = ws.carve(buf, o, (n,))
    u, o = ws.carve(buf, o, (n,))
    tmp, o = ws.carve(buf, o, (6,))
    tmp2, o = ws.carve(buf, o, (6,))
    joint, o = ws.carve(buf, o, (8,))
    It, o = ws.carve(buf, o, (6, 6))
    M, o = ws.carve(buf, o, (8,))
    c, o = ws.carve(buf, o, (n,))
    s, o = ws.carve(buf, o, (n,))
    return Ad, V, C, Wh, WB, Ih, Omega, u, tmp, tmp2, joint, It, M, c, s


@serial
def aba_single(packed, q, qd, tau, qdd):
    """One sample into ``qdd`` (n,), without external forces."""
    aba_single_ext(packed, q, qd, tau, None, qdd)


@serial
def aba_single_ext(packed, q, qd, tau, f_ext, qdd):
    """One sample into ``qdd`` (n,); ``f_ext`` (n, 6) or None. Checks the lengths and
    finiteness of the inputs; the workspace lives on this call's stack
    (on the heap for very large models)."""
    n = njoints(packed)
    ws.require_sample(n, q, qd, tau, qdd)
    size = workspace_size(n)
    if size <= ws.STACK_FLOATS:
        aba_core(packed, q, qd, tau, f_ext, qdd, ws.stack_buffer(size))
    else:  # a long chain: on the heap, away from small thread stacks
        aba_core(packed, q, qd, tau, f_ext, qdd, np.empty(size))


@parallel
def aba_batch(packed, q, qd, tau, f_ext, threads):
    """(B, n) samples in parallel, in chunks of at least ``MIN_CHUNK`` samples with one heap
    workspace each; ``f_ext`` (B, n, 6) or None. Checks the shapes and finiteness of the
    inputs."""
    ws.require_rows(njoints(packed), (q, qd, tau))
    qdd = np.empty(q.shape)
    starts, stops = ws.chunks(q.shape[0], threads)
    for c in prange(starts.shape[0]):
        work = np.empty(workspace_size(q.shape[1]))
        for b in range(starts[c], stops[c]):
            aba_core(packed, q[b], qd[b], tau[b], ws.row(f_ext, b), qdd[b], work)
    return qdd
