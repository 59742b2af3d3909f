"""Per-call workspaces of the recursive algorithms, and the parallel batch loop pattern.

Each algorithm's single-sample core takes ``(packed model, sample, output, work)`` and
allocates nothing: it unpacks the model and carves its arrays out of ``work`` itself, so a
call passes a handful of arrays (each array argument is a 7-9 word struct in compiled
code). A one-sample entry point takes ``work`` from its own stack frame (``stack_buffer``:
no allocator, no reference counts, gone when the call returns) up to ``STACK_FLOATS``; a
batch allocates one heap workspace per thread chunk. Both are arrays of one type, so each
core is compiled for one signature (LLVM may still inline it differently into the single and
batch entries, so results can differ in the last bits, far below the 1e-12 asked); it reads
``work`` through a bare pointer (``data_pointer``). Concurrent calls never share memory.
"""

from __future__ import annotations

import math

import numpy as np
from numba import types
from numba.extending import overload

from .._jit import serial
from .._views import carve, data_pointer, stack_buffer

STACK_FLOATS = 8192
"""The largest workspace (64 KiB) a one-sample call takes from its stack; larger ones (ABA
beyond about 80 joints) go on the heap, so that small thread stacks never overflow."""

__all__ = ["MIN_CHUNK", "STACK_FLOATS", "all_finite", "carve", "chunks", "data_pointer",
           "require_rows", "require_sample", "row", "stack_buffer"]


@serial
def motors(n):
    return np.empty((n, 8))


@serial
def bivectors(n):
    return np.empty((n, 6))


@serial
def require_sample(n, a, b, c, out):
    """Check one sample's inputs: ``a, b, c`` of length ``n`` and finite, ``out`` of length
    ``n`` (rows). Raises a bare ``ValueError`` (shape) or ``FloatingPointError`` (NaN, inf)
    that the Python caller turns into a message naming the array and joint."""
    if a.shape[0] != n or b.shape[0] != n or c.shape[0] != n or out.shape[0] != n:
        raise ValueError("wrong input length")
    for j in range(n):
        if not (math.isfinite(a[j]) and math.isfinite(b[j]) and math.isfinite(c[j])):
            raise FloatingPointError("non-finite input")


def row(x, b):
    """``x[b]``, or ``None`` when ``x`` is None (optional per-sample inputs such as f_ext);
    compiled, the choice is made by type at compile time."""
    return None if x is None else x[b]


@overload(row, inline="always")
def _row(x, b):
    if isinstance(x, types.NoneType):
        return lambda x, b: None
    return lambda x, b: x[b]


@serial
def all_finite(x):
    """True when a C-contiguous array holds no NaN or inf (numpy's isfinite().all() costs
    microseconds on small arrays)."""
    for v in x.reshape(-1):
        if not math.isfinite(v):
            return False
    return True


@serial
def require_rows(n, arrays):
    """Check a batch's inputs (a tuple of arrays): each (B, n) with the same B, and finite.
    Raises a bare ``ValueError`` (shape) or ``FloatingPointError`` (NaN, inf) that the
    Python caller turns into a message naming the array, sample and joint."""
    for x in arrays:
        if x.shape[1] != n or x.shape[0] != arrays[0].shape[0]:
            raise ValueError("wrong input shape")
    for x in arrays:
        if not all_finite(x):
            raise FloatingPointError("non-finite input")


MIN_CHUNK = 4
"""The fewest samples a thread is given: a batch of fewer than twice this many runs as one
chunk, since waking a second thread costs about as much as computing a few samples."""


@serial
def chunks(batch, threads):
    """Split ``batch`` samples into contiguous chunks, one per thread and at least
    ``MIN_CHUNK`` samples each (one chunk for small batches): (starts, stops)."""
    t = min(max(threads, 1), max(batch // MIN_CHUNK, 1))
    size = (batch + t - 1) // t
    starts = np.empty(t, dtype=np.int64)
    stops = np.empty(t, dtype=np.int64)
    for c in range(t):
        starts[c] = min(c * size, batch)
        stops[c] = min((c + 1) * size, batch)
    return starts, stops
