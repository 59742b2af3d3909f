"""The inverse mass matrix ``M(q)⁻¹`` from the articulated-body recursion, in O(n nv),
without forming or factorising M (Pinocchio's ``computeMinverse``); ``docs/derivatives.md``
derives it (M1-M5).

``q̈ = M⁻¹ τ`` is ABA (Algorithms 1 and 3) with no velocity and no gravity, and it is linear
in τ: every quantity of the recursion is a matrix with one column per torque. In world
coordinates (as in ``crba``) the articulated inertias add without moving. Backward pass
(j = n..1), ``Î_j`` the articulated inertia (eq. 16's sum in one frame), ``F_j`` the bias
wrench per torque column (nonzero on the coordinates of j's subtree):

    U_j = Î_j[S_j],   D_j = ⟨S_j, U_j⟩                                          (M1)
    M⁻¹[j, j] = D_j⁻¹,   M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ for c below j           (M2)
    F_λ[c] += F_j[c] + U_j M⁻¹[j, c],   Î_λ += Î_j - U_j D_j⁻¹ U_jᵀ

Forward pass (j = 1..n), ``A_j[c]`` the acceleration of body j per torque column, written
over F_j for the columns c from j on:

    M⁻¹[j, c] -= ⟨D_j⁻¹ U_j, A_λ[c]⟩,   A_j[c] = A_λ[c] + S_j M⁻¹[j, c]          (M3)

The entries at and after j's own coordinates make the upper triangle, mirrored (M4).

M⁻¹ does not change when the whole tree moves rigidly, so a tree whose root is a free flyer
is computed in the root body's own frame (M5): there the root's six S_k are the unit twists,
each one coefficient, and its pairings ⟨S_j, F_j[c]⟩ and its accelerations S_j M⁻¹[j, c]
read and write single coefficients instead of taking six-term dot products.

The recursion (``minverse_recursion``) is only arithmetic on arrays and the pivots' test
(``positive``), so that it runs on one sample's numbers or, through
``kernels.lane_arrays``, on ``W`` samples at once (``minverse_lanes``): the same operations
in the same order, the same numbers.
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import dot, inertia_apply
from ..kernels.lane_arrays import positive
from ..kernels.layout import added, coefficients, scaled
from ..kernels.rigid import rigid_frame, rigid_matrix, rigid_move_inertia, rigid_move_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import frame_motors, free_root, unit_coefficient
from .pivots import articulated_inertia, joint_pivot, pivot_gain
from .status import OK, SINGULAR, fault
from .work.minverse import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Mw": ("n", 8),  # the world motors
    "M": ("n", 8),  # the joint motors
    "Ih": ("n", 6, 6),  # the articulated inertias Î_j
    "par": (10,),  # ten parameters of an inertia
    "F": ("n", "nv", 6),  # a wrench or twist per torque column
    "Sw": ("nv", 6),  # S_k in the world
    "U": ("nv", 6),  # U_j = Î_j[S_j]
    "G": ("nv", 6),  # D_j⁻¹ U_j
    "D": (6, 6),
    "Dinv": (6, 6),
    "It": (6, 6),  # Ĩ_j
    "P": (6, 6),  # the rows of D_j⁻¹ S_jᵀ, one per coordinate of j
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
    "units": (2, "nv"),  # a free root's S_k = units[1, k] e_{units[0, k]} (M5), numbers
    "e": (6,),
}


@inline
def world_axes_inertias(m, q, c, s, tmp8, M, Mw, par, Sw, Ih):
    """``Sw`` (nv, 6) the joints' S_k and ``Ih`` (n, 6, 6) the bodies' I_j in the world, a
    free root's tree in its own frame (M5); the other arrays are scratch."""
    frame_motors(m, q, c, s, tmp8, M, Mw, True)
    move_axes_inertias(m, Mw, par, Sw, Ih)


@inline
def move_axes_inertias(m, Mw, par, Sw, Ih):
    """``Sw`` the S_k and ``Ih`` the I_j moved by the world motors ``Mw`` (eqs. 4, 16);
    ``par`` (10) scratch. Only arithmetic: it runs on ``W`` samples at once as well."""
    for j in range(m.n):
        r, p = rigid_frame(Mw[j])
        for k in range(m.iv[j], m.iv[j + 1]):
            rigid_move_twist(r, p, m.S[k], Sw[k])  # S_j in the world (eq. 4)
        rigid_move_inertia(r, p, m.inertias[j], par)  # I_j in the world (eq. 16)
        rigid_matrix(par, Ih[j])  # Î_j = I_j


