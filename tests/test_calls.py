"""The path of a call (``cgadyn.algorithms.calls``): the fast C path and the checked path
give the same answers on any accepted input, compile one signature per entry, and the packed
model and workspaces hold what they should."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from numba import njit

import cgadyn
from cgadyn.algorithms.calls import ENTRIES
from cgadyn.algorithms.table import ALGORITHMS
from cgadyn.cga.conventions import motion_from_twist
from cgadyn.multibody import build_model
from cgadyn.multibody.packed import unpack, with_gravity

PANDA = cgadyn.load("panda")
RNG = np.random.default_rng(11)
Q, V, A = (RNG.uniform(-1, 1, 9) for _ in range(3))
SAME = {"rtol": 1e-13, "atol": 1e-13}
"""Single and batch entries compile the same core into different callers, where fused
multiply-adds may land differently: last-bit differences, far inside the 1e-12 asked."""


def test_the_c_extension_is_built_and_used():
    """``cgadyn._native`` is built by ``pip install`` (setup.py) and takes one-sample calls."""
    from cgadyn import _native
    from cgadyn.algorithms.calls import SLOTS, fast

    cgadyn.rnea(PANDA, Q, V, A)
    assert fast is _native.call
    tau = fast(SLOTS["rnea"], PANDA.packed, Q, V, A, None)
    np.testing.assert_array_equal(tau, cgadyn.rnea(PANDA, Q, V, A))
    assert fast(SLOTS["rnea"], PANDA.packed, Q.tolist(), V, A, None) is None  # not canonical
    assert fast(SLOTS["rnea"], PANDA.packed, Q[:8], V, A, None) is None  # wrong length


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


def batch_variants(x: np.ndarray) -> list:
    strided = np.zeros((x.shape[0], 2 * x.shape[1]))
    strided[:, ::2] = x
    readonly = x.copy()
    readonly.setflags(write=False)
    return [x.tolist(), np.asfortranarray(x), strided[:, ::2], readonly, x.astype(np.float32)]


@pytest.mark.parametrize("k", range(5))
def test_odd_batches_give_the_canonical_answer_and_compile_one_signature(k):
    q, v, a = (RNG.uniform(-1, 1, (3, 9)) for _ in range(3))
    want = (cgadyn.rnea(PANDA, q, v, a), cgadyn.aba(PANDA, q, v, a), cgadyn.crba(PANDA, q))
    oq, ov, oa = (batch_variants(x)[k] for x in (q, v, a))
    got = (cgadyn.rnea(PANDA, oq, ov, oa), cgadyn.aba(PANDA, oq, ov, oa),
           cgadyn.crba(PANDA, oq))
    tol = 1e-6 if k == 4 else 1e-13  # float32 inputs
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g, w, rtol=tol, atol=tol)
        assert g.dtype == np.float64 and g.flags.c_contiguous
    for alg in ALGORITHMS:
        for kind in ("single", "batch"):
            entry = getattr(ENTRIES[alg.name], kind)
            assert len(entry.signatures) <= 1, (entry, entry.signatures)


@pytest.mark.parametrize("batch", [1, 2, 7, 8, 9, 64])
def test_batches_equal_their_rows(batch):
    rng = np.random.default_rng(batch)
    q, v, a = (rng.uniform(-1, 1, (batch, 9)) for _ in range(3))
    for name, args in (("rnea", (q, v, a)), ("aba", (q, v, a)), ("crba", (q,)),
                       ("link_placements", (q,)), ("energy", (q, v))):
        f = getattr(cgadyn, name)
        rows = np.array([f(PANDA, *(x[b] for x in args)) for b in range(batch)])
        np.testing.assert_allclose(f(PANDA, *args), rows, err_msg=name, **SAME)


def test_empty_batches_give_empty_results():
    z = np.zeros((0, 9))
    assert cgadyn.rnea(PANDA, z, z, z).shape == (0, 9)
    assert cgadyn.crba(PANDA, z).shape == (0, 9, 9)
    assert cgadyn.jacobian(PANDA, z, "panda_hand").shape == (0, 6, 9)


def test_bad_batches_are_explained():
    q = RNG.uniform(-1, 1, (5, 9))
    bad = q.copy()
    bad[3, 4] = np.nan
    nan_at = r"q contains NaN or inf at index \(3, 4\) \(joint 'panda_joint5'\)"
    with pytest.raises(ValueError, match=nan_at):
        cgadyn.rnea(PANDA, bad, q, q)
    with pytest.raises(ValueError, match=nan_at):
        cgadyn.crba(PANDA, bad)
    with pytest.raises(ValueError, match="9"):
        cgadyn.aba(PANDA, q[:, :8], q[:, :8], q[:, :8])
    with pytest.raises(ValueError, match="batches of the same size"):
        cgadyn.rnea(PANDA, q, q[:4], q)


def test_outputs_are_fresh_arrays():
    a, b = cgadyn.rnea(PANDA, Q, V, A), cgadyn.rnea(PANDA, Q, V, A)
    assert a is not b and not np.shares_memory(a, b)
    a[:] = 0.0
    np.testing.assert_array_equal(b, cgadyn.rnea(PANDA, Q, V, A))


def test_batch_outputs_share_one_block_without_overlap():
    rng = np.random.default_rng(7)
    q, v, a = (rng.uniform(-1, 1, (5, 9)) for _ in range(3))
    outs = cgadyn.rnea_derivatives(PANDA, q, v, a)
    assert [o.shape for o in outs] == [(5, PANDA.nv, PANDA.nv)] * 3
    for i, x in enumerate(outs):
        assert x.flags.c_contiguous and x.ctypes.data % 64 == 0
        for y in outs[i + 1:]:
            assert not np.shares_memory(x, y)
    ref = [o.copy() for o in outs]
    outs[0][:] = np.nan  # the other results are not touched
    for x, y in zip(outs[1:], ref[1:], strict=True):
        np.testing.assert_array_equal(x, y)
    single = cgadyn.rnea_derivatives(PANDA, q[3], v[3], a[3])
    for x, y in zip(ref, single, strict=True):
        np.testing.assert_array_equal(x[3], y)


def test_a_dropped_batch_block_is_reused_and_a_live_one_never():
    rng = np.random.default_rng(8)
    q, v, a = (rng.uniform(-1, 1, (1024, 9)) for _ in range(3))  # 2 MiB of results
    first = cgadyn.rnea_derivatives(PANDA, q, v, a)
    address = first[0].ctypes.data
    ref = [x.copy() for x in first]
    del first
    again = cgadyn.rnea_derivatives(PANDA, q, v, a)
    assert again[0].ctypes.data == address  # the dropped block, with the same numbers
    for x, y in zip(again, ref, strict=True):
        np.testing.assert_array_equal(x, y)
    row = again[2][5]  # one view of one result keeps the whole block alive
    del again
    other = cgadyn.rnea_derivatives(PANDA, -q, v, a)
    assert not np.shares_memory(other[0], row)
    np.testing.assert_array_equal(row, ref[2][5])


def test_kept_blocks_stay_under_their_bound(monkeypatch):
    from cgadyn.algorithms import _blocks

    monkeypatch.setattr(_blocks, "KEEP_BYTES", 6 << 20)
    rng = np.random.default_rng(9)
    for b in (700, 900, 1100, 1300):  # 1.3 to 2.4 MiB each
        q = rng.uniform(-1, 1, (b, 9))
        assert cgadyn.rnea_derivatives(PANDA, q, q, q)[0].shape == (b, 9, 9)
        assert _blocks.kept_bytes() <= 6 << 20


@njit
def _unpacked(packed):
    m = unpack(packed)
    return (m.n, m.nq, m.nv, m.nl, m.parents.copy(), m.types.copy(), m.iq.copy(), m.iv.copy(),
            m.dof_parent.copy(), m.dof_joint.copy(), m.subtree_end.copy(), m.link_joint.copy(),
            m.placements.copy(), m.S.copy(), m.inertias.copy(), m.gravity.copy(),
            m.link_placements.copy())


def test_packed_model_unpacks_to_its_fields():
    for name in ("panda", "gripper", "ur5"):
        m = cgadyn.load(name)
        got = _unpacked(m.packed)
        assert got[:4] == (m.njoints, m.nq, m.nv, m.nlinks)
        for value, field in zip(got[4:], ("parents", "joint_types", "idx_q", "idx_v",
                                          "dof_parent", "dof_joint", "subtree_end", "link_joint",
                                          "placements", "motion_subspace", "inertias"),
                                strict=False):
            np.testing.assert_array_equal(value, getattr(m, field), err_msg=field)
        np.testing.assert_array_equal(got[16], m.link_placements)
        # V̇_0 = -g: the twist of an upward linear acceleration of 9.81
        np.testing.assert_allclose(motion_from_twist(got[15]), [0, 0, 9.81, 0, 0, 0])
        moon = _unpacked(with_gravity(m.packed, (0.0, 0.0, -1.62)))[15]
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


SCRIPT = """
import json, numpy as np, cgadyn
m = cgadyn.load("gripper")
rng = np.random.default_rng(3)
q, v, a = (rng.uniform(-1, 1, m.nv) for _ in range(3))
print(json.dumps({"rnea": cgadyn.rnea(m, q, v, a).tolist(),
                  "aba": cgadyn.aba(m, q, v, a).tolist(),
                  "crba": cgadyn.crba(m, q).tolist(),
                  "jac": cgadyn.jacobian(m, q, m.link_names[-1]).tolist()}))
"""


@pytest.mark.slow
def test_without_the_c_extension_the_dispatcher_gives_the_same_numbers():
    """``CGADYN_NATIVE=0``: one-sample calls go through numba's dispatcher instead."""
    runs = []
    for native in ("1", "0"):
        env = dict(os.environ, CGADYN_NATIVE=native)
        out = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True,
                             text=True, check=True, timeout=900)
        runs.append(json.loads(out.stdout))
    for key in runs[0]:
        np.testing.assert_allclose(runs[1][key], runs[0][key], err_msg=key, **SAME)
