"""Articulated-body forward dynamics (ABA) in CGA: Algorithms 1 and 3 of the CGA paper.

On trees, with ``λ(j) = parents[j]``; ``S_j`` the joint's motion subspace (one screw
``B_j`` for a one-dof joint, six unit twists for a free flyer: ``multibody.joints``).
First forward pass (j = 1..n)::

    M_j  = X_j M_J(q_j)
    V_j  = ~M_j V_λ M_j + S_j q̇_j
    c_j  = V_j × S_j q̇_j                         velocity-product acceleration
    Î_j  = I_j                                   articulated-body inertia, Algorithm 1
    Ŵ_j  = V_j × I_j[V_j] - W_ext,j              bias wrench

Backward pass (j = n..1), Algorithm 1 folded into Algorithm 3::

    U_j  = Î_j[S_j]                              the paper's W_B, one wrench per column
    D_j  = -S_jᵀ · U_j                           Ω_j = D_j⁻¹ (a number for one dof)
    τ̂_j  = τ_j + S_jᵀ · Ŵ_j
    G_j  = U_j D_j⁻¹,   ũ_j = D_j⁻¹ τ̂_j
    Ĩ_j  = Î_j - U_j G_jᵀ                        Algorithm 1, second line
    W̄_j  = Ŵ_j + Ĩ_j[c_j] + U_j ũ_j
    Î_λ += M_j * Ĩ_j                             eq. (16)
    Ŵ_λ += M_j W̄_j ~M_j

Second forward pass (j = 1..n), with V̇_0 = -g::

    V̄_j  = ~M_j V̇_λ M_j + c_j
    q̈_j  = ũ_j + G_jᵀ · V̄_j                      = Ω_j (τ̂_j + V̄_j · W_Bj) for one dof
    V̇_j  = V̄_j + S_j q̈_j

A joint whose columns S_k are each ±e_i (an axis along one of its frame's axes, as URDFs
mostly write them, and every column of a spherical, planar, translation or free-flyer
joint: the packed model's ``unit_axis``, from ``joints.unit_axes``) takes U_j, τ̂_j (and
D_j of one dof) from coefficient i of Î_j and Ŵ_j, and adds S_j q̈_j to coefficient i of
V̇_j: the same numbers without the products.

At a joint of three such columns without rotor inertia (spherical, planar, translation),
Ĩ_j is zero on the joint's own coefficients and is formed, applied and moved to the parent
on the other three alone (``pivots.outside``, ``schur_block``, ``schur_apply``,
``outside_congruence_add``).

A one-dof joint never forms Ĩ_j (a 6x6 matrix stored per joint and loaded back, work that
the parent's update can skip):
``inertia_congruence_downdate_add`` moves ``Î_j - U_j G_jᵀ`` into the parent's inertia,
forming it as ``Î_j`` is loaded, and the bias wrench takes
``Ĩ_j[c_j] = Î_j[c_j] + U_j (G_jᵀ · c_j)``::

    W̄_j  = Ŵ_j + Î_j[c_j] + U_j (ũ_j + G_jᵀ · c_j)
    Î_λ += M_j * (Î_j - U_j G_jᵀ)                eq. (16)

the same numbers up to rounding. The body inertia in Ŵ_j is applied from its ten
parameters (``kernels.rigid``: a body's inertia is rigid).

A D_j that is not positive definite (a subtree without mass, or without inertia along the
joint's motion) is a fault at joint j. As in ``rnea``, each joint's sandwich is expanded
once into its matrix ``Ad_j`` (``M_j W ~M_j = Ad_j W``, ``~M_j V M_j = Ad_jᵀ V``,
``M_j * I = Ad_j I Ad_jᵀ``).
"""

from __future__ import annotations

import math