@inline
def minverse_pass(m, q, Minv, k_):
    """``Minv`` (nv, nv), full and symmetric; a status. ``k_`` the workspace arrays."""
    world_axes_inertias(m, q, k_.c, k_.s, k_.tmp8, k_.M, k_.Mw, k_.par, k_.Sw, k_.Ih)
    j = minverse_recursion(m, k_, k_.units, Minv)
    if j >= 0:
        return fault(SINGULAR, j)
    mirror_upper(Minv)
    return OK


@inline
def minverse_recursion(m, k_, units, Minv):
    """M1-M3 from ``k_.Sw`` and ``k_.Ih`` (the S_k and I_j in the world, a free root's
    tree in its own frame, M5): the upper triangle of ``Minv``; -1, or the first joint whose
    D_j is not positive definite. ``k_`` the workspace (``WORKSPACE``), of numbers or its
    lane twin; ``units`` (2, nv) numbers, for a free root's unit twists."""
    Ih, F, Sw, U, G = k_.Ih, k_.F, k_.Sw, k_.U, k_.G
    D, Dinv, It, P, e = k_.D, k_.Dinv, k_.It, k_.P, k_.e
    nv = m.nv
    for j in range(m.n):  # S_k = s e_i of a free root (M5): i and s, numbers in any case
        if free_root(m.parents[j], m.types[j]):
            for k in range(m.iv[j], m.iv[j + 1]):
                i, x = unit_coefficient(m.S[k])
                units[0, k], units[1, k] = i, x
    for i in range(nv):
        for k in range(i, nv):
            Minv[i, k] = 0.0
    for j in range(m.n):  # the bias columns each joint's children add into
        for col in range(m.iv[j], m.subtree_end[j]):
            for i in range(6):
                F[j, col, i] = 0.0
    for j in range(m.n - 1, -1, -1):
        k0, k1, end = m.iv[j], m.iv[j + 1], m.subtree_end[j]
        if free_root(m.parents[j], m.types[j]):
            if not _free_root_backward(Ih[j], Sw, U, D, Dinv, F[j], Minv, k0, end, units, e,
                                       m.armature):
                return j
            continue
        for k in range(k0, k1):
            inertia_apply(Ih[j], Sw[k], U[k])  # U_j = Î_j[S_j] (M1)
        omega = 0.0
        if k1 - k0 == 1:
            d = -dot(Sw[k0], U[k0]) + m.armature[k0]  # D_j = ⟨S_j, U_j⟩ + rotor inertia
            if not positive(d):
                return j
            omega = 1.0 / d
            Dinv[0, 0] = omega
        elif not joint_pivot(m.armature, Sw, U, k0, k1, D, Dinv):  # D_j, D_j⁻¹ (M1)
            return j
        pivot_gain(Dinv, U, k0, k1, G)  # D_j⁻¹ U_j
        for a in range(k0, k1):
            for b in range(k0, k1):
                Minv[a, b] = Dinv[a - k0, b - k0]  # M⁻¹[j, j] = D_j⁻¹ (M2), the whole block
        parent = m.parents[j]
        if k1 - k0 == 1:  # one coordinate: the same with a number for D_j⁻¹
            s_j, u_j = coefficients(Sw[k0]), coefficients(U[k0])  # in registers
            for col in range(k1, end):  # M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ (M2)
                Minv[k0, col] = omega * dot(s_j, F[j, col])
            if parent >= 0:
                for col in range(k0, end):  # F_λ[c] += F_j[c] + U_j M⁻¹[j, c] (M2)
                    x = Minv[k0, col]
                    for i in range(6):
                        F[parent, col, i] += F[j, col, i] + u_j[i] * x
        else:
            for a in range(k0, k1):  # the rows of D_j⁻¹ S_jᵀ, once per joint
                p = scaled(Sw[k0], Dinv[a - k0, 0])
                for b in range(k0 + 1, k1):
                    p = added(p, Sw[b], Dinv[a - k0, b - k0])
                for i in range(6):
                    P[a - k0, i] = p[i]
            for col in range(k1, end):  # M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ (M2)
                f = coefficients(F[j, col])  # in registers
                for a in range(k0, k1):
                    Minv[a, col] = dot(P[a - k0], f)  # ⟨(D_j⁻¹ S_jᵀ)_a, F_j[c]⟩
            if parent >= 0:
                for col in range(k0, end):  # F_λ[c] += F_j[c] + U_j M⁻¹[j, c] (M2)
                    f = coefficients(F[j, col])
                    for a in range(k0, k1):
                        f = added(f, U[a], Minv[a, col])
                    for i in range(6):
                        F[parent, col, i] += f[i]
        if parent >= 0 and k1 - k0 == 1:  # Î_λ += Î_j - U_j D_j⁻¹ U_jᵀ in one pass (M2)
            for i in range(6):
                w = U[k0, i]
                for k in range(6):
                    Ih[parent, i, k] += Ih[j, i, k] - w * G[k0, k]
        elif parent >= 0:
            articulated_inertia(Ih[j], U, G, k0, k1, It)  # Ĩ_j = Î_j - U_j D_j⁻¹ U_jᵀ
            for i in range(6):
                for k in range(6):
                    Ih[parent, i, k] += It[i, k]  # Î_λ += Ĩ_j, one frame: a sum (M2)
    for j in range(m.n):
        k0, k1 = m.iv[j], m.iv[j + 1]
        parent = m.parents[j]
        if free_root(parent, m.types[j]):
            for col in range(k0, nv):  # A_j[c] = S_j M⁻¹[j, c], one coefficient each (M3, M5)
                for i in range(6):
                    F[j, col, i] = 0.0
                for a in range(k0, k1):
                    F[j, col, int(units[0, a])] = units[1, a] * Minv[a, col]
            continue
        if parent >= 0 and k1 - k0 == 1:  # one coordinate, below another joint
            g_j, s_j = coefficients(G[k0]), coefficients(Sw[k0])  # in registers
            for col in range(k0, nv):
                x = Minv[k0, col] + dot(g_j, F[parent, col])  # -⟨D⁻¹U_j, A_λ[c]⟩ (M3)
                Minv[k0, col] = x
                for i in range(6):
                    F[j, col, i] = F[parent, col, i] + s_j[i] * x  # A_λ[c] + S_j M⁻¹[j, c]
            continue
        start = k0 if parent >= 0 else k0 + 1  # a root's A_λ is zero
        for col in range(k0, nv):
            if parent >= 0:
                f = coefficients(F[parent, col])  # in registers
                for a in range(k0, k1):
                    Minv[a, col] += dot(G[a], f)  # -⟨D⁻¹U_j, A_λ[c]⟩ (M3)
            else:
                f = scaled(Sw[k0], Minv[k0, col])
            for a in range(start, k1):
                f = added(f, Sw[a], Minv[a, col])
            for i in range(6):
                F[j, col, i] = f[i]  # A_j[c] = A_λ[c] + S_j M⁻¹[j, c]
    return -1


