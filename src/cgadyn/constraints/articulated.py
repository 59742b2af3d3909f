"""The Delassus matrix ``G = J M⁻¹ Jᵀ`` by the articulated-body recursion (C12), and ``M⁻¹ x``
by its two sweeps (C13), without forming or factoring M (``docs/constraints.md``).

In world coordinates (``algorithms.minverse.move_axes_inertias``: every S_k and I_j moved by
the world motors, eqs. 4, 16) the articulated inertias add without moving (M1, M2):

    U_j = Î_j[S_j],   D_j = ⟨S_j, U_j⟩ + armature,   Î_λ += Î_j - U_j D_j⁻¹ U_jᵀ

A constraint row r is a wrench ``W_r`` on the body that carries its end 1 (and ``-W_r`` on
end 2's): the force direction e at the point p, ``W = (p × e, e)`` (n, f), or the torque
direction e, ``W = (e, 0)``, so that ``⟨V, W_r⟩`` is the row's value of the body's twist V.
``G[r, s]`` is the acceleration of row r per unit force on row s. Applied as an external
wrench, row s's force passes up the tree through each joint's projection
``E_λ += E_j - U_j D_j⁻¹ ⟨S_j, E_j⟩`` (ABA's bias wrench with no velocity and no gravity),
and every joint it crosses adds ``S_j D_j⁻¹ ⟨S_j, E_j⟩`` to the accelerations of its
subtree; the same projections carry that acceleration down to row r's body. Hence

    Z_j[r] = ⟨S_j, E_j[r]⟩,   E_λ[r] += E_j[r] - U_j D_j⁻¹ Z_j[r],
    G = Σ_j Z_jᵀ D_j⁻¹ Z_j                                                      (C12)

with ``E_j[r]`` the wrench of row r at joint j, nonzero only on the path from row r's
bodies to the root, so that joint j pairs only the rows of constraints below it: O(n) for
the articulated inertias, O(depth) per row for the wrenches and one block of G per joint per
pair of rows below it (Featherstone's and Carpentier's O(n + m²) Delassus; a leg's joint
adds to its foot's block only). The same recursion on one column with the velocity
terms is ABA in the world (C13, ``articulated_sweeps``): the free acceleration
``M⁻¹ (τ - h)`` and ``M⁻¹ Jᵀ λ`` from the forces as wrenches on the rows' bodies, J never
formed (``row_values`` reads ``J x`` from the bodies' twists).

The arrays are the constraint core's workspace (``core.WORKSPACE``): ``Sa`` the S_k,
``Ih`` the Î_j, ``U``, ``Gd`` (D_j⁻¹ U_j) and ``Dinv`` (row k holds D_j⁻¹'s row for
coordinate k) per coordinate.
"""

from __future__ import annotations

from .._jit import inline
from ..algorithms.pivots import articulated_inertia, joint_pivot, pivot_gain
from ..kernels import (
    adjoint_apply,
    dot,
    inertia_apply,
    twist_cross,
    twist_cross_wrench,
    twist_sandwich_rev,
    wrench_adjoint,
    wrench_sandwich,
)
from ..kernels.lane_arrays import positive
from ..kernels.layout import coefficients, store_bivector
from ..multibody.joints import free_root