from .._jit import core
from ..kernels import (
    adjoint_apply,
    adjoint_apply_transpose,
    dot,
    inertia_apply,
    inertia_congruence_add,
    inertia_congruence_downdate_add,
    twist_cross,
    twist_cross_wrench,
    wrench_adjoint,
)
from ..kernels.rigid import rigid_apply, rigid_parameters
from ..multibody.joints import joint_motors, joint_scalars, joint_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .pivots import (
    articulated_inertia,
    joint_pivot,
    outside,
    outside_congruence_add,
    pivot_gain,
    schur_apply,
    schur_block,
    unit_pivot,
)
from .status import OK, SINGULAR, fault
from .work.aba import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Ad": ("n", 6, 6),  # M_j (·) ~M_j as a matrix, per body
    "V": ("n", 6),  # the bodies' twists
    "C": ("n", 6),  # the bias twists c_j
    "Wh": ("n", 6),  # the bias wrenches
    "Ih": ("n", 6, 6),  # the articulated inertias Î_j
    "U": ("nv", 6),  # U_j = Î_j[S_j]
    "G": ("nv", 6),  # D_j⁻¹ U_j
    "ut": ("nv",),  # ũ
    "u": ("nv",),  # τ̂
    "tmp": (6,),
    "tmp2": (6,),
    "It": (6, 6),  # Ĩ_j
    "D": (6, 6),
    "Dinv": (6, 6),
    "M": ("n", 8),  # the joint motors
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


