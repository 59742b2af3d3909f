"""The lane intrinsics one by one (``kernels.lanes``: load, store, gather, scatter,
store_transposed, stream, boundary, lane, splat, fma) and the lanes layout's addressing
(``kernels.lane_arrays``: ``a[i]``, ``a[i, k]``, ``a[j, i, k]`` of lane views, read and
written, and a straight kernel emitted on them), each against numpy's indexing of the same
numbers. They run compiled, and under ``NUMBA_DISABLE_JIT`` through ``test_nojit.py``'s
parity runs of the algorithms that use them."""

from __future__ import annotations

import numpy as np
from numba import njit

from cgadyn.kernels import motor_mul
from cgadyn.kernels.lane_arrays import lane_array, lane_matrix, lane_tensor
from cgadyn.kernels.lanes import (
    W,
    boundary,
    fma,
    gather,
    lane,
    load,
    scatter,
    splat,
    store,
    store_transposed,
    stream,
)


def _flat(n: int) -> np.ndarray:
    return np.arange(n, dtype=float) * 1.25 - 3.0


@njit(cache=False)
def _load_store(a, out, offset):
    store(out, offset, load(a, offset))


@njit(cache=False)
def _gather_scatter(a, out, offset, stride):
    scatter(out, offset, stride, gather(a, offset, stride))


@njit(cache=False)
def _lanes_of(a, offset):
    x = load(a, offset)
    return lane(x, 0), lane(x, W - 1), lane(splat(2.5), 3)


def test_load_store_gather_scatter_move_the_numbers_numpy_indexes():
    a = _flat(200)
    out = np.zeros_like(a)
    _load_store(a, out, 13)
    assert np.array_equal(out[13:13 + W], a[13:13 + W])
    assert not out[:13].any() and not out[13 + W:].any()
    out[:] = 0.0
    _gather_scatter(a, out, 5, 17)
    idx = 5 + 17 * np.arange(W)
    assert np.array_equal(out[idx], a[idx])
    assert np.count_nonzero(out) == np.count_nonzero(a[idx])
    assert _lanes_of(a, 40) == (a[40], a[40 + W - 1], 2.5)


@njit(cache=False)
def _transpose(a, out, offset, stride):
    store_transposed(out, offset, stride, load(a, 0), load(a, W), load(a, 2 * W),
                     load(a, 3 * W), load(a, 4 * W), load(a, 5 * W), load(a, 6 * W),
                     load(a, 7 * W))


def test_store_transposed_writes_each_samples_numbers_as_one_run():
    """x_i[l] lands at offset + l stride + i: W vectors of W lanes, transposed."""
    a = _flat(W * W)
    out = np.zeros(3 + W * 11)
    _transpose(a, out, 3, 11)
    x = a.reshape(W, W)  # x[i, l]: number i of sample l
    for l in range(W):
        assert np.array_equal(out[3 + l * 11:3 + l * 11 + W], x[:, l])
    assert not out[:3].any()


@njit(cache=False)
def _stream(a, out, offset):
    stream(out, offset, load(a, 0))


@njit(cache=False)
def _fma(a, b, c):
    out = np.empty(W)
    store(out, 0, fma(load(a, 0), load(b, 0), load(c, 0)))
    return out


@njit(cache=False)
def _boundary(a):
    return boundary(a)


def test_stream_boundary_and_fma():
    a = _flat(W)
    out = np.zeros(64)
    for o in range(8):  # the numbers before the first 64-byte boundary of out[o:]
        start = _boundary(out[o:])
        assert 0 <= start < 8 and (out[o:].ctypes.data + 8 * start) % 64 == 0
    start = _boundary(out)
    _stream(a, out, start)  # a non-temporal store, at a 64-byte boundary
    assert np.array_equal(out[start:start + W], a)
    assert np.count_nonzero(out) == np.count_nonzero(a)
    odd = np.frombuffer(np.zeros(80, dtype=np.uint8), dtype=float, offset=3, count=8)
    assert _boundary(odd) == -1  # not on an 8-byte boundary: no run of whole numbers
    b, c = _flat(W) + 0.5, _flat(W) * 3.0
    assert np.allclose(_fma(a, b, c), a * b + c, rtol=1e-15, atol=0)


