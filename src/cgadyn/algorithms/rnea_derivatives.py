"""Analytic derivatives of inverse dynamics: ∂τ/∂q, ∂τ/∂v and ∂τ/∂a = M(q), in world
coordinates. The derivation, with the equation numbers cited here, is in
``docs/derivatives.md``.

Everything is expressed in the world frame, where a quantity X carried by the bodies below
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
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import dot, twist_cross, twist_cross_wrench, wrench_sandwich
from ..kernels.rigid import (
    rigid_apply,
    rigid_frame,
    rigid_move_inertia,
    rigid_move_twist,
    rigid_rate,
)
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import world_motors
from .status import OK


@inline
def _set(t, out):
    """Write a 6-tuple into ``out``."""
    out[0], out[1], out[2], out[3], out[4], out[5] = t[0], t[1], t[2], t[3], t[4], t[5]


@inline
def _add(t, out):
    """Add a 6-tuple to ``out``."""
    out[0] += t[0]
    out[1] += t[1]
    out[2] += t[2]
    out[3] += t[3]
    out[4] += t[4]
    out[5] += t[5]


@inline
def _pair(x, w):
    """The power pairing ``⟨V, W⟩ = -V · W`` of a twist and a wrench (eq. 9)."""
    return -dot(x, w)


@inline
def rnea_derivatives_forward(m, q, v, a, f, k_):
    """The forward pass: world motors, axes, inertias and their rates, twists, accelerations,
    momenta and body wrenches, and the per-coordinate twists u, ψ, w; into the workspace
    arrays of ``k_`` (see ``_workspace``)."""
    Mw, M, V, A, h, F, Iw, Id, Sw, U, Psi, Wv, P, Q, G, H, t1, t2, tmp8, c, s = k_
    world_motors(m, q, c, s, tmp8, M, Mw)  # M^w_j
    for j in range(m.n):
        r, p = rigid_frame(Mw[j])
        k0, k1 = m.iv[j], m.iv[j + 1]
        for k in range(k0, k1):
            rigid_move_twist(r, p, m.S[k], Sw[k])  # S_k in the world (eq. 4)
        rigid_move_inertia(r, p, m.inertias[j], Iw[j])  # I_j in the world (eq. 16)
        parent = m.parents[j]
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
        for i in range(6):  # A_j = A_λ + V_j × S_j q̇_j + S_j q̈_j, A_0 = -g (D2)
            A[j, i] += t2[i] + (m.gravity[i] if parent < 0 else A[parent, i])
        for k in range(k0, k1):
            if parent < 0:  # the world does not move: u = 0, ψ = A_0 × S
                for i in range(6):
                    U[k, i] = 0.0
                twist_cross(m.gravity, Sw[k], Psi[k])
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
        if f.shape[0] > 0:
            wrench_sandwich(Mw[j], f[j], t1)  # W_ext,j, given in the joint's frame
            for i in range(6):
                F[j, i] -= t1[i]
        rigid_rate(Iw[j], V[j], Id[j])  # İ_j = V_j × I_j - I_j V_j× (D6)


@inline
def rnea_derivatives_backward(m, k_, dq, dv, da):
    """The backward pass: composites, P, Q, G, H, and the entries (D8-D11); ``da`` (0, nv)
    when M is not wanted."""
    Mw, M, V, A, h, F, Ic, Idc, Sw, U, Psi, Wv, P, Q, G, H, t1, t2, tmp8, c, s = k_
    mass = da.shape[0] > 0
    for i in range(m.nv):  # entries of coordinates on different branches stay zero
        for k in range(m.nv):
            dq[i, k] = 0.0
            dv[i, k] = 0.0
    if mass:
        for i in range(m.nv):
            for k in range(m.nv):
                da[i, k] = 0.0
    for j in range(m.n - 1, -1, -1):  # children come after their parents: I^c_j complete
        k0, k1 = m.iv[j], m.iv[j + 1]
        for k in range(k0, k1):  # (D11)
            _set(rigid_apply(Ic[j], Sw[k]), P[k])  # P_k = I^c[S_k]
            _set(rigid_apply(Idc[j], Sw[k]), t2)  # İ^c[S_k]
            twist_cross_wrench(Sw[k], h[j], t1)  # S_k × h^c
            for i in range(6):
                Q[k, i] = t2[i] - t1[i]  # Q_k = İ^c[S_k] - S_k × h^c
                H[k, i] = t2[i] + t1[i]
            _add(rigid_apply(Ic[j], Wv[k]), H[k])  # H_k = I^c[w_k] + İ^c[S_k] + S_k × h^c
            twist_cross_wrench(Sw[k], F[j], G[k])  # S_k × F^c
            _add(rigid_apply(Ic[j], Psi[k]), G[k])  # + I^c[ψ_k]
            _add(rigid_apply(Idc[j], U[k]), G[k])  # + İ^c[u_k]
            twist_cross_wrench(U[k], h[j], t1)
            for i in range(6):
                G[k, i] += t1[i]  # + u_k × h^c
        for k in range(k0, k1):
            for l in range(k0, k1):  # the joint's own coordinates: k at l's joint
                dq[k, l] = _pair(Psi[l], P[k]) + _pair(U[l], Q[k])  # (D8)
                dv[k, l] = _pair(Wv[l], P[k]) + _pair(Sw[l], Q[k])  # (D9)
                if mass:
                    da[k, l] = _pair(Sw[l], P[k])  # M (D10)
            l = m.dof_parent[k0]
            while l >= 0:  # the coordinates of every joint above
                dq[k, l] = _pair(Psi[l], P[k]) + _pair(U[l], Q[k])  # k below l (D8)
                dq[l, k] = _pair(Sw[l], G[k])  # l above k
                dv[k, l] = _pair(Wv[l], P[k]) + _pair(Sw[l], Q[k])  # (D9)
                dv[l, k] = _pair(Sw[l], H[k])
                if mass:
                    da[k, l] = da[l, k] = _pair(Sw[l], P[k])  # (D10)
                l = m.dof_parent[l]
        parent = m.parents[j]
        if parent >= 0:  # the composites of the parent's subtree (D7)
            for i in range(10):
                Ic[parent, i] += Ic[j, i]
                Idc[parent, i] += Idc[j, i]
            for i in range(6):
                h[parent, i] += h[j, i]
                F[parent, i] += F[j, i]


@core
def rnea_derivatives_core(m, q, v, a, f, dq, dv, da, option, work):
    """``dq = ∂τ/∂q``, ``dv = ∂τ/∂v`` and ``da = ∂τ/∂a = M`` (nv, nv) of one sample; ``f``
    the external wrenches (n, 6), or (0, 6) for none."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = _workspace(ws.data_pointer(work), m)
    rnea_derivatives_forward(m, q, v, a, f, k_)
    rnea_derivatives_backward(m, k_, dq, dv, da)
    status = check_result(dq)
    if status == OK:
        status = check_result(dv)
    return status


