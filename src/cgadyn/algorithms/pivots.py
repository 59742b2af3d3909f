"""A joint's pivot in the articulated-body recursion: the three steps that ABA (Algorithm 1),
M⁻¹ (M1, M2) and the Delassus recursion (C12, C13) share at a joint of several coordinates
``k0 .. k1`` (a one-coordinate joint takes them with a number for D_j, inline in each):

    D_j = -S_jᵀ · U_j + armature,   given U_j = Î_j[S_j]        Algorithm 1; M1
    G_j = U_j D_j⁻¹                                             Algorithm 1; M2
    Ĩ_j = Î_j - U_j G_jᵀ                                        Algorithm 1, second line

At a joint of three coordinates whose columns are each ±e_i (a spherical, planar or
translation joint: ``unit_axis``) and without rotor inertia, D_j is Î_j's block on those
three coefficients (up to signs that cancel) and Ĩ_j its Schur complement there, zero in
their rows and columns: Ĩ_j lives on the other three coefficients ``o`` (``outside``),

    Ĩ_oo = Î_oo - U_o G_oᵀ,   M_j * Ĩ_j = X_o Ĩ_oo X_oᵀ   (X the wrench adjoint, eq. 16)

``schur_block``, ``schur_apply`` and ``outside_congruence_add``, a third of the products
of the full forms.

``S`` and ``U`` hold one row per coordinate (``S[k]``, ``U[k]``, k in ``k0 .. k1``);
``D`` and ``Dinv`` are (6, 6) of which the leading (k1 - k0) block is used. Only
arithmetic and ``positive``: each runs on one sample's numbers or on ``W`` samples at once
(``kernels.lane_arrays``), as ``minverse``'s batches do.
"""

from __future__ import annotations

from .._jit import inline
from ..kernels import dot
from ._dense import spd_inverse


@inline
def joint_pivot(armature, S, U, k0, k1, D, Dinv):
    """``D`` = D_j = -S_jᵀ · U_j plus the rotors' inertia ``armature[k]`` on its diagonal,
    and ``Dinv`` = D_j⁻¹ (``D`` is overwritten). False when D_j is not positive definite
    (a subtree without inertia along the joint's motion)."""
    for a in range(k0, k1):
        for b in range(k0, k1):
            D[a - k0, b - k0] = -dot(S[a], U[b])  # D_j = -S_jᵀ · U_j
        D[a - k0, a - k0] += armature[a]  # + the rotors' inertia
    return spd_inverse(D, k1 - k0, Dinv)


@inline
def unit_pivot(armature, unit_axis, S, U, k0, k1, D, Dinv):
    """``joint_pivot`` at a joint whose columns are each ±e_i (``unit_axis[k] = i``): the
    pairing ``-S_aᵀ · U_b`` reads coefficient ``i_a`` of U_b alone."""
    for a in range(k0, k1):
        i = unit_axis[a]
        for b in range(k0, k1):
            D[a - k0, b - k0] = S[a, i] * U[b, i]  # D_j = -S_jᵀ · U_j (· is -Σ)
        D[a - k0, a - k0] += armature[a]  # + the rotors' inertia
    return spd_inverse(D, k1 - k0, Dinv)


@inline
def pivot_gain(Dinv, U, k0, k1, G):
    """``G[k]`` for k in ``k0 .. k1``: G_j = U_j D_j⁻¹, one wrench per coordinate."""
    for a in range(k0, k1):
        for i in range(6):
            G[a, i] = 0.0
        for b in range(k0, k1):
            w = Dinv[a - k0, b - k0]
            for i in range(6):
                G[a, i] += w * U[b, i]


@inline
def articulated_inertia(Ih, U, G, k0, k1, It):
    """``It`` = Ĩ_j = Î_j - U_j G_jᵀ from ``Ih`` = Î_j (6, 6), symmetric: the upper half
    formed, the lower mirrored."""
    for k in range(6):
        for l in range(k, 6):
            It[k, l] = Ih[k, l]
    for a in range(k0, k1):
        for k in range(6):
            w = U[a, k]
            for l in range(k, 6):
                It[k, l] -= w * G[a, l]
    for k in range(6):
        for l in range(k + 1, 6):
            It[l, k] = It[k, l]


@inline
def outside(unit_axis, armature, k0, k1):
    """``(True, o0, o1, o2)``: the three coefficients outside the joint's own where its
    three columns are each ±e_i, on three different axes, and it carries no rotor inertia
    (the module's docstring); False first for any other joint."""
    mask = 0
    if k1 - k0 != 3:
        return False, 0, 0, 0
    for k in range(k0, k1):
        if unit_axis[k] < 0 or armature[k] != 0.0:
            return False, 0, 0, 0
        mask |= 1 << unit_axis[k]
    o0 = o1 = o2 = -1
    n = 0
    for i in range(6):
        if not (mask >> i) & 1:
            n += 1
            if n == 1:
                o0 = i
            elif n == 2:
                o1 = i
            else:
                o2 = i
    return n == 3, o0, o1, o2


@inline
def schur_block(Ih, U, G, k0, k1, o0, o1, o2, It):
    """``It[o, o]`` = Ĩ_oo = Î_oo - U_o G_oᵀ on the coefficients ``o`` (``outside``), the
    only block of Ĩ_j that is not zero; the rest of ``It`` is left as it was."""
    for a in range(3):
        k = o0 if a == 0 else o1 if a == 1 else o2
        for b in range(a, 3):
            l = o0 if b == 0 else o1 if b == 1 else o2
            acc = Ih[k, l]
            for c in range(k0, k1):
                acc -= U[c, k] * G[c, l]
            It[k, l] = acc
            It[l, k] = acc


@inline
def schur_apply(It, x, o0, o1, o2, out):
    """``out = Ĩ x`` (``kernels.inertia_apply``) for Ĩ zero outside its block on the
    coefficients ``o`` (``schur_block``): zero on the joint's own coefficients."""
    for k in range(6):
        out[k] = 0.0
    for a in range(3):
        k = o0 if a == 0 else o1 if a == 1 else o2
        out[k] = It[k, o0] * x[o0] + It[k, o1] * x[o1] + It[k, o2] * x[o2]


@inline
def outside_congruence_add(X, It, o0, o1, o2, T, out):
    """``out += X Ĩ Xᵀ`` (M_j * Ĩ_j, eq. 16, as ``kernels.inertia_congruence_add``) for
    Ĩ zero outside its block on the coefficients ``o`` (``schur_block``): ``T = X_o
    Ĩ_oo`` (6 x 3, into the first three columns of ``T``), then ``T X_oᵀ``, its upper
    half formed and mirrored."""
    a00, a01, a02 = It[o0, o0], It[o0, o1], It[o0, o2]
    a11, a12, a22 = It[o1, o1], It[o1, o2], It[o2, o2]
    for k in range(6):
        x0, x1, x2 = X[k, o0], X[k, o1], X[k, o2]
        T[k, 0] = x0 * a00 + x1 * a01 + x2 * a02
        T[k, 1] = x0 * a01 + x1 * a11 + x2 * a12
        T[k, 2] = x0 * a02 + x1 * a12 + x2 * a22
    for k in range(6):
        t0, t1, t2 = T[k, 0], T[k, 1], T[k, 2]
        for l in range(k, 6):
            acc = t0 * X[l, o0] + t1 * X[l, o1] + t2 * X[l, o2]
            out[k, l] += acc
            if l != k:
                out[l, k] += acc
