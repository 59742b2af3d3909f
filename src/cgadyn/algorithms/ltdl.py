"""M's factorisation along the tree and its inverse from it (Featherstone's LTDL):
``aba_derivatives`` has M already (the rnea derivatives' ∂τ/∂a) and gets q̈ and M⁻¹ from it
(``docs/derivatives.md``, L1-L4 and D13); ``minverse`` alone runs the articulated-body
recursion instead (M1-M5).

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

The cost is ``Σ_k k d_k`` (``d_k`` the number of coordinates supporting k).
"""

from __future__ import annotations

import math

from .._jit import inline

__all__ = ["ltdl", "ltdl_inverse", "ltdl_solve"]


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
    """``x = M⁻¹ x`` with ``H = Lᵀ D L`` (L1, L2): ``Lᵀ y = x`` from the leaves, ``D⁻¹``,
    then ``L z = y`` from the root."""
    par = m.dof_parent
    for k in range(m.nv - 1, -1, -1):
        i = par[k]
        while i >= 0:
            x[i] -= H[k, i] * x[k]
            i = par[i]
    for k in range(m.nv):
        x[k] /= H[k, k]
    for k in range(m.nv):
        i = par[k]
        while i >= 0:
            x[k] -= H[k, i] * x[i]
            i = par[i]