@core
def aba_core(m, q, v, tau, f, qdd, work):
    """One sample of Algorithm 3 into ``qdd`` (nv); ``f`` the external wrenches (n, 6), or
    (0, 6) for none; ``work`` ``workspace_size`` floats. Returns a status."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    n, S = m.n, m.S
    k_ = workspace(ws.data_pointer(work), m)
    Ad = k_.Ad
    V = k_.V
    C = k_.C
    Wh = k_.Wh
    Ih = k_.Ih
    U = k_.U
    G = k_.G
    ut = k_.ut
    u = k_.u
    tmp = k_.tmp
    tmp2 = k_.tmp2
    It = k_.It
    D = k_.D
    Dinv = k_.Dinv
    M = k_.M
    tmp8 = k_.tmp8
    c = k_.c
    s = k_.s
    joint_scalars(q, c, s)  # the scalars of every revolute joint motor (eq. 6)
    joint_motors(m, q, c, s, tmp8, M)  # M_j = X_j M_J(q_j)
    for j in range(n):
        p = m.parents[j]
        wrench_adjoint(M[j], Ad[j])  # M_j (·) ~M_j as a matrix
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
        else:
            adjoint_apply_transpose(Ad[j], V[p], V[j])  # ~M_j V_λ M_j
        joint_twist(m, j, v, tmp)  # S_j q̇_j
        for k in range(6):
            V[j, k] += tmp[k]  # V_j = ~M_j V_λ M_j + S_j q̇_j
        twist_cross(V[j], tmp, C[j])  # c_j = V_j × S_j q̇_j
        for k in range(6):  # Î_j = I_j
            for l in range(6):
                Ih[j, k, l] = m.inertias[j, k, l]
        tmp[0], tmp[1], tmp[2], tmp[3], tmp[4], tmp[5] = rigid_apply(
            rigid_parameters(m.inertias[j]), V[j])  # I_j[V_j], I_j rigid
        twist_cross_wrench(V[j], tmp, Wh[j])  # Ŵ_j = V_j × I_j[V_j]
        if f.shape[0] > 0:
            for k in range(6):
                Wh[j, k] -= f[j, k]
    for j in range(n - 1, -1, -1):
        k0, k1 = m.iv[j], m.iv[j + 1]
        axis = m.unit_axis[k0]
        if axis >= 0:  # S_j = ±e_i: the products below read coefficient i (``dot`` is -Σ)
            for k in range(k0, k1):  # each column of a joint of several alike
                i = m.unit_axis[k]
                sign = S[k, i]
                for l in range(6):
                    U[k, l] = sign * Ih[j, l, i]  # U_j = Î_j[S_j]
                u[k] = tau[k] - sign * Wh[j, i]  # τ̂_j = τ_j + S_jᵀ · Ŵ_j (· is -Σ)
            d = S[k0, axis] * U[k0, axis]
        else:
            for k in range(k0, k1):
                inertia_apply(Ih[j], S[k], U[k])  # U_j = Î_j[S_j]
                u[k] = tau[k] + dot(S[k], Wh[j])  # τ̂_j = τ_j + S_jᵀ · Ŵ_j
            d = -dot(S[k0], U[k0])
        d += m.armature[k0]  # D_j = -S_jᵀ · U_j + the rotor's inertia
        if k1 - k0 == 1:  # one dof: Ω_j = D_j⁻¹ = (-B_j · W_Bj)⁻¹
            omega = 1.0 / d
            if not (d > 0.0 and math.isfinite(omega)):
                return fault(SINGULAR, j)
            for l in range(6):
                G[k0, l] = omega * U[k0, l]  # G_j = U_j Ω_j
            ut[k0] = omega * u[k0]  # ũ_j = Ω_j τ̂_j
        else:  # several: D_j⁻¹ of the symmetric positive definite D_j
            if not (unit_pivot(m.armature, m.unit_axis, S, U, k0, k1, D, Dinv) if axis >= 0
                    else joint_pivot(m.armature, S, U, k0, k1, D, Dinv)):  # D_j, D_j⁻¹
                return fault(SINGULAR, j)
            pivot_gain(Dinv, U, k0, k1, G)  # G_j = U_j D_j⁻¹
            for a in range(k0, k1):
                ut[a] = 0.0
                for b in range(k0, k1):
                    ut[a] += Dinv[a - k0, b - k0] * u[b]  # ũ_j = D_j⁻¹ τ̂_j
        p = m.parents[j]
        if p < 0:
            continue
        if k1 - k0 == 1:  # Ĩ_j = Î_j - U_j G_jᵀ only inside the congruence
            inertia_apply(Ih[j], C[j], tmp)  # Î_j[c_j]
            w = ut[k0] + dot(C[j], G[k0])  # ũ_j + G_jᵀ · c_j
            for k in range(6):  # W̄_j = Ŵ_j + Î_j[c_j] + U_j (ũ_j + G_jᵀ · c_j)
                tmp[k] += Wh[j, k] + U[k0, k] * w
            inertia_congruence_downdate_add(Ad[j], Ih[j], U[k0], G[k0], Ih[p])  # eq. (16)
        else:
            three, o0, o1, o2 = outside(m.unit_axis, m.armature, k0, k1)
            if three:  # Ĩ_j on the three other coefficients alone (``pivots``)
                schur_block(Ih[j], U, G, k0, k1, o0, o1, o2, It)  # Ĩ_oo = Î_oo - U_o G_oᵀ
                schur_apply(It, C[j], o0, o1, o2, tmp)  # Ĩ_j[c_j]
            else:
                articulated_inertia(Ih[j], U, G, k0, k1, It)  # Ĩ_j = Î_j - U_j G_jᵀ
                inertia_apply(It, C[j], tmp)
            for k in range(6):  # W̄_j = Ŵ_j + Ĩ_j[c_j] + U_j ũ_j
                tmp[k] += Wh[j, k]
            for a in range(k0, k1):
                for k in range(6):
                    tmp[k] += U[a, k] * ut[a]
            if three:  # Î_λ += M_j * Ĩ_j, eq. (16)
                outside_congruence_add(Ad[j], It, o0, o1, o2, D, Ih[p])
            else:
                inertia_congruence_add(Ad[j], It, Ih[p])
        adjoint_apply(Ad[j], tmp, tmp2)  # M_j W̄_j ~M_j
        for k in range(6):
            Wh[p, k] += tmp2[k]
    for j in range(n):  # V now holds the accelerations V̇_j, V̇_0 = -g
        p = m.parents[j]
        adjoint_apply_transpose(Ad[j], m.gravity if p < 0 else V[p], tmp)
        for k in range(6):
            tmp[k] += C[j, k]  # V̄_j = ~M_j V̇_λ M_j + c_j
        k0, k1 = m.iv[j], m.iv[j + 1]
        for a in range(k0, k1):
            qdd[a] = ut[a] + dot(tmp, G[a])  # q̈_j = ũ_j + G_jᵀ · V̄_j
        for k in range(6):
            V[j, k] = tmp[k]
        if m.unit_axis[k0] >= 0:  # S_j = ±e_i
            for a in range(k0, k1):
                i = m.unit_axis[a]
                V[j, i] += qdd[a] * S[a, i]  # V̇_j = V̄_j + S_j q̈_j
        else:
            for a in range(k0, k1):
                for k in range(6):
                    V[j, k] += qdd[a] * S[a, k]  # V̇_j = V̄_j + S_j q̈_j
    return check_result(qdd)
