"""``sim.pages.zeros``: the rollouts' contact records, zeros that cost only the pages
written."""

from __future__ import annotations

import gc
import os

import numpy as np
import pytest

from cgadyn.sim import pages


def test_small_and_large_are_writable_zeros_of_their_shape():
    for shape in ((3, 0, 5, 3), (2, 4), (4, 3, 1001, 3 * 64)):
        x = pages.zeros(shape)
        assert x.shape == shape and x.dtype == np.float64 and x.flags.writeable
        assert not np.any(x)
        if x.size:
            x[(-1,) * len(shape)] = 2.5
            assert x.sum() == 2.5


def test_a_view_outlives_the_array_it_was_taken_of():
    view = pages.zeros((64, 1 << 14))[:, ::2].T
    gc.collect()
    view[-1, -1] = 1.0
    assert view.sum() == 1.0 and view.shape == (1 << 13, 64)


def _resident_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs Linux's /proc")
def test_a_stream_written_costs_its_pages_not_the_huge_pages_around_it():
    # one float written every 2 MiB of 256 MiB: with huge pages the whole 256 MiB becomes
    # resident, with small pages 128 pages of 4 KiB
    x = pages.zeros((128, 1 << 18))
    before = _resident_bytes()
    x[:, 0] = 1.0
    grown = _resident_bytes() - before
    assert grown < 16 << 20, f"writing 128 floats made {grown} bytes resident"