@inline
def articulated_inertias(m, k_):
    """M1 and Î_λ's update (M2) for every joint, leaves first: ``U``, ``Gd``, ``Dinv`` per
    coordinate; -1, or the first joint whose D_j is not positive definite. A free-flyer
    root without rotor inertia gets the Cholesky factor of its Î_j instead, in place
    (``k_.fr[j]`` 1), which C12' and C13' read."""
    Ih, Sa, U, Gd, Dinv, D, Dj, It = k_.Ih, k_.Sa, k_.U, k_.Gd, k_.Dinv, k_.Dm, k_.Dj, k_.It
    for j in range(m.n - 1, -1, -1):
        k0, k1 = m.iv[j], m.iv[j + 1]
        k_.fr[j] = 0.0
        if free_root(m.parents[j], m.types[j]):
            rotors = 0.0
            for k in range(k0, k1):
                rotors += abs(m.armature[k])
            if rotors == 0.0:
                k_.fr[j] = 1.0
                if not _cholesky6(Ih[j]):
                    return j
                continue
        for k in range(k0, k1):
            inertia_apply(Ih[j], Sa[k], U[k])  # U_j = Î_j[S_j] (M1)
        if k1 - k0 == 1:
            d = -dot(Sa[k0], U[k0]) + m.armature[k0]  # D_j = ⟨S_j, U_j⟩ + rotor inertia
            if not positive(d):
                return j
            w = 1.0 / d
            Dinv[k0, 0] = w
            for i in range(6):
                Gd[k0, i] = U[k0, i] * w
        else:
            if not joint_pivot(m.armature, Sa, U, k0, k1, D, Dj):  # D_j, D_j⁻¹ (M1)
                return j
            pivot_gain(Dj, U, k0, k1, Gd)  # D_j⁻¹ U_j
            for a in range(k0, k1):
                for b in range(k0, k1):
                    Dinv[a, b - k0] = Dj[a - k0, b - k0]
        p = m.parents[j]
        if p < 0:
            continue
        if k1 - k0 == 1:  # Î_λ += Î_j - U_j D_j⁻¹ U_jᵀ (M2), symmetric: the lower half
            for i in range(6):
                w = U[k0, i]
                for k in range(i + 1):
                    x = Ih[p, i, k] + (Ih[j, i, k] - w * Gd[k0, k])
                    Ih[p, i, k] = x
                    Ih[p, k, i] = x
        else:
            articulated_inertia(Ih[j], U, Gd, k0, k1, It)  # Ĩ_j
            for i in range(6):
                for k in range(6):
                    Ih[p, i, k] += It[i, k]
    return -1


@inline
def delassus_rows(m, nc, nr, k_, G):
    """``G`` (nr, nr) of C12 from the rows' wrenches ``k_.W[e, r]`` on the bodies
    ``k_.rb[e, r]`` (end e; -1 the world; end 2's wrench counts negative), after
    ``articulated_inertias``. Constraint c holds rows ``k_.blocks[0, c] ..
    k_.blocks[1, c]``; its rows pass the same joints, so paths are walked per constraint,
    and each joint takes all the rows that pass it at once (independent sums, which the
    processor overlaps)."""
    Sa, Gd, Dinv, W, rb, act, Ec, Z, Y, live, blocks = (
        k_.Sa, k_.Gd, k_.Dinv, k_.W, k_.rb, k_.act, k_.Ec, k_.Z, k_.Y, k_.live, k_.blocks)
    for j in range(m.n):
        for c in range(nc):
            act[j, c] = 0.0
    for r in range(nr):
        for s in range(nr):
            G[r, s] = 0.0
    for c in range(nc):
        r0, r1 = int(blocks[0, c]), int(blocks[1, c])
        for e in range(2):  # the constraint's path: its rows' wrenches from its bodies up
            j = int(rb[e, r0])
            while j >= 0 and act[j, c] == 0.0:
                act[j, c] = 1.0
                for r in range(r0, r1):
                    for i in range(6):
                        Ec[j, r, i] = 0.0
                j = m.parents[j]
        for e in range(2):
            b = int(rb[e, r0])
            if b >= 0:
                sign = 1.0 if e == 0 else -1.0
                for r in range(r0, r1):
                    for i in range(6):
                        Ec[b, r, i] += sign * W[e, r, i]
    for j in range(m.n - 1, -1, -1):
        k0, k1 = m.iv[j], m.iv[j + 1]
        na = 0
        for c in range(nc):
            if act[j, c] != 0.0:
                live[na] = c
                na += 1
        if na == 0:
            continue
        p = m.parents[j]
        if k_.fr[j] != 0.0:  # a free root: G += E_jᵀ Î_j⁻¹ E_j (C12')
            _free_root_rows(Ec[j], k_.Ih[j], k_.Yt, live, na, nr, na == nc, blocks, G)
            continue
        if k1 - k0 == 1:  # one coordinate: S_j, D_j⁻¹ U_j in registers, D_j⁻¹ a number
            sj, gj, w = coefficients(Sa[k0]), coefficients(Gd[k0]), Dinv[k0, 0]
            for t in range(na):  # a block's size is a constant in each branch: unrolled
                r0 = int(blocks[0, int(live[t])])
                if int(blocks[1, int(live[t])]) - r0 == 3:
                    _one_coordinate(Ec, Z, j, p, k0, r0, 3, sj, gj)
                else:
                    _one_coordinate(Ec, Z, j, p, k0, r0, 6, sj, gj)
            for t in range(na):  # G += Z_jᵀ D_j⁻¹ Z_j on the rows below j, lower half (C12)
                ra = int(blocks[0, int(live[t])])
                small = int(blocks[1, int(live[t])]) - ra == 3
                for t2 in range(t):
                    rc = int(blocks[0, int(live[t2])])
                    if int(blocks[1, int(live[t2])]) - rc == 3:
                        if small:
                            _rank_one(G, Z, k0, w, ra, 3, rc, 3, False)
                        else:
                            _rank_one(G, Z, k0, w, ra, 6, rc, 3, False)
                    elif small:
                        _rank_one(G, Z, k0, w, ra, 3, rc, 6, False)
                    else:
                        _rank_one(G, Z, k0, w, ra, 6, rc, 6, False)
                if small:
                    _rank_one(G, Z, k0, w, ra, 3, ra, 3, True)
                else:
                    _rank_one(G, Z, k0, w, ra, 6, ra, 6, True)
            continue
        for t in range(na):
            c = int(live[t])
            for r in range(int(blocks[0, c]), int(blocks[1, c])):
                for k in range(k0, k1):
                    Z[k, r] = -dot(Sa[k], Ec[j, r])  # Z_j[r] = ⟨S_j, E_j[r]⟩ (C12)
                for a in range(k0, k1):  # Y_j = D_j⁻¹ Z_j
                    x = 0.0
                    for b in range(k0, k1):
                        x += Dinv[a, b - k0] * Z[b, r]
                    Y[a - k0, r] = x
                if p >= 0:
                    for i in range(6):
                        x = Ec[j, r, i]
                        for k in range(k0, k1):
                            x -= Gd[k, i] * Z[k, r]
                        Ec[p, r, i] += x  # E_λ[r] += E_j[r] - U_j D_j⁻¹ Z_j[r] (C12)
        for t in range(na):  # G += Y_jᵀ Z_j on the rows below j, the lower half (C12)
            c = int(live[t])
            for t2 in range(t + 1):
                c2 = int(live[t2])
                s0 = int(blocks[0, c2])
                for r in range(int(blocks[0, c]), int(blocks[1, c])):
                    s1 = r + 1 if c2 == c else int(blocks[1, c2])
                    for s in range(s0, s1):
                        x = G[r, s]
                        for a in range(k1 - k0):
                            x += Y[a, r] * Z[k0 + a, s]
                        G[r, s] = x
    for r in range(nr):  # ``live`` is in increasing order: the sums fill the lower half
        for s in range(r):
            G[s, r] = G[r, s]


