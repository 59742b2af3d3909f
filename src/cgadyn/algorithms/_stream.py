"""Writing a batch's large results past the caches.

A batch of ``rnea_derivatives`` writes three nv x nv matrices a sample (talos: 35 KB,
140 MB for 4096 samples), more than the caches hold, and it writes them fast. Written in
place, each cache line of the result is first read from memory, then written back, and
on two cores the batch runs at the speed of memory, not of the recursion. So its batch
(``rnea_derivatives_lanes``) has the core write each sample's results into small arrays
of its chunk, which stay in the first-level cache, and copies them out with non-temporal
stores (``kernels.lanes.stream``), which write whole lines without reading them first,
so that memory carries each line once instead of twice. It does so only for results larger
than ``STREAM_FLOATS``. A batch of ``minverse`` does the same with each group's eight
matrices (``minverse_lanes``). (``aba_derivatives`` computes longer on each sample, so its
ordinary stores keep up with memory, and it does not stream.)
"""

from __future__ import annotations

from .._jit import inline
from ..kernels.lanes import W, boundary, load, stream

STREAM_FLOATS = 1 << 22
"""Results of a batch above this many floats (32 MiB) are streamed. Below it a result
mostly stays in the last-level cache from one call to the next, and ordinary stores, which
keep it there, are the better choice; above it the result cannot stay cached, and streaming
saves the read of every line. Near the threshold the two are close; it is set where
streaming won between calls of other work (the benchmark's cases in turn), where less of a
result stays cached than when one call is repeated (the commit that set it records the
measurements)."""


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
