"""Writing a batch's large results past the caches.

A batch of ``rnea_derivatives`` writes three nv x nv matrices a sample (talos: 35 KB,
140 MB for 4096 samples), more than the caches hold, and it writes them fast. Written in
place, each cache line of the result is first read from memory, then written back, and
on two cores the batch runs at the speed of memory, not of the recursion. So its batch
(``rnea_derivatives_lanes``) has the core write each sample's results into small arrays
of its chunk, which stay in the first-level cache, and copies them out with non-temporal
stores (``kernels.lanes.stream``), which write whole lines without reading them first: on
two cores of a Xeon, 48 GB/s against 15 GB/s for ordinary stores. It does so only for
results larger than ``STREAM_FLOATS``. A batch of ``minverse`` does the same with each
group's eight matrices (``minverse_lanes``).
(``aba_derivatives`` spends twice as long on each sample, so its stores keep up with
memory, and streaming measured no faster: 9.3 against 9.1 µs a sample on talos.)
"""

from __future__ import annotations

from .._jit import inline
from ..kernels.lanes import W, boundary, load, stream

STREAM_FLOATS = 1 << 22
"""Results of a batch above this many floats (32 MiB) are streamed. Below it they mostly
stay in the last-level cache from one call to the next, where ordinary stores are faster:
``rnea_derivatives`` on 2 threads of a Xeon, µs a sample, ordinary / streamed: talos
(nv = 38) 4.2 / 4.4 at 1024 samples (34 MiB), 5.4 / 4.4 at 4096 (135 MiB); anymal
(nv = 18) 1.46 / 1.59 at 4096 (30 MiB), 1.59 / 1.59 at 16384 (122 MiB). Those are one
call repeated; between calls of other work (the benchmark's cases in turn) less stays
cached, and streaming wins earlier: talos's ``minverse`` at 4096 samples (45 MiB),
1.89-2.04 ordinary against 1.75-1.79 streamed (repeated alone: 1.61 against 1.73)."""


@inline
def stream_copy(src, dst):
    """``dst[...] = src`` (two C-contiguous matrices of one shape) by non-temporal stores;
    the numbers before ``dst``'s first 64-byte boundary and after its last are copied one
    by one (all of them, if ``dst`` is not aligned to 8 bytes). The caller ends its run of
    copies with ``lanes.fence``."""
    n, cols = dst.size, dst.shape[1]
    head = boundary(dst)
    i = n if head < 0 else min(head, n)
    for k in range(i):
        dst[k // cols, k % cols] = src[k // cols, k % cols]
    while i + W <= n:
        stream(dst, i, load(src, i))
        i += W
    for k in range(i, n):
        dst[k // cols, k % cols] = src[k // cols, k % cols]
