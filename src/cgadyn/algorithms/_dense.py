"""Small dense linear algebra for compiled cores: the inverse of a joint's inertia D_j, and
row operations ``r -= Σ a_t x_t`` over up to four rows at once (four multiply-adds per
load and store of r, in loops the compiler vectorises)."""

from __future__ import annotations

from .._jit import inline


@inline
def spd_inverse(a, k, out):
    """``out[:k, :k] = a[:k, :k]⁻¹`` for a symmetric positive definite ``a`` (k <= 6), by
    Gauss-Jordan elimination without pivoting, which is stable for such matrices; ``a`` is
    overwritten. Returns False when a pivot is not positive (``a`` is not positive
    definite), leaving ``out`` meaningless. The pivots are those of ``a = L D Lᵀ``."""
    for i in range(k):
        for j in range(k):
            out[i, j] = 1.0 if i == j else 0.0
    for p in range(k):
        pivot = a[p, p]
        if not pivot > 0.0:
            return False
        r = 1.0 / pivot
        for j in range(k):
            a[p, j] *= r
            out[p, j] *= r
        for i in range(k):
            if i != p:
                f = a[i, p]
                for j in range(k):
                    a[i, j] -= f * a[p, j]
                    out[i, j] -= f * out[p, j]
    return True


@inline
def rows_subtract4(r, a0, x0, a1, x1, a2, x2, a3, x3):
    """``r -= a0 x0 + a1 x1 + a2 x2 + a3 x3`` on rows: four multiply-adds per load and store
    of r."""
    for c in range(r.shape[0]):
        r[c] -= a0 * x0[c] + a1 * x1[c] + a2 * x2[c] + a3 * x3[c]


@inline
def rows_subtract2(r, a0, x0, a1, x1):
    """``r -= a0 x0 + a1 x1`` on rows."""
    for c in range(r.shape[0]):
        r[c] -= a0 * x0[c] + a1 * x1[c]


@inline
def rows_subtract1(r, a0, x0):
    """``r -= a0 x0`` on rows."""
    for c in range(r.shape[0]):
        r[c] -= a0 * x0[c]
