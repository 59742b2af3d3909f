"""Batch outputs come from ``algorithms._pool``: a buffer is reused only when no array of
an earlier result still refers to it."""

import numpy as np

import cgadyn
from cgadyn import oracle


def _address(x):
    return x.__array_interface__["data"][0]


def test_pool_reuses_only_free_buffers():
    model, _ = oracle.models("anymal", None)  # 512 x 18 x 18 floats: 1.3 MB per output
    s = oracle.sample(model, 512, np.random.default_rng(0))
    first = cgadyn.rnea_derivatives(model, s.q, s.v, s.a)
    kept = [x.copy() for x in first]
    t = oracle.sample(model, 512, np.random.default_rng(1))
    second = cgadyn.rnea_derivatives(model, t.q, t.v, t.a)
    for a, b in zip(first, kept, strict=True):
        np.testing.assert_array_equal(a, b)  # a held result is never written again
    held = second[0][3]  # a view keeps its buffer in use
    addresses = [_address(x) for x in second]
    del second
    third = cgadyn.rnea_derivatives(model, s.q, s.v, s.a)
    now = [_address(x) for x in third]
    assert addresses[0] not in now
    assert addresses[1] in now and addresses[2] in now
    for a, b in zip(third, kept, strict=True):
        np.testing.assert_array_equal(a, b)
    assert held.shape == (18, 18)
