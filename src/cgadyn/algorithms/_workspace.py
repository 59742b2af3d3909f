"""Per-call workspaces of the recursive algorithms, and the parallel batch loop pattern.

Each algorithm's single-sample core writes into a workspace it is given and allocates
nothing; the Python-facing function allocates one workspace per call, and a batch
allocates one per thread chunk, so concurrent calls never share memory.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def carve(buf, offset, shape):
    """A C-contiguous view of ``shape`` into ``buf`` at ``offset``, and the next offset.

    One allocation per call holds every array of an algorithm's workspace.
    """
    size = 1
    for s in shape:
        size *= s
    return buf[offset:offset + size].reshape(shape), offset + size


@njit(cache=True, nogil=True)
def motors(n):
    return np.empty((n, 8))


@njit(cache=True, nogil=True)
def bivectors(n):
    return np.empty((n, 6))


@njit(cache=True, nogil=True)
def inertias(n):
    return np.empty((n, 6, 6))


@njit(cache=True, nogil=True)
def require_finite(a, b, c):
    """Raise ``FloatingPointError`` when an input holds NaN or inf (explained by the caller)."""
    for j in range(a.shape[0]):
        if not (math.isfinite(a[j]) and math.isfinite(b[j]) and math.isfinite(c[j])):
            raise FloatingPointError("non-finite input")


@njit(cache=True, nogil=True)
def all_finite(x):
    """True when a C-contiguous array holds no NaN or inf (numpy's isfinite().all() costs
    microseconds on small arrays)."""
    for v in x.reshape(-1):
        if not math.isfinite(v):
            return False
    return True


@njit(cache=True, nogil=True)
def chunks(batch, threads):
    """Split ``batch`` samples into one contiguous chunk per thread: (starts, stops)."""
    t = min(max(threads, 1), max(batch, 1))
    size = (batch + t - 1) // t
    starts = np.empty(t, dtype=np.int64)
    stops = np.empty(t, dtype=np.int64)
    for c in range(t):
        starts[c] = min(c * size, batch)
        stops[c] = min((c + 1) * size, batch)
    return starts, stops
