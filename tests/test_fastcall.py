"""The one-sample fast path: any accepted input gives the canonical answer, nothing new is
compiled for odd inputs, and the packed model and stack workspaces hold what they should."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit, types

import cgadyn
from cgadyn.algorithms import api
from cgadyn.cga.conventions import motion_from_twist
from cgadyn.multibody import build_model
from cgadyn.multibody.packed import unpack, with_gravity

PANDA = cgadyn.load("panda")
RNG = np.random.default_rng(11)
Q, V, A = (RNG.uniform(-1, 1, 9) for _ in range(3))


def variants(x: np.ndarray) -> list:
    """The same numbers in forms that are not the canonical float64 C-contiguous array."""
    strided = np.zeros(18)
    strided[::2] = x
    readonly = x.copy()
    readonly.setflags(write=False)
    return [x.tolist(), tuple(x), memoryview(x.copy()),
            strided[::2], readonly, np.asfortranarray(x[None])[0], x.astype(np.longdouble)]


@pytest.mark.parametrize("k", range(7))
def test_odd_inputs_give_the_canonical_answer(k):
    want = (cgadyn.rnea(PANDA, Q, V, A), cgadyn.aba(PANDA, Q, V, A), cgadyn.crba(PANDA, Q))
    q, v, a = (variants(x)[k] for x in (Q, V, A))
    got = (cgadyn.rnea(PANDA, q, v, a), cgadyn.aba(PANDA, q, v, a), cgadyn.crba(PANDA, q))
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g, w, rtol=1e-13, atol=1e-13)
        assert g.dtype == np.float64 and g.flags.c_contiguous and g.flags.writeable


def test_integer_and_float32_inputs_are_converted():
    qi = np.arange(9) % 2
    np.testing.assert_allclose(cgadyn.rnea(PANDA, qi, qi, qi),
                               cgadyn.rnea(PANDA, qi.astype(float), qi * 1.0, qi * 1.0))
    q32 = Q.astype(np.float32)
    np.testing.assert_allclose(cgadyn.aba(PANDA, q32, V, A),
                               cgadyn.aba(PANDA, q32.astype(np.float64), V, A))


def test_odd_inputs_compile_nothing_new():
    """Only the canonical signatures exist after calls with lists, views and other dtypes."""
    for k in range(7):
        q = variants(Q)[k]
        cgadyn.rnea(PANDA, q, q, q)
        cgadyn.aba(PANDA, q, q, q)
        cgadyn.crba(PANDA, q)
    for entry in (api._RNEA, api._ABA, api._CRBA):
        assert len(entry.dispatcher.signatures) == 1, entry.dispatcher.signatures


def batch_variants(x: np.ndarray) -> list:
    """The same (B, n) numbers in forms that are not the canonical float64 C-contiguous
    array."""
    strided = np.zeros((x.shape[0], 2 * x.shape[1]))
    strided[:, ::2] = x
    readonly = x.copy()
    readonly.setflags(write=False)
    return [x.tolist(), np.asfortranarray(x), strided[:, ::2], readonly, x.astype(np.float32)]


SAME = {"rtol": 1e-13, "atol": 1e-13}
"""Single and batch entries compile the same core into different callers, where fused
multiply-adds may land differently: last-bit differences, far inside the 1e-12 asked."""


@pytest.mark.parametrize("batch", [1, 2, 7, 8, 9, 64])
def test_batches_equal_their_rows(batch):
    """Small batches run on the calling thread, larger ones in chunks of MIN_CHUNK or more:
    every split gives each row's one-sample answer."""
    rng = np.random.default_rng(batch)
    q, v, a = (rng.uniform(-1, 1, (batch, 9)) for _ in range(3))
    for name, args in (("rnea", (q, v, a)), ("aba", (q, v, a)), ("crba", (q,))):
        f = getattr(cgadyn, name)
        rows = np.array([f(PANDA, *(x[b] for x in args)) for b in range(batch)])
        np.testing.assert_allclose(f(PANDA, *args), rows, err_msg=name, **SAME)


@pytest.mark.parametrize("k", range(5))
def test_odd_batches_give_the_canonical_answer_and_compile_nothing_new(k):
    q, v, a = (RNG.uniform(-1, 1, (3, 9)) for _ in range(3))
    want = (cgadyn.rnea(PANDA, q, v, a), cgadyn.aba(PANDA, q, v, a), cgadyn.crba(PANDA, q))
    oq, ov, oa = (batch_variants(x)[k] for x in (q, v, a))
    got = (cgadyn.rnea(PANDA, oq, ov, oa), cgadyn.aba(PANDA, oq, ov, oa),
           cgadyn.crba(PANDA, oq))
    tol = 1e-6 if k == 4 else 1e-13  # float32 inputs
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g, w, rtol=tol, atol=tol)
        assert g.dtype == np.float64 and g.flags.c_contiguous
    for entry in (api._RNEA_B, api._ABA_B, api._CRBA_B):  # (f_ext None or an array)
        for signature in entry.dispatcher.signatures:
            arrays = [t for t in signature if isinstance(t, types.Array)]
            assert all(t.dtype == types.float64 and t.layout == "C" and t.mutable
                       for t in arrays), signature


