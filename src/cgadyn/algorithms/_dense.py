"""Small dense linear algebra for compiled cores: Cholesky's factor of a symmetric positive
definite matrix and the solve with it (the constraint core's, ADMM's, the IK's), the
inverse of a joint's inertia D_j,
row operations ``r -= Σ a_t x_t`` over up to four rows at once (four multiply-adds per
load and store of r, in loops the compiler vectorises), and the product ``-A X`` in blocks
held in vector registers."""

from __future__ import annotations

import math

from .._jit import inline
from ..kernels.lane_arrays import positive
from ..kernels.lanes import W, fnma, load, splat, store


@inline
def cholesky(A, n, pivot):
    """Cholesky ``A = L Lᵀ`` in place: L below the diagonal, the reciprocals ``1 / L_aa`` on
    it (so that ``cholesky`` and ``cholesky_substitute`` multiply, one division per row); the first
    row whose pivot² falls below ``pivot`` times its count of rows, or -1."""
    for a in range(n):
        for c in range(a + 1):
            acc = A[a, c]
            for k in range(c):
                acc -= A[a, k] * A[c, k]
            if a == c:
                if not acc > pivot * (a + 1):
                    return a
                A[a, a] = 1.0 / math.sqrt(acc)
            else:
                A[a, c] = acc * A[c, c]
    return -1


@inline
def cholesky_substitute(L, n, x):
    """``x = (L Lᵀ)⁻¹ x`` in place, L from ``cholesky``."""
    for a in range(n):
        acc = x[a]
        for k in range(a):
            acc -= L[a, k] * x[k]
        x[a] = acc * L[a, a]
    for a in range(n - 1, -1, -1):
        acc = x[a]
        for k in range(a + 1, n):
            acc -= L[k, a] * x[k]
        x[a] = acc * L[a, a]


@inline
def spd_inverse(a, k, out):
    """``out[:k, :k] = a[:k, :k]⁻¹`` for a symmetric positive definite ``a`` (k <= 6), by
    Gauss-Jordan elimination without pivoting, which is stable for such matrices; ``a`` is
    overwritten. Returns False when a pivot is not positive (``a`` is not positive
    definite) or its inverse not finite, leaving ``out`` meaningless. The pivots are those
    of ``a = L D Lᵀ``. Only arithmetic and ``positive``: it runs on numbers, or on ``W``
    samples at once (``kernels.lane_arrays``)."""
    for i in range(k):
        for j in range(k):
            out[i, j] = 1.0 if i == j else 0.0
    for p in range(k):
        pivot = a[p, p]
        if not positive(pivot):
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


@inline
def minus_product(A, X, h, out):
    """``out = -A X[:, h : h + n]`` for ``A`` (n, n), ``X`` (n, w) and ``out`` (n, n), all
    C-contiguous, ``n >= W``. A block of four rows by ``W`` columns of ``out`` accumulates
    in four vector registers over the whole sum (``kernels/lanes.py``), each load of ``W``
    numbers of X serving four rows of A and nothing stored until the block is done; the
    last block of rows and of columns overlaps the one before it (its numbers are written
    twice, the same)."""
    n, w = A.shape[0], X.shape[1]
    zero = splat(0.0)
    i = 0
    while i < n:
        i = min(i, n - 4)
        c = 0
        while c < n:
            c = min(c, n - W)
            a0, a1, a2, a3 = zero, zero, zero, zero
            for k in range(n):
                x = load(X, k * w + h + c)
                a0 = fnma(splat(A[i, k]), x, a0)
                a1 = fnma(splat(A[i + 1, k]), x, a1)
                a2 = fnma(splat(A[i + 2, k]), x, a2)
                a3 = fnma(splat(A[i + 3, k]), x, a3)
            store(out, i * n + c, a0)
            store(out, (i + 1) * n + c, a1)
            store(out, (i + 2) * n + c, a2)
            store(out, (i + 3) * n + c, a3)
            c += W
        i += 4