@inline
def _one_coordinate(Ec, Z, j, p, k0, r0, size, sj, gj):
    """C12 at a joint of one coordinate for the ``size`` rows from ``r0`` (3 or 6, a constant
    where called, so that the loop unrolls): ``Z_j[r] = ⟨S_j, E_j[r]⟩`` and the wrench
    ``E_λ[r] += E_j[r] - U_j D_j⁻¹ Z_j[r]`` passed to the parent p (none at a root); ``sj``,
    ``gj`` the coefficients of S_j and D_j⁻¹ U_j."""
    s0, s1, s2, s3, s4, s5 = sj
    g0, g1, g2, g3, g4, g5 = gj
    for r in range(r0, r0 + size):
        e0, e1, e2, e3, e4, e5 = coefficients(Ec[j, r])
        z = s0 * e0 + s1 * e1 + s2 * e2 + s3 * e3 + s4 * e4 + s5 * e5
        Z[k0, r] = z
        if p >= 0:
            Ec[p, r, 0] += e0 - g0 * z
            Ec[p, r, 1] += e1 - g1 * z
            Ec[p, r, 2] += e2 - g2 * z
            Ec[p, r, 3] += e3 - g3 * z
            Ec[p, r, 4] += e4 - g4 * z
            Ec[p, r, 5] += e5 - g5 * z


@inline
def _rank_one(G, Z, k0, w, ra, na, rb, nb, diagonal):
    """``G[r, s] += Z_j[r] D_j⁻¹ Z_j[s]`` (C12) for the ``na`` rows from ``ra`` and the ``nb``
    from ``rb`` (constants where called), ``s <= r`` on a ``diagonal`` block."""
    for r in range(ra, ra + na):
        y = w * Z[k0, r]
        for s in range(rb, r + 1 if diagonal else rb + nb):
            G[r, s] += y * Z[k0, s]


