"""Output blocks of batch calls, kept for reuse once the caller has let go of them.

A batch of derivatives on a large robot returns a block of a hundred MiB or more (talos,
4096 samples of ``rnea_derivatives``: 142 MiB). The kernel maps a fresh block page by page
and zeroes each page on its first touch, a cost that grows with the block and that the
batch's arithmetic does not hide; a block that an earlier call returned and its caller has
since dropped is mapped already. So the blocks of batch outputs are kept here, up to
``KEEP_BYTES`` in all, the newest last, and a call takes a kept block of its size once
nothing but this module refers to it: every output array is a view of its block and holds
a reference to it, so a block is reused only when no result of its call is alive. A caller
that keeps its results gets new blocks, and this module never holds more than
``KEEP_BYTES``.
"""

from __future__ import annotations

import sys
import threading

import numpy as np

KEEP_BYTES = 256 << 20
"""The most memory that kept blocks hold (a batch of 4096 talos derivatives needs 142 MiB)."""

MIN_BYTES = 1 << 20
"""Blocks below this size are not kept: the allocator reuses small freed memory itself."""

_kept: list[np.ndarray] = []
_lock = threading.Lock()


def block(floats: int) -> np.ndarray:
    """A float64 array of ``floats`` elements with undefined contents: a kept block of that
    size that nothing else refers to, else a new one (kept if it is large enough, dropping
    the oldest kept blocks beyond ``KEEP_BYTES``)."""
    if floats * 8 < MIN_BYTES:
        return np.empty(floats)
    with _lock:
        for i in range(len(_kept)):
            # references: the list and the call's argument, so no result of it is alive
            if _kept[i].size == floats and sys.getrefcount(_kept[i]) == 2:
                b = _kept.pop(i)
                _kept.append(b)
                return b
        b = np.empty(floats)
        if b.nbytes <= KEEP_BYTES:
            _kept.append(b)
            while sum(k.nbytes for k in _kept) > KEEP_BYTES:
                del _kept[0]
        return b


def kept_bytes() -> int:
    """The memory that kept blocks hold now."""
    with _lock:
        return sum(k.nbytes for k in _kept)
