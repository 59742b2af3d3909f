"""The one driver of the batches computed ``W`` samples at a time (``minverse_lanes``,
``rnea_derivatives_lanes``, ``aba_derivatives_lanes``).

A thread's chunk ``start .. stop`` of a batch goes in whole groups of ``W`` samples, each
computed at once by the algorithm's ``group``; a group that reports a fault (a quaternion, a
pivot, a result that is not finite, in any of its samples) is computed again one sample at
a time by ``single``, which reports the first fault exactly as a single call does, at its
own sample; so are the samples after the last whole group. Results written past the caches
(``_stream``) are fenced before the chunk returns.
"""

from __future__ import annotations

from .._jit import inline
from ..kernels.lanes import W, fence
from .status import OK, at_sample


@inline
def in_groups(group, single, start, stop, args):
    """Samples ``start .. stop``: ``group(b, args)`` (True when the ``W`` samples from b are
    done) for each whole group, ``single(i, args)`` (a status) for a failed group's samples
    and the tail; a status, at the sample of the first fault."""
    b = start
    while b + W <= stop:
        if not group(b, args):
            for i in range(b, b + W):  # again one at a time, for the exact fault
                s = single(i, args)
                if s != OK:
                    return at_sample(s, i)
        b += W
    for i in range(b, stop):
        s = single(i, args)
        if s != OK:
            return at_sample(s, i)
    fence()
    return OK
