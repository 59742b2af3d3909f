"""Analytic derivatives of inverse dynamics: ∂τ/∂q, ∂τ/∂v and ∂τ/∂a = M(q), in one fixed
frame (the world, or a free-flyer root's, D14). The derivation, with the equation numbers
cited here, is in ``docs/derivatives.md``.

Everything is expressed in one fixed frame, where a quantity X carried by the bodies below
joint L moves under a change of the joint's coordinate l as ``∂X/∂q_l = S_l × X`` (D1). The
twists and accelerations of the bodies below L move so, up to the terms that the parent's
motion brings (D3, D4); the body wrenches follow (D6) and, summed over subtrees, the
composite wrenches (D7). Pairing them with the joints' axes gives the derivatives (D8-D10):

    ∂τ_k/∂q_l = ⟨ψ_l, P_k⟩ + ⟨u_l, Q_k⟩      k at or below l's joint
    ∂τ_k/∂q_l = ⟨S_k, G_l⟩                    k above l's joint
    ∂τ_k/∂v_l = ⟨w_l, P_k⟩ + ⟨S_l, Q_k⟩      k at or below l's joint
    ∂τ_k/∂v_l = ⟨S_k, H_l⟩                    k above l's joint
    M_kl      = ⟨S_l, P_k⟩

with, per coordinate l of joint L (parent λ): ``u_l = V_λ × S_l``, ``ψ_l = A_λ × S_l +
V_λ × u_l``, ``w_l = V_L × S_l + u_l`` (D3-D5); per coordinate k of joint j, from the
composites of its subtree (inertia ``I^c``, its rate ``İ^c``, momentum ``h^c``, wrench
``F^c``): ``P_k = I^c[S_k]``, ``Q_k = İ^c[S_k] - S_k × h^c``, ``G_k = S_k × F^c +
I^c[ψ_k] + İ^c[u_k] + u_k × h^c``, ``H_k = I^c[w_k] + İ^c[S_k] + S_k × h^c`` (D11). ⟨·,·⟩ is
the power pairing of eq. (9), ``⟨V, W⟩ = -V · W``. The rigid inertias and their rates are
kept as ten parameters (``kernels.rigid``): in one frame the composites are plain sums.

A free-flyer root is computed in its own frame, frozen at q (D14): the torques and their
derivatives are pairings, which a common motion of the whole tree leaves alone, and there
the root's six S_k are unit twists, so that their pairings read one coefficient.
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import dot, twist_cross, twist_cross_wrench, twist_sandwich_rev, wrench_sandwich
from ..kernels.layout import coefficients
from ..kernels.rigid import (
    rigid_apply,
    rigid_frame,
    rigid_move_inertia,
    rigid_move_twist,
    rigid_rate,
)
from ..multibody.joints import joint_scalars
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import chain_motors, free_root, unit_coefficient
from .status import OK
from .work.rnea_derivatives import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Mw": ("n", 8),  # the bodies' motors in the frame
    "M": ("n", 8),  # the joint motors
    "V": ("n", 6),  # twists, accelerations, momenta and body wrenches
    "A": ("n", 6),
    "h": ("n", 6),
    "F": ("n", 6),
    "Iw": ("n", 10),  # I_j and İ_j in the frame; the composites accumulate in place
    "Id": ("n", 10),
    "Sw": ("nv", 6),  # S_k and the per-coordinate twists u, ψ, w
    "U": ("nv", 6),
    "Psi": ("nv", 6),
    "Wv": ("nv", 6),
    "P": (6, "nv"),  # P, Q, G, H by coefficient
    "Q": (6, "nv"),
    "G": (6, "nv"),
    "H": (6, "nv"),
    "g": (6,),  # the base acceleration
    "t1": (6,),
    "t2": (6,),
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


@inline
def _set(t, out):
    """Write a 6-tuple into ``out``."""
    out[0], out[1], out[2], out[3], out[4], out[5] = t[0], t[1], t[2], t[3], t[4], t[5]


@inline
def _set_column(t, X, k):
    """Write a 6-tuple into column k of ``X`` (6, nv)."""
    X[0, k], X[1, k], X[2, k], X[3, k], X[4, k], X[5, k] = t[0], t[1], t[2], t[3], t[4], t[5]


@core
def rnea_derivatives_forward(m, q, v, a, f, work):
    """The forward pass: motors, axes, inertias and their rates, twists, accelerations,
    momenta and body wrenches, and the per-coordinate twists u, ψ, w; into the workspace
    ``work`` (``WORKSPACE``). In the world frame, or a free-flyer root's (D14). A shared
    pass takes its workspace as the flat buffer and carves it here: the arrays' fixed
    widths (6, 8, 10) are then constants of its code, which they are not in arrays
    passed to it."""
    k_ = workspace(ws.data_pointer(work), m)
    joint_scalars(q, k_.c, k_.s)  # the scalars c, s of the revolute joint motors (eq. 6)
    forward_from_scalars(m, q, v, a, f, f.shape[0] > 0, k_)


@inline
def forward_from_scalars(m, q, v, a, f, forces, k_):
    """``rnea_derivatives_forward`` from the joint scalars c, s of ``k_`` on (``forces``:
    whether ``f`` holds external wrenches). Only arithmetic, so that it runs on ``W``
    samples at once as well (``rnea_derivatives_lanes``)."""
    Mw, M, V, A, h, F, Iw, Id = k_.Mw, k_.M, k_.V, k_.A, k_.h, k_.F, k_.Iw, k_.Id
    Sw, U, Psi, Wv, g, t1, t2, tmp8, c, s = (k_.Sw, k_.U, k_.Psi, k_.Wv, k_.g, k_.t1, k_.t2,
                                             k_.tmp8, k_.c, k_.s)
    chain_motors(m, q, c, s, tmp8, M, Mw, True)  # M^w_j, a free root at the identity (D14)
    for j in range(m.n):
        r, p = rigid_frame(Mw[j])
        k0, k1 = m.iv[j], m.iv[j + 1]
        for k in range(k0, k1):
            rigid_move_twist(r, p, m.S[k], Sw[k])  # S_k in the frame (eq. 4)
        rigid_move_inertia(r, p, m.inertias[j], Iw[j])  # I_j in the frame (eq. 16)
        parent = m.parents[j]
        if free_root(parent, m.types[j]):
            twist_sandwich_rev(M[j], m.gravity, g)  # A_0 = -g seen from the root (D14)
        elif parent < 0:
            _set(m.gravity, g)  # A_0 = -g
        for i in range(6):
            t1[i] = 0.0  # S_j q̇_j
            t2[i] = 0.0  # S_j q̈_j
        for k in range(k0, k1):
            for i in range(6):
                t1[i] += v[k] * Sw[k, i]
                t2[i] += a[k] * Sw[k, i]
        for i in range(6):  # V_j = V_λ + S_j q̇_j (D2)
            V[j, i] = t1[i] if parent < 0 else V[parent, i] + t1[i]
        twist_cross(V[j], t1, A[j])  # V_j × S_j q̇_j: Ṡ_j = V_j × S_j
        for i in range(6):  # A_j = A_λ + V_j × S_j q̇_j + S_j q̈_j (D2)
            A[j, i] += t2[i] + (g[i] if parent < 0 else A[parent, i])
        for k in range(k0, k1):
            if parent < 0:  # the base does not move: u = 0, ψ = A_0 × S
                for i in range(6):
                    U[k, i] = 0.0
                twist_cross(g, Sw[k], Psi[k])
            else:
                twist_cross(V[parent], Sw[k], U[k])  # u_k = V_λ × S_k (D3)
                twist_cross(A[parent], Sw[k], Psi[k])
                twist_cross(V[parent], U[k], t1)
                for i in range(6):
                    Psi[k, i] += t1[i]  # ψ_k = A_λ × S_k + V_λ × u_k (D4)
            twist_cross(V[j], Sw[k], Wv[k])
            for i in range(6):
                Wv[k, i] += U[k, i]  # w_k = V_j × S_k + V_λ × S_k (D5)
        _set(rigid_apply(Iw[j], V[j]), h[j])  # h_j = I_j[V_j]
        _set(rigid_apply(Iw[j], A[j]), F[j])
        twist_cross_wrench(V[j], h[j], t1)
        for i in range(6):
            F[j, i] += t1[i]  # F_j = I_j[A_j] + V_j × I_j[V_j] - W_ext,j (eq. 15)
        if forces:
            wrench_sandwich(Mw[j], f[j], t1)  # W_ext,j, given in the joint's frame
            for i in range(6):
                F[j, i] -= t1[i]
        rigid_rate(Iw[j], V[j], Id[j])  # İ_j = V_j × I_j - I_j V_j× (D6)


@core
def rnea_derivatives_backward(m, work, dq, dv, da):
    """The backward pass: composites and P, Q, G, H (D7, D11), then the entries (D8-D10);
    ``da`` (0, nv) when M is not wanted. P, Q, G, H are kept by coefficient, as six rows
    over the coordinates (column k is coordinate k's), so that the entries of a
    coordinate l with the contiguous range of coordinates at or below its joint are loops
    over columns, which the compiler vectorises; l's own twists are six numbers each.
    ``work`` the flat workspace, as in ``rnea_derivatives_forward``."""
    composites(m, workspace(ws.data_pointer(work), m))
    entries(m, work, dq, dv, da)


@inline
def composites(m, k_):
    """The backward pass's first half: the composites (D7) and P, Q, G, H (D11). Only
    arithmetic, so that it runs on ``W`` samples at once as well."""
    Ic, Idc = k_.Iw, k_.Id  # I_j and İ_j, summed in place into the composites (D7)
    h, F, Sw, U, Psi, Wv, t1, t2 = k_.h, k_.F, k_.Sw, k_.U, k_.Psi, k_.Wv, k_.t1, k_.t2
    P, Q, G, H = k_.P, k_.Q, k_.G, k_.H
    for j in range(m.n - 1, -1, -1):  # children come after their parents: I^c_j complete
        for k in range(m.iv[j], m.iv[j + 1]):  # (D11)
            _set_column(rigid_apply(Ic[j], Sw[k]), P, k)  # P_k = I^c[S_k]
            w = rigid_apply(Idc[j], Sw[k])  # İ^c[S_k]
            x = rigid_apply(Ic[j], Wv[k])  # I^c[w_k]
            twist_cross_wrench(Sw[k], h[j], t1)  # S_k × h^c
            for i in range(6):
                Q[i, k] = w[i] - t1[i]  # Q_k = İ^c[S_k] - S_k × h^c
                H[i, k] = x[i] + w[i] + t1[i]  # H_k = I^c[w_k] + İ^c[S_k] + S_k × h^c
            w = rigid_apply(Ic[j], Psi[k])  # I^c[ψ_k]
            x = rigid_apply(Idc[j], U[k])  # İ^c[u_k]
            twist_cross_wrench(Sw[k], F[j], t1)  # S_k × F^c
            twist_cross_wrench(U[k], h[j], t2)  # u_k × h^c
            for i in range(6):
                G[i, k] = t1[i] + w[i] + x[i] + t2[i]  # G_k
        parent = m.parents[j]
        if parent >= 0:  # the composites of the parent's subtree (D7)
            for i in range(10):
                Ic[parent, i] += Ic[j, i]
                Idc[parent, i] += Idc[j, i]
            for i in range(6):
                h[parent, i] += h[j, i]
                F[parent, i] += F[j, i]


@inline
def entries(m, work, dq, dv, da):
    """The backward pass's second half: the entries (D8-D10) from P, Q, G, H and the
    per-coordinate twists S, u, ψ, w of the flat workspace ``work``. Inlined into its two
    callers, ``rnea_derivatives_backward`` and the batch's loop over a group's samples
    (``rnea_derivatives_lanes._group``), which both write the results into arrays whose
    shapes they know (a called pass reads them at every index)."""
    k_ = workspace(ws.data_pointer(work), m)
    Sw, U, Psi, Wv, P, Q, G, H = k_.Sw, k_.U, k_.Psi, k_.Wv, k_.P, k_.Q, k_.G, k_.H
    nv = m.nv
    mass = da.shape[0] > 0
    for i in range(nv):  # entries of coordinates on different branches stay zero
        for k in range(nv):
            dq[i, k] = 0.0
            dv[i, k] = 0.0
    if mass:
        for i in range(nv):
            for k in range(nv):
                da[i, k] = 0.0
    for j in range(m.n):
        k0, k1, end = m.iv[j], m.iv[j + 1], m.subtree_end[j]  # j's subtree: k0 .. end
        parent = m.parents[j]
        root = parent < 0  # u_l = 0
        free = free_root(parent, m.types[j])  # S_l a unit twist (D14)
        for l in range(k0, k1):
            psi, w = coefficients(Psi[l]), coefficients(Wv[l])
            if free:  # ⟨S_l, W⟩ = S_l[i] W[i]
                i, x = unit_coefficient(Sw[l])
                for k in range(k0, end):  # k at or below l (D8, D9)
                    dq[k, l] = -dot(psi, P[:, k])
                    dv[k, l] = -dot(w, P[:, k]) + x * Q[i, k]
                for k in range(k1, end):  # l above k
                    dq[l, k] = x * G[i, k]
                    dv[l, k] = x * H[i, k]
                if mass:
                    for k in range(k0, end):
                        da[l, k] = da[k, l] = x * P[i, k]  # (D10)
                continue
            S = coefficients(Sw[l])
            if root:
                for k in range(k0, end):  # k at or below l (D8, D9)
                    dq[k, l] = -dot(psi, P[:, k])
                    dv[k, l] = -dot(w, P[:, k]) - dot(S, Q[:, k])
            else:
                u = coefficients(U[l])
                for k in range(k0, end):  # k at or below l (D8, D9)
                    dq[k, l] = -dot(psi, P[:, k]) - dot(u, Q[:, k])
                    dv[k, l] = -dot(w, P[:, k]) - dot(S, Q[:, k])
            for k in range(k1, end):  # l above k (D8, D9)
                dq[l, k] = -dot(S, G[:, k])
                dv[l, k] = -dot(S, H[:, k])
            if mass:
                for k in range(k0, end):
                    da[l, k] = da[k, l] = -dot(S, P[:, k])  # (D10)
    if mass:
        for k in range(nv):
            da[k, k] += m.armature[k]  # the rotors' inertia on M's diagonal


@core
def rnea_derivatives_core(m, q, v, a, f, dq, dv, da, work):
    """``dq = ∂τ/∂q``, ``dv = ∂τ/∂v`` and ``da = ∂τ/∂a = M`` (nv, nv) of one sample; ``f``
    the external wrenches (n, 6), or (0, 6) for none."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    rnea_derivatives_forward(m, q, v, a, f, work)
    rnea_derivatives_backward(m, work, dq, dv, da)
    status = check_result(dq)
    if status == OK:
        status = check_result(dv)
    return status