@inline
def workspace_size(n, nq, nv, nl):
    return 60 * n + 48 * nv + 2 * nq + 20


@inline
def _workspace(buf, m):
    """Mw, M (n, 8); V, A, h, F (n, 6); Iw, İ (n, 10) (the composites accumulate in place);
    Sw, U, Ψ, Wv, P, Q, G, H (nv, 6); t1, t2 (6), tmp8 (8), the joint motors' scalars c, s
    (nq)."""
    Mw, o = ws.carve(buf, 0, (m.n, 8))
    M, o = ws.carve(buf, o, (m.n, 8))
    V, o = ws.carve(buf, o, (m.n, 6))
    A, o = ws.carve(buf, o, (m.n, 6))
    h, o = ws.carve(buf, o, (m.n, 6))
    F, o = ws.carve(buf, o, (m.n, 6))
    Iw, o = ws.carve(buf, o, (m.n, 10))
    Id, o = ws.carve(buf, o, (m.n, 10))
    Sw, o = ws.carve(buf, o, (m.nv, 6))
    U, o = ws.carve(buf, o, (m.nv, 6))
    Psi, o = ws.carve(buf, o, (m.nv, 6))
    Wv, o = ws.carve(buf, o, (m.nv, 6))
    P, o = ws.carve(buf, o, (m.nv, 6))
    Q, o = ws.carve(buf, o, (m.nv, 6))
    G, o = ws.carve(buf, o, (m.nv, 6))
    H, o = ws.carve(buf, o, (m.nv, 6))
    t1, o = ws.carve(buf, o, (6,))
    t2, o = ws.carve(buf, o, (6,))
    tmp8, o = ws.carve(buf, o, (8,))
    c, o = ws.carve(buf, o, (m.nq,))
    s, o = ws.carve(buf, o, (m.nq,))
    return Mw, M, V, A, h, F, Iw, Id, Sw, U, Psi, Wv, P, Q, G, H, t1, t2, tmp8, c, s
