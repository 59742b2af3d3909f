"""The inverse mass matrix ``M(q)⁻¹`` from M (``crba``) and its factorisation along the tree;
``docs/derivatives.md`` derives it (M1-M4).

M has the sparsity of the kinematic tree (Featherstone's expanded tree, one node per
velocity coordinate, ``dof_parent`` λ): ``M[k, i]`` for ``i < k`` is zero unless i
supports k. Eliminating from the leaves keeps that pattern:

    M = Lᵀ D L,   L unit lower triangular, L[k, i] ≠ 0 only for i supporting k         (M1)
    for k = nv-1..0, i = λ(k), λ(λ(k)), ...:
        L[k, i] = M[k, i] / D_k,   M[i, j] -= L[k, i] M[k, j]   (j = i, λ(i), ...)     (M2)

with ``D_k`` the diagonal left once k's descendants are eliminated (Featherstone's LTDL).
Then ``Z = M⁻¹`` solves ``L Z = D⁻¹ L⁻ᵀ``, whose right side is upper triangular with
diagonal ``D⁻¹``; row by row, k = 0..nv-1, from the rows of the coordinates supporting k:

    Z[k, c] = -Σ_{i supports k} L[k, i] Z[i, c]                  for c < k         (M3)
    Z[k, k] = D_k⁻¹ - Σ_{i supports k} L[k, i] Z[k, i],   Z[c, k] = Z[k, c]           (M4)

The cost beyond crba is ``Σ_k k d_k`` (``d_k`` the number of coordinates supporting k), and
every entry is written once, where the articulated-body recursion (Pinocchio's
``computeMinverse``) carries a 6-vector per column through every joint.
"""

from __future__ import annotations

import math

from .._jit import core, inline
from . import _workspace as ws
from ._checks import check_result
from .crba import crba_core
from .crba import workspace_size as crba_size
from .status import OK, SINGULAR, fault


@inline
def ltdl(m, H):
    """``H = M`` into ``Lᵀ D L`` in place (M1, M2): L below the diagonal, D on it; the rest
    of the lower triangle (pairs on different branches) stays as it was (zero). Returns -1,
    or the first coordinate whose pivot is not positive."""
    par = m.dof_parent
    for k in range(m.nv - 1, -1, -1):
        d = H[k, k]
        if not (d > 0.0 and math.isfinite(d)):
            return k
        i = par[k]
        while i >= 0:
            a = H[k, i] / d  # L[k, i] (M2)
            j = i
            while j >= 0:
                H[i, j] -= a * H[k, j]  # M[i, j] -= L[k, i] M[k, j]
                j = par[j]
            H[k, i] = a
            i = par[i]
    return -1


@inline
def ltdl_inverse(m, H, lk):
    """``H = Lᵀ D L`` (``ltdl``'s result) into ``M⁻¹``, full and symmetric, in place (M3,
    M4); ``lk`` (nv) scratch for the L entries of one row, which that row's result
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
                H[k, c] = -a * H[i, c]  # Z[k, c] = -Σ L[k, i] Z[i, c] (M3)
            for t in range(1, n):
                i = par[i]
                a = lk[t]
                for c in range(k):
                    H[k, c] -= a * H[i, c]
            i = par[k]
            for t in range(n):
                x -= lk[t] * H[k, i]  # Z[k, k] = D_k⁻¹ - Σ L[k, i] Z[k, i] (M4)
                i = par[i]
        else:
            for c in range(k):  # a root coordinate: no coordinate supports it
                H[k, c] = 0.0
        H[k, k] = x
        for c in range(k):
            H[c, k] = H[k, c]  # Z[c, k] = Z[k, c] (M4)


@inline
def minverse_from_mass(m, H, lk):
    """``H = M`` into ``M⁻¹`` in place (M1-M4); a status (a singular joint when a pivot
    is not positive)."""
    k = ltdl(m, H)
    if k >= 0:
        return fault(SINGULAR, m.dof_joint[k])
    ltdl_inverse(m, H, lk)
    return OK


@core
def minverse_core(m, q, Minv, option, work):
    """``Minv = M(q)⁻¹`` (nv, nv), full and symmetric."""
    lk, rest = _workspace(ws.data_pointer(work), m)
    status = crba_core(m, q, Minv, option, rest)  # M (checks q and that M is finite)
    if status != OK:
        return status
    status = minverse_from_mass(m, Minv, lk)
    if status != OK:
        return status
    return check_result(Minv)


@inline
def workspace_size(n, nq, nv, nl):
    return nv + crba_size(n, nq, nv, nl)


@inline
def _workspace(buf, m):
    """One row of L (nv), then crba's workspace."""
    lk, o = ws.carve(buf, 0, (m.nv,))
    rest, o = ws.carve(buf, o, (crba_size(m.n, m.nq, m.nv, m.nl),))
    return lk, rest
