"""Reuse of batch outputs that no caller holds any more.

A batch of 4096 samples writes megabytes of results (three (B, nv, nv) matrices for the
derivatives: 32 MB on an 18-dof robot). Memory fresh from the operating system costs a page
fault and the kernel's zeroing on its first write, and the C allocator hands large blocks
back to the system when they are freed, so every batch paid that again: about 0.7 µs per
sample for the rnea derivatives of a quadruped, a sixth to a third of the batch's time.
Here each large output is a view of a buffer that the pool keeps; once every array of a
result (and every view of it) is gone, the buffer's reference count says so and the next
batch of the same size writes into it, already mapped. Buffers still referenced are never
handed out again. At most ``LIMIT`` bytes are kept; a buffer in use when that is exceeded is
simply forgotten (it lives on in its arrays)."""

from __future__ import annotations

import sys
import threading

import numpy as np

LIMIT = 256 * 2**20
"""Bytes of buffers the pool keeps at most."""
SMALL = 2**20
"""Outputs below this many bytes are allocated as usual (the allocator reuses them)."""

_buffers: list[np.ndarray] = []
_lock = threading.Lock()
_FREE = 3
"""``sys.getrefcount`` of a buffer that nobody else holds: the pool's list, the loop
variable and the call's own argument."""


def empty(shape: tuple[int, ...]) -> np.ndarray:
    """An uninitialised float64 array of ``shape``, from a free buffer of the pool when one
    of the same size exists."""
    size = 1
    for d in shape:
        size *= d
    if 8 * size < SMALL:
        return np.empty(shape)
    with _lock:
        for raw in _buffers:
            if raw.size == size and sys.getrefcount(raw) == _FREE:
                return raw.reshape(shape)
        raw = np.empty(size)
        _buffers.append(raw)
        total = sum(b.nbytes for b in _buffers)
        i = 0
        while total > LIMIT and i < len(_buffers) - 1:  # the oldest first, never the new one
            old = _buffers[i]
            total -= old.nbytes
            del _buffers[i]
            del old
        return raw.reshape(shape)