@inline
def _cholesky6(A):
    """``A = L Lᵀ`` in place for a 6x6 symmetric ``A``: L below the diagonal, the
    reciprocals ``1 / L_aa`` on it (its solves multiply); False where A is not positive
    definite."""
    for a in range(6):
        for c in range(a + 1):
            acc = A[a, c]
            for k in range(c):
                acc -= A[a, k] * A[c, k]
            if a == c:
                if not positive(acc):
                    return False
                A[a, a] = 1.0 / acc ** 0.5
            else:
                A[a, c] = acc * A[c, c]
    return True


@inline
def _free_root_rows(E, L, Yt, live, na, nr, whole, blocks, G):
    """``G += Eᵀ Î⁻¹ E`` on the rows that reach a free-flyer root, ``L`` the Cholesky factor
    of its articulated inertia Î (``articulated_inertias``). Its six S_k span every twist,
    so ``Z_jᵀ D_j⁻¹ Z_j = Eᵀ S (Sᵀ Î S)⁻¹ Sᵀ E = Eᵀ Î⁻¹ E`` (C12'): with ``Y = L⁻¹ E``,
    ``G += Yᵀ Y``; no S_k, U_j or D_j. ``Yt`` holds Y's columns as rows. ``whole``: every
    constraint reaches it (the usual case), so G's whole lower half takes one plain loop."""
    d0, d1, d2, d3, d4, d5 = L[0, 0], L[1, 1], L[2, 2], L[3, 3], L[4, 4], L[5, 5]
    for t in range(na):
        c = int(live[t])
        for r in range(int(blocks[0, c]), int(blocks[1, c])):
            e0, e1, e2, e3, e4, e5 = coefficients(E[r])  # Y = L⁻¹ E, forward substitution
            y0 = e0 * d0
            y1 = (e1 - L[1, 0] * y0) * d1
            y2 = (e2 - L[2, 0] * y0 - L[2, 1] * y1) * d2
            y3 = (e3 - L[3, 0] * y0 - L[3, 1] * y1 - L[3, 2] * y2) * d3
            y4 = (e4 - L[4, 0] * y0 - L[4, 1] * y1 - L[4, 2] * y2 - L[4, 3] * y3) * d4
            y5 = (e5 - L[5, 0] * y0 - L[5, 1] * y1 - L[5, 2] * y2 - L[5, 3] * y3
                  - L[5, 4] * y4) * d5
            Yt[r, 0], Yt[r, 1], Yt[r, 2], Yt[r, 3], Yt[r, 4], Yt[r, 5] = y0, y1, y2, y3, y4, y5
    if whole:
        for r in range(nr):
            y0, y1, y2, y3, y4, y5 = coefficients(Yt[r])
            for s in range(r + 1):
                G[r, s] += (y0 * Yt[s, 0] + y1 * Yt[s, 1] + y2 * Yt[s, 2]
                            + y3 * Yt[s, 3] + y4 * Yt[s, 4] + y5 * Yt[s, 5])
        return
    for t in range(na):
        c = int(live[t])
        for r in range(int(blocks[0, c]), int(blocks[1, c])):
            y0, y1, y2, y3, y4, y5 = coefficients(Yt[r])
            for t2 in range(t + 1):
                c2 = int(live[t2])
                s1 = r + 1 if c2 == c else int(blocks[1, c2])
                for s in range(int(blocks[0, c2]), s1):
                    G[r, s] += (y0 * Yt[s, 0] + y1 * Yt[s, 1] + y2 * Yt[s, 2]
                                + y3 * Yt[s, 3] + y4 * Yt[s, 4] + y5 * Yt[s, 5])