@inline
def _free_root_backward(Ih, Sw, U, D, Dinv, F, Minv, k0, end, units, e, armature):
    """(M1, M2) for a free-flyer root in its own frame (M5): its coordinates ``k0 .. k0 + 6``
    have the unit twists S_k = s e_i, so ``⟨S_a, F[c]⟩ = s F[c][i]`` (``units`` holds i
    and s, ``e`` (6) is scratch); there is no parent to pass anything to. False if D is
    not positive definite."""
    for k in range(k0, k0 + 6):
        inertia_apply(Ih, Sw[k], U[k])  # U_j = Î_j[S_j] (M1)
    if not joint_pivot(armature, Sw, U, k0, k0 + 6, D, Dinv):  # D_j, D_j⁻¹ (M1)
        return False
    for a in range(6):
        for b in range(6):
            Minv[k0 + a, k0 + b] = Dinv[a, b]  # M⁻¹[j, j] = D_j⁻¹ (M2), the whole block
    for col in range(k0 + 6, end):  # M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ (M2)
        for b in range(6):
            e[b] = -units[1, k0 + b] * F[col, int(units[0, k0 + b])]  # -⟨S_b, F_j[c]⟩
        for a in range(6):
            x = 0.0
            for b in range(6):
                x += Dinv[a, b] * e[b]
            Minv[k0 + a, col] = x
    return True


@inline
def mirror_upper(X):
    """Copy the upper triangle of a square matrix onto its lower triangle (M4)."""
    for i in range(X.shape[0]):
        for k in range(i):
            X[i, k] = X[k, i]


@core
def minverse_core(m, q, Minv, work):
    """``Minv = M(q)⁻¹`` (nv, nv), full and symmetric."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    status = minverse_pass(m, q, Minv, workspace(ws.data_pointer(work), m))
    if status != OK:
        return status
    return check_result(Minv)