def test_bad_batches_are_explained():
    q = RNG.uniform(-1, 1, (5, 9))
    bad = q.copy()
    bad[3, 4] = np.nan
    nan_at = r"q contains NaN or inf at index \(3, 4\) \(joint 'panda_joint5'\)"
    with pytest.raises(ValueError, match=nan_at):
        cgadyn.rnea(PANDA, bad, q, q)
    with pytest.raises(ValueError, match="q"):
        cgadyn.crba(PANDA, bad)
    with pytest.raises(ValueError, match="9"):
        cgadyn.aba(PANDA, q[:, :8], q[:, :8], q[:, :8])
    with pytest.raises(ValueError):
        cgadyn.rnea(PANDA, q, q[:4], q)


def test_outputs_are_fresh_arrays():
    a, b = cgadyn.rnea(PANDA, Q, V, A), cgadyn.rnea(PANDA, Q, V, A)
    assert a is not b and not np.shares_memory(a, b)
    a[:] = 0.0
    np.testing.assert_array_equal(b, cgadyn.rnea(PANDA, Q, V, A))


@njit
def _unpacked(packed):
    parents, types, placements, axes, inertias, base = unpack(packed)
    return parents.copy(), types.copy(), placements.copy(), axes.copy(), inertias.copy(), \
        base.copy()


def test_packed_model_unpacks_to_its_fields():
    for name in ("panda", "gripper", "ur5"):
        m = cgadyn.load(name)
        parents, types, placements, axes, inertias, base = _unpacked(m.packed)
        np.testing.assert_array_equal(parents, m.parents)
        np.testing.assert_array_equal(types, m.joint_types)
        np.testing.assert_array_equal(placements, m.placements)
        np.testing.assert_array_equal(axes, m.axes)
        np.testing.assert_array_equal(inertias, m.inertias)
        # V̇_0 = -g: the twist of an upward linear acceleration of 9.81
        np.testing.assert_allclose(motion_from_twist(base), [0, 0, 9.81, 0, 0, 0])
        moon = _unpacked(with_gravity(m.packed, (0.0, 0.0, -1.62)))[5]
        np.testing.assert_allclose(motion_from_twist(moon), [0, 0, 1.62, 0, 0, 0])


def _chain(n: int) -> cgadyn.Model:
    """A serial chain of n revolute joints with random axes, placements and bodies."""
    rng = np.random.default_rng(n)
    placements = np.tile(np.eye(4), (n, 1, 1))
    placements[:, :3, 3] = rng.uniform(-0.2, 0.2, (n, 3))
    inertia = np.tile(np.diag([0.02, 0.03, 0.04]), (n, 1, 1))
    return build_model(
        f"chain{n}", [f"j{i}" for i in range(n)], ["revolute"] * n, list(range(-1, n - 1)),
        placements, rng.normal(size=(n, 3)), rng.uniform(0.5, 2.0, n),
        rng.uniform(-0.05, 0.05, (n, 3)), inertia,
    )


@pytest.mark.parametrize("n", [60, 300])
def test_long_chains_agree_with_the_batch_path(n):
    """60 joints (one-sample workspaces on the stack) and 300 (on the heap): the one-sample
    entries equal the batch entries (per-thread heap workspace) and RNEA inverts ABA."""
    m = _chain(n)
    rng = np.random.default_rng(5)
    q, v, tau = (rng.uniform(-1, 1, (4, n)) for _ in range(3))
    single = np.array([cgadyn.aba(m, q[b], v[b], tau[b]) for b in range(4)])
    np.testing.assert_allclose(cgadyn.aba(m, q, v, tau), single, rtol=1e-12,
                               atol=1e-12 * np.abs(single).max())
    np.testing.assert_allclose(cgadyn.rnea(m, q[0], v[0], single[0]), tau[0], rtol=1e-8,
                               atol=1e-8 * np.abs(tau[0]).max())
    H = cgadyn.crba(m, q[1])
    np.testing.assert_allclose(cgadyn.crba(m, q[:3])[1], H, rtol=1e-12,
                               atol=1e-12 * np.abs(H).max())