@inline
def body_motion(m, v, f, k_, bias):
    """From the world S_k (``k_.Sa``) and the velocity v: every body's world twist
    ``V_j = V_λ + S_j v_j`` (``k_.Vw``), the velocity-product acceleration
    ``c_j = V_j × S_j v_j`` (``k_.Cw``; in the world ``Ṡ_j = V_j × S_j``) and the bodies'
    accelerations at q̈ = 0 without gravity ``A_j = A_λ + c_j`` (``k_.Aw``); with ``bias``
    also the bias wrench of ABA in the external sign, ``E_j = f_j - V_j × I_j[V_j]``
    (``k_.Eb``; Algorithm 3's Ŵ_j negated, I_j from ``k_.Ih`` before the articulated pass,
    ``f`` the external wrenches in the bodies' frames, or (0, 6) for none)."""
    Sa, Vw, Cw, Aw, Eb, t = k_.Sa, k_.Vw, k_.Cw, k_.Aw, k_.Eb, k_.tw
    for j in range(m.n):
        p = m.parents[j]
        for i in range(6):
            t[i] = 0.0
        for k in range(m.iv[j], m.iv[j + 1]):
            x = v[k]
            for i in range(6):
                t[i] += Sa[k, i] * x  # S_j v_j
        for i in range(6):
            Vw[j, i] = (Vw[p, i] if p >= 0 else 0.0) + t[i]
        twist_cross(Vw[j], t, Cw[j])  # c_j = V_j × S_j v_j
        for i in range(6):
            Aw[j, i] = (Aw[p, i] if p >= 0 else 0.0) + Cw[j, i]
        if bias:
            inertia_apply(k_.Ih[j], Vw[j], t)  # I_j[V_j]
            twist_cross_wrench(Vw[j], t, Eb[j])  # V_j × I_j[V_j]
            for i in range(6):
                Eb[j, i] = -Eb[j, i]
            if f.shape[0] > 0:  # + M^w_j f_j ~M^w_j, the external wrench in the world
                wrench_adjoint(k_.Mw[j], k_.Dm)
                adjoint_apply(k_.Dm, f[j], t)
                for i in range(6):
                    Eb[j, i] += t[i]


@inline
def articulated_sweeps(m, x, E, bias, gravity, k_, out):
    """``out = M⁻¹ (x + Σ_j J_jᵀ E_j)`` for generalised forces x (nv) and wrenches E (n, 6,
    consumed) on the bodies (C13), after ``articulated_inertias``; with ``bias`` ABA
    itself (Algorithm 3 in the world): the velocity products c_j (``k_.Cw``) and the base
    acceleration ``gravity`` (``-g``) enter, so that with E the bias wrenches
    (``body_motion``) and x = τ, out is the free acceleration ``M⁻¹ (τ - h)``.

        backward:  u_j = x_j + ⟨S_j, E_j⟩,   y_j = D_j⁻¹ u_j,
                   E_λ += E_j - Ĩ_j[c_j] - U_j y_j,   Ĩ_j[c] = Î_j[c] - U_j ⟨c, D_j⁻¹ U_j⟩
        forward:   q̈_j = y_j - ⟨A_λ + c_j, D_j⁻¹ U_j⟩,   A_j = A_λ + c_j + S_j q̈_j

    Without ``bias`` c_j and the base acceleration are zero. A free root whose Î_j holds its
    Cholesky factor (``k_.fr[j]``) is solved by C13' (``_free_root_motion``). ``E`` ends as
    the bodies' accelerations."""
    Sa, U, Gd, Dinv, Cw, y, t = k_.Sa, k_.U, k_.Gd, k_.Dinv, k_.Cw, k_.ys, k_.tw
    for j in range(m.n - 1, -1, -1):
        k0, k1 = m.iv[j], m.iv[j + 1]
        if k_.fr[j] != 0.0:
            continue  # a free root: its q̈_j in the forward sweep (C13')
        for k in range(k0, k1):
            y[k] = x[k] - dot(Sa[k], E[j])  # u_j = x_j + ⟨S_j, E_j⟩
        for a in range(k0, k1):
            acc = 0.0
            for b in range(k0, k1):
                acc += Dinv[a, b - k0] * y[b]
            out[a] = acc  # y_j = D_j⁻¹ u_j
        p = m.parents[j]
        if p < 0:
            continue
        if bias:
            inertia_apply(k_.Ih[j], Cw[j], t)  # Î_j[c_j]
            for i in range(6):
                E[p, i] += E[j, i] - t[i]
            for a in range(k0, k1):
                w = -dot(Cw[j], Gd[a]) - out[a]  # ⟨c_j, D_j⁻¹ U_j⟩ - y_j
                for i in range(6):
                    E[p, i] += U[a, i] * w
        else:
            for i in range(6):
                acc = E[j, i]
                for a in range(k0, k1):
                    acc -= U[a, i] * out[a]
                E[p, i] += acc  # E_λ += E_j - U_j y_j
    for j in range(m.n):  # E now holds the accelerations A_j
        k0, k1 = m.iv[j], m.iv[j + 1]
        p = m.parents[j]
        for i in range(6):
            t[i] = E[p, i] if p >= 0 else (gravity[i] if bias else 0.0)
            if bias:
                t[i] += Cw[j, i]  # A_λ + c_j
        if k_.fr[j] != 0.0:
            _free_root_motion(m, j, k0, x, E[j], k_.Ih[j], t, k_, out)
            continue
        for a in range(k0, k1):
            out[a] += dot(t, Gd[a])  # q̈_j = y_j - ⟨A_λ + c_j, D_j⁻¹ U_j⟩
        for i in range(6):
            acc = t[i]
            for a in range(k0, k1):
                acc += Sa[a, i] * out[a]
            E[j, i] = acc  # A_j = A_λ + c_j + S_j q̈_j