@njit(cache=False)
def _read_views(a, j, i, k):
    v, m, t = lane_array(a, 3), lane_matrix(a, 5, 4), lane_tensor(a, 2, 3, 4)
    out = np.empty(6 * W)
    store(out, 0, v[i])  # a vector's element
    store(out, W, m[i, k])  # a matrix's element
    store(out, 2 * W, m[i][k])  # a row, then its element
    store(out, 3 * W, t[j, i, k])  # a tensor's element
    store(out, 4 * W, t[j][i, k])  # a matrix of the tensor, then its element
    store(out, 5 * W, t[j, i][k])  # a row of the tensor, then its element
    return out


@njit(cache=False)
def _write_views(a, j, i, k, x):
    v, m, t = lane_array(a, 3), lane_matrix(a, 5, 4), lane_tensor(a, 2, 3, 4)
    v[i] = load(x, 0)
    m[i, k] = 7.0  # a number, in every lane
    t[j, i, k] = load(x, W)


def test_lane_views_address_element_offset_plus_strides_times_w():
    """Element (offset + i0 s0 + i1 s1 + i2) W of the flat array: ``a[i]`` of a vector,
    ``a[i, k]`` of a matrix (row stride ``cols``), ``a[j, i, k]`` of a tensor (``rows``
    x ``cols`` a matrix), through every way of indexing them."""
    a = _flat(W * 80)
    lanes = a.reshape(-1, W)  # lanes[x]: the W samples of element x
    j, i, k = 2, 1, 3
    got = _read_views(a, j, i, k).reshape(6, W)
    assert np.array_equal(got[0], lanes[3 + i])
    assert np.array_equal(got[1], lanes[5 + i * 4 + k])
    assert np.array_equal(got[2], lanes[5 + i * 4 + k])
    for r in (3, 4, 5):
        assert np.array_equal(got[r], lanes[2 + j * 12 + i * 4 + k])
    b = np.zeros_like(a)
    x = _flat(2 * W) + 100.0
    _write_views(b, j, i, k, x)
    written = b.reshape(-1, W)
    assert np.array_equal(written[3 + i], x[:W])
    assert np.array_equal(written[5 + i * 4 + k], np.full(W, 7.0))
    assert np.array_equal(written[2 + j * 12 + i * 4 + k], x[W:])
    assert np.count_nonzero(np.abs(written).sum(axis=1)) == 3


_CORE = {"cache": False, "fastmath": {"contract"}, "error_model": "numpy"}  # as _jit.core


@njit(**_CORE)
def _motor_products(a, b, out, offset):
    motor_mul(lane_matrix(a, offset, 8)[1], lane_matrix(b, offset, 8)[2],
                  lane_matrix(out, offset, 8)[3])


@njit(**_CORE)
def _motor_product(a, b, out):
    motor_mul(a, b, out)


def test_an_emitted_kernel_on_lane_views_equals_it_per_sample():
    """A generated kernel on lane views (emitted by ``kernels.straight`` through the same
    addressing) gives, in every lane, bit for bit, the kernel's numbers on that sample's
    motors compiled as a core compiles them."""
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(W * 40,)), rng.normal(size=(W * 40,))
    out = np.zeros(W * 40)
    _motor_products(a, b, out, 2)
    A, B, O = (x.reshape(-1, W) for x in (a, b, out))
    for s in range(W):
        want = np.empty(8)
        _motor_product(A[2 + 8:2 + 16, s].copy(), B[2 + 16:2 + 24, s].copy(), want)
        assert np.array_equal(O[2 + 24:2 + 32, s], want)
