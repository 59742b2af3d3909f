"""M's factorisation along the tree and its inverse from it (Featherstone's LTDL):
``aba_derivatives`` has M already (the rnea derivatives' ∂τ/∂a) and gets q̈, M⁻¹ and, on a
small branched tree, ``-M⁻¹ [∂τ/∂q  ∂τ/∂v]`` from it (``docs/derivatives.md``, L1-L6, D13 and
D15); ``minverse`` alone runs the articulated-body recursion instead (M1-M5).

M has the sparsity of the kinematic tree (Featherstone's expanded tree, one node per
velocity coordinate, ``dof_parent`` λ): ``M[k, i]`` for ``i < k`` is zero unless i
supports k. Eliminating from the leaves keeps that pattern:

    M = Lᵀ D L,   L unit lower triangular, L[k, i] ≠ 0 only for i supporting k         (L1)
    for k = nv-1..0, i = λ(k), λ(λ(k)), ...:
        L[k, i] = M[k, i] / D_k,   M[i, j] -= L[k, i] M[k, j]   (j = i, λ(i), ...)     (L2)

with ``D_k`` the diagonal left once k's descendants are eliminated. Then ``Z = M⁻¹`` solves
``L Z = D⁻¹ L⁻ᵀ``, whose right side is upper triangular with diagonal ``D⁻¹``; row by row,
k = 0..nv-1, from the rows of the coordinates supporting k:

    Z[k, c] = -Σ_{i supports k} L[k, i] Z[i, c]                  for c < k         (L3)
    Z[k, k] = D_k⁻¹ - Σ_{i supports k} L[k, i] Z[k, i],   Z[c, k] = Z[k, c]           (L4)

The cost is ``Σ_k k d_k`` (``d_k`` the number of coordinates supporting k). A matrix X of
right-hand sides (rows are coordinates) is solved, ``Y = s M⁻¹ X``, by the same two sweeps
on whole rows, the first pulling from the coordinates below i (i+1 .. e_i, contiguous in
the tree's order), the second from those supporting k:

    W[i] = X[i] - Σ_{k below i} L[k, i] W[k]                     for i = nv-1..0     (L5)
    Y[k] = s D_k⁻¹ W[k] - Σ_{i supports k} L[k, i] Y[i]          for k = 0..nv-1     (L6)

at ``2 Σ_k d_k + nv`` row operations, against nv² for the product with M⁻¹. A
congruence ``Xᵀ M⁻¹ X`` (the Delassus operator of the rows ``Xᵀ = J``) takes the first
sweep alone:

    Xᵀ M⁻¹ X = Wᵀ D⁻¹ W = Σ_k W[k]ᵀ W[k] / D_k,   W = L⁻ᵀ X by (L5)                  (L7)

a sum of one symmetric rank-one term per coordinate, nonzero only on the columns of X that
the coordinate supports.
"""

from __future__ import annotations

import math

from .._jit import inline
from . import _workspace as ws
from ._dense import rows_subtract1, rows_subtract2, rows_subtract4

__all__ = ["ltdl", "ltdl_inverse", "ltdl_lower_rows", "ltdl_solve", "ltdl_solve_rows",
           "supports"]


@inline
def ltdl(m, H):
    """``H = M`` into ``Lᵀ D L`` in place (L1, L2): L below the diagonal, D on it; the rest
    of the lower triangle (pairs on different branches) stays as it was (zero). Returns -1,
    or the first coordinate whose pivot is not positive."""
    par = m.dof_parent
    for k in range(m.nv - 1, -1, -1):
        d = H[k, k]
        if not (d > 0.0 and math.isfinite(d)):
            return k
        i = par[k]
        while i >= 0:
            a = H[k, i] / d  # L[k, i] (L2)
            j = i
            while j >= 0:
                H[i, j] -= a * H[k, j]  # M[i, j] -= L[k, i] M[k, j]
                j = par[j]
            H[k, i] = a
            i = par[i]
    return -1


