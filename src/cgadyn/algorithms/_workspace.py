"""Per-call workspaces of the recursive algorithms, and the parallel batch loop pattern.

Each algorithm's single-sample core writes into a workspace it is given and allocates
nothing. A one-sample entry point takes its workspace from its own stack frame
(``stack_buffer``: no allocator, no reference counts, gone when the call returns); a
batch allocates one workspace per thread chunk on the heap. ``carve`` cuts either into
the C-contiguous arrays the core needs, so concurrent calls never share memory.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit, types
from numba.extending import intrinsic, overload


@intrinsic
def _alloca_floats(typingctx, size):
    sig = types.CPointer(types.float64)(types.intp)

    def codegen(context, builder, signature, args):
        return builder.alloca(context.get_value_type(types.float64), size=args[0])

    return sig, codegen


@intrinsic
def _advance(typingctx, pointer, offset):
    sig = pointer(pointer, types.intp)

    def codegen(context, builder, signature, args):
        return builder.gep(args[0], [args[1]])

    return sig, codegen


if numba.config.DISABLE_JIT:

    def stack_buffer(size: int) -> np.ndarray:
        """Pure Python: a heap array stands in for the stack buffer."""
        return np.empty(size)

else:
    stack_buffer = _alloca_floats
    """``size`` uninitialised floats on the stack of the compiled function that calls it,
    as a pointer for ``carve``. Valid until that function returns, so call it only in
    the body of an entry point (never in a loop, never in a helper that returns it)."""


def carve(buf, offset, shape):
    """A C-contiguous view of ``shape`` into ``buf`` at ``offset``, and the next offset.

    ``buf`` is a float64 array (the view keeps it alive) or a ``stack_buffer`` pointer
    (the view is valid while that stack frame lives). One buffer per call holds every
    array of an algorithm's workspace.
    """
    size = 1
    for s in shape:
        size *= s
    return buf[offset:offset + size].reshape(shape), offset + size


@overload(carve)
def _carve(buf, offset, shape):
    if isinstance(buf, types.CPointer):

        def on_stack(buf, offset, shape):
            size = 1
            for s in shape:
                size *= s
            return numba.carray(_advance(buf, offset), shape), offset + size

        return on_stack

    def on_heap(buf, offset, shape):
        size = 1
        for s in shape:
            size *= s
        return buf[offset:offset + size].reshape(shape), offset + size

    return on_heap


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