@inline
def _free_root_motion(m, j, k0, x, E, L, t, k_, out):
    """C13' at a free-flyer root j, ``L`` the Cholesky factor of its Î_j: its six S_k span
    every twist, so the sweeps' ``q̈_j = D_j⁻¹ (u_j - U_jᵀ t)`` with ``u_j = x_j + S_jᵀ E_j``
    is ``A_j = Î_j⁻¹ (S_j⁻ᵀ x_j + E_j)`` and ``q̈_j = S_j⁻¹ (A_j - t)`` (t its base
    acceleration plus c_j). ``S_j = T B``: T the twist sandwich by the world motor, B the
    free flyer's unit twists (a signed permutation, so ``B⁻ᵀ = B``), and the wrench
    sandwich is ``T⁻ᵀ`` (both keep the pairing), so ``S_j⁻ᵀ x = M (B x) ~M`` and
    ``S_j⁻¹ V = Bᵀ (~M V M)``. ``E`` (6) ends as A_j."""
    b, w = k_.Dm[0], k_.Dm[1]
    for i in range(6):
        acc = 0.0
        for a in range(6):
            acc += m.S[k0 + a, i] * x[k0 + a]
        b[i] = acc  # B x
    wrench_sandwich(k_.Mw[j], b, w)  # S_j⁻ᵀ x
    for i in range(6):  # L Lᵀ A = S_j⁻ᵀ x + E, forward then back substitution
        acc = w[i] + E[i]
        for k in range(i):
            acc -= L[i, k] * b[k]
        b[i] = acc * L[i, i]
    for i in range(5, -1, -1):
        acc = b[i]
        for k in range(i + 1, 6):
            acc -= L[k, i] * E[k]
        E[i] = acc * L[i, i]
    for i in range(6):
        w[i] = E[i] - t[i]
    twist_sandwich_rev(k_.Mw[j], w, b)  # ~M (A_j - t) M
    for a in range(6):
        out[k0 + a] = -dot(m.S[k0 + a], b)  # q̈_j = Bᵀ (~M (A_j - t) M)


@inline
def row_values(m, nr, X, k_, out):
    """``out[r] = ⟨X_{b₁}, W₁_r⟩ - ⟨X_{b₂}, W₂_r⟩``: row r's value of the bodies' twists X
    (n, 6; the world's is zero), which is ``(J x)_r`` for the twists ``X_j = Σ S_k x_k``
    along each body's path (C12's rows as wrenches)."""
    for r in range(nr):
        acc = 0.0
        for e in range(2):
            b = int(k_.rb[e, r])
            if b >= 0:
                value = -dot(X[b], k_.W[e, r])
                acc += value if e == 0 else -value
        out[r] = acc


@inline
def row_forces(m, nr, lam, k_, E):
    """``E`` (n, 6) the wrenches of the forces λ on the bodies: ``λ_r W₁_r`` on end 1's,
    ``-λ_r W₂_r`` on end 2's, so that ``Σ_j J_jᵀ E_j = Jᵀ λ``."""
    for j in range(m.n):
        for i in range(6):
            E[j, i] = 0.0
    for r in range(nr):
        for e in range(2):
            b = int(k_.rb[e, r])
            if b >= 0:
                x = lam[r] if e == 0 else -lam[r]
                for i in range(6):
                    E[b, i] += x * k_.W[e, r, i]


@inline
def row_wrench(p, e1, e2, e3, linear, out):
    """``out`` the wrench of a row (C12): the force direction e at the point p,
    ``(p × e, e)`` (``linear``), or the torque direction e, ``(e, 0)``; as coefficients."""
    if linear:
        store_bivector(p[1] * e3 - p[2] * e2, p[2] * e1 - p[0] * e3, p[0] * e2 - p[1] * e1,
                       e1, e2, e3, out)
    else:
        store_bivector(e1, e2, e3, 0.0, 0.0, 0.0, out)
