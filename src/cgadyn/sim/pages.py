"""Zero arrays whose memory costs only the pages written: the rollouts' contact records.

A rollout with a world records, per contact slot and per joint coordinate, a stream of
forces over its steps (``rollout._keep_contacts``), slot- and coordinate-major, into zeros
that nothing writes where no contact, limit or friction loss acts. Fresh anonymous memory
is zero without being written: the kernel maps a zeroed page on the first write into it.
So a stream never written costs no memory and no time, provided the pages are small.

numpy asks the kernel for transparent huge pages (``madvise(MADV_HUGEPAGE)``) on every
allocation of 4 MiB or more, and the kernel then zeroes 2 MiB at the first write into
any of it: a rollout's whole record (56 slots of 1001 steps of the Ant are 1.3 MiB) is
zeroed because one foot touched the ground. ``zeros`` maps the memory itself and asks
for small pages (``MADV_NOHUGEPAGE``, where the platform has it), so that only the
streams written are paid for. The array owns the mapping: it is unmapped when the last
view of it goes.
"""

from __future__ import annotations

import mmap

import numpy as np

SMALL = 1 << 22
"""Bytes below which ``zeros`` is ``np.zeros``: numpy asks for no huge pages there."""


def zeros(shape: tuple[int, ...]) -> np.ndarray:
    """A float64 array of zeros of ``shape``, in pages that the kernel maps, zeroed, at
    their first write (4 KiB on Linux, not 2 MiB)."""
    size = int(np.prod(shape, dtype=np.int64)) * 8
    if size < SMALL:
        return np.zeros(shape)
    memory = mmap.mmap(-1, size)
    advice = getattr(mmap, "MADV_NOHUGEPAGE", None)
    if advice is not None:
        memory.madvise(advice)
    return np.frombuffer(memory, dtype=np.float64).reshape(shape)