@inline
def ltdl_inverse(m, H, lk):
    """``H = Lᵀ D L`` (``ltdl``'s result) into ``M⁻¹``, full and symmetric, in place (L3,
    L4); ``lk`` (nv) scratch for the L entries of one row, which that row's result
    overwrites."""
    par = m.dof_parent
    for k in range(m.nv):
        i = par[k]
        n = 0
        while i >= 0:
            lk[n] = H[k, i]  # L[k, i], i supporting k
            n += 1
            i = par[i]
        x = 1.0 / H[k, k]  # D_k⁻¹
        if n > 0:
            i = par[k]
            a = lk[0]
            for c in range(k):
                H[k, c] = -a * H[i, c]  # Z[k, c] = -Σ L[k, i] Z[i, c] (L3)
            for t in range(1, n):
                i = par[i]
                a = lk[t]
                for c in range(k):
                    H[k, c] -= a * H[i, c]
            i = par[k]
            for t in range(n):
                x -= lk[t] * H[k, i]  # Z[k, k] = D_k⁻¹ - Σ L[k, i] Z[k, i] (L4)
                i = par[i]
        else:
            for c in range(k):  # a root coordinate: no coordinate supports it
                H[k, c] = 0.0
        H[k, k] = x
        for c in range(k):
            H[c, k] = H[k, c]  # Z[c, k] = Z[k, c] (L4)


@inline
def ltdl_solve(m, H, x):
    """``x = M⁻¹ x`` with ``H = Lᵀ D L`` (L1, L2): L5-L6 on x as one column."""
    ltdl_solve_rows(m, H, ws.carve(ws.data_pointer(x), 0, (m.nv, 1))[0], 1.0)


@inline
def supports(m):
    """``Σ_k d_k``, the number of pairs (k, i) with i supporting k: L's entries below the
    diagonal, ``e_i - i - 1`` coordinates below each i."""
    n = 0
    for i in range(m.nv):
        n += m.subtree_end[m.dof_joint[i]] - i - 1
    return n


@inline
def ltdl_lower_rows(m, H, X):
    """``X = L⁻ᵀ X`` for right-hand sides X (nv, w), with ``H = Lᵀ D L``: the first sweep
    (L5) alone, which a Delassus operator ``J M⁻¹ Jᵀ = Wᵀ D⁻¹ W`` needs (L7)."""
    for i in range(m.nv - 1, -1, -1):  # W[i] = X[i] - Σ_{k below i} L[k, i] W[k] (L5)
        k, e = i + 1, m.subtree_end[m.dof_joint[i]]
        while k + 4 <= e:
            rows_subtract4(X[i], H[k, i], X[k], H[k + 1, i], X[k + 1], H[k + 2, i], X[k + 2],
                       H[k + 3, i], X[k + 3])
            k += 4
        if k + 2 <= e:
            rows_subtract2(X[i], H[k, i], X[k], H[k + 1, i], X[k + 1])
            k += 2
        if k < e:
            rows_subtract1(X[i], H[k, i], X[k])


@inline
def ltdl_solve_rows(m, H, X, scale):
    """``X = scale M⁻¹ X`` for right-hand sides X (nv, w), with ``H = Lᵀ D L`` (L5, L6):
    each sweep over a row of X takes up to four other rows at once, in loops of w that the
    compiler vectorises."""
    ltdl_lower_rows(m, H, X)
    par = m.dof_parent
    for k in range(m.nv):  # Y[k] = s D_k⁻¹ W[k] - Σ_{i supports k} L[k, i] Y[i] (L6)
        r, d = X[k], scale / H[k, k]
        for c in range(r.shape[0]):
            r[c] *= d
        i = par[k]
        while i >= 0:  # the supporting coordinates i, i1, i2, i3 in turn
            i1 = par[i]
            i2 = par[i1] if i1 >= 0 else -1
            i3 = par[i2] if i2 >= 0 else -1
            if i3 >= 0:
                rows_subtract4(r, H[k, i], X[i], H[k, i1], X[i1], H[k, i2], X[i2], H[k, i3], X[i3])
                i = par[i3]
            elif i1 >= 0:
                rows_subtract2(r, H[k, i], X[i], H[k, i1], X[i1])
                i = i2
            else:
                rows_subtract1(r, H[k, i], X[i])
                i = -1
