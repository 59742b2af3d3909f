"""``_threads.in_chunks``: every index of a batch once, on as many threads as numba has, and
a chunk's exception raised on the calling thread."""

from __future__ import annotations

import threading

import numba
import numpy as np
import pytest

from cgadyn._threads import in_chunks


@pytest.mark.parametrize("batch", [1, 2, 3, 7, 64])
@pytest.mark.parametrize("threads", [1, 2])
def test_every_index_once_in_contiguous_chunks(batch, threads):
    saved = numba.get_num_threads()
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        seen = np.zeros(batch, dtype=int)
        chunks, where = [], set()

        def run(b0, b1):
            chunks.append((b0, b1))
            where.add(threading.get_ident())
            seen[b0:b1] += 1

        in_chunks(run, batch)
        expected = min(numba.get_num_threads(), batch)
    finally:
        numba.set_num_threads(saved)
    assert seen.tolist() == [1] * batch
    assert len(chunks) == expected and len(where) == expected
    assert all(b1 - b0 >= batch // expected for b0, b1 in chunks)


def test_a_chunks_exception_is_raised_on_the_calling_thread():
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one thread only")
    saved = numba.get_num_threads()
    numba.set_num_threads(2)
    done = []

    def run(b0, b1):
        if b0 > 0:
            raise RuntimeError(f"chunk from {b0} failed")
        done.append(b0)

    try:
        with pytest.raises(RuntimeError, match="chunk from 5 failed"):
            in_chunks(run, 10)
    finally:
        numba.set_num_threads(saved)
    assert done == [0]  # the other chunk ran to its end
