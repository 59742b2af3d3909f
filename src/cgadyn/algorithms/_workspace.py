"""Per-call workspaces of the recursive algorithms, and the chunks of a parallel batch.

Each algorithm's core takes the unpacked model, one sample, its outputs and ``work`` and
allocates nothing: it carves its arrays out of ``work`` (``carve``, bare views through the
pointer ``data_pointer(work)``). A one-sample entry takes ``work`` from its own stack frame
(``stack_buffer``: no allocator, no reference counts, gone when the call returns) up to
``STACK_FLOATS``; a batch allocates one heap workspace per chunk of samples. Both are arrays
of one type, so each core is compiled for one signature. Concurrent calls never share
memory. Each core module declares its arrays once, by name and shape, in ``WORKSPACE``;
``tools/generate_workspaces.py`` writes from it ``work/<module>.py``, with the size, the
carving into a named tuple and the lane twin (``docs/architecture.md``, "Workspaces").
"""

from __future__ import annotations

import numpy as np

from .._jit import serial
from .._views import bare_view, carve, data_pointer, stack_buffer

STACK_FLOATS = 8192
"""The largest workspace (64 KiB) a one-sample call takes from its stack; larger ones (ABA
beyond about 80 joints) go on the heap, so that small thread stacks never overflow."""

MIN_CHUNK = 4
"""The fewest samples a thread is given: a batch of fewer than twice this many runs as one
chunk, since waking a second thread costs about as much as computing a few samples."""

__all__ = ["MIN_CHUNK", "STACK_FLOATS", "bare_view", "carve", "chunks", "data_pointer",
           "stack_buffer"]


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
