"""dask arrays of states through rnea, aba, crba, the derivatives and simulate: the same
numbers as numpy, chunk by chunk, on dask's threads and on a LocalCluster of two worker
processes; models pickle small. Skipped without dask (the optional extra ``dask``)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import cgadyn
from cgadyn import oracle

da = pytest.importorskip("dask.array")
dask = pytest.importorskip("dask")

ALGORITHMS = {"rnea": "qva", "aba": "qvt", "crba": "q", "rnea_derivatives": "qva",
              "aba_derivatives": "qvt"}


@pytest.fixture(scope="module")
def panda():
    model = cgadyn.load("panda")
    s = oracle.sample(model, 10, 0)
    return model, {"q": s.q, "v": s.v, "a": s.a, "t": s.tau}


def chunked(x, rows=4):
    return da.from_array(x, chunks=(rows,) + (-1,) * (x.ndim - 1))


def compare(out, ref):
    out = dask.compute(*out) if isinstance(out, tuple) else (out.compute(),)
    ref = ref if isinstance(ref, tuple) else (ref,)
    for x, y in zip(out, ref, strict=True):
        np.testing.assert_array_equal(x, y)


def test_models_pickle_small():
    for robot in ("panda", "solo12"):
        model = cgadyn.load(robot)
        data = pickle.dumps(model)
        assert len(data) < 64 * 1024
        again = pickle.loads(data)
        q = oracle.sample(model, 1, 0).q[0]
        np.testing.assert_array_equal(cgadyn.crba(again, q), cgadyn.crba(model, q))


@pytest.mark.parametrize("name", sorted(ALGORITHMS))
def test_dask_equals_numpy(panda, name):
    model, s = panda
    args = [s[k] for k in ALGORITHMS[name]]
    out = getattr(cgadyn, name)(model, *(chunked(x) for x in args))
    assert (out[0] if isinstance(out, tuple) else out).chunks[0] == (4, 4, 2)
    compare(out, getattr(cgadyn, name)(model, *args))


def test_dask_with_one_shared_sample_and_gravity(panda):
    model, s = panda
    out = cgadyn.aba(model, chunked(s["q"]), s["v"][0], s["t"][0], gravity=(0, 1.0, -3.0))
    ref = cgadyn.aba(model, s["q"], np.broadcast_to(s["v"][0], (10, 9)),
                     np.broadcast_to(s["t"][0], (10, 9)), gravity=(0, 1.0, -3.0))
    compare(out, ref)


def test_dask_simulate_equals_numpy(panda):
    model, s = panda
    pd = cgadyn.PD(5.0, 0.5)
    traj = cgadyn.simulate(model, chunked(s["q"]), chunked(s["v"]), 1e-3, 20, controller=pd)
    ref = cgadyn.simulate(model, s["q"], s["v"], 1e-3, 20, controller=pd)
    q, e, done, diverged = dask.compute(traj.q, traj.energy, traj.completed, traj.diverged)
    np.testing.assert_array_equal(q, ref.q)
    np.testing.assert_array_equal(e, ref.energy)
    assert list(done) == [20] * 10 and not diverged.any()
    taus = np.random.default_rng(1).normal(size=(10, 20, model.nv))  # the MPC pattern
    traj = cgadyn.simulate(model, s["q"][0], s["v"][0], 1e-3, 20, tau=chunked(taus))
    ref = cgadyn.simulate(model, s["q"][0], s["v"][0], 1e-3, 20, tau=taus)
    np.testing.assert_array_equal(traj.v.compute(), ref.v)


def test_dask_simulate_keeps_every_kth_state(panda):
    model, s = panda
    for kwargs in (dict(record_every=7), dict(final_only=True)):
        traj = cgadyn.simulate(model, chunked(s["q"]), chunked(s["v"]), 1e-3, 20, **kwargs)
        ref = cgadyn.simulate(model, s["q"], s["v"], 1e-3, 20, **kwargs)
        q, e = dask.compute(traj.q, traj.energy)
        np.testing.assert_array_equal(q, ref.q)
        np.testing.assert_array_equal(e, ref.energy)
        np.testing.assert_array_equal(traj.t, ref.t)


def test_dask_bad_input(panda):
    model, s = panda
    with pytest.raises(ValueError, match="every other state must be"):
        cgadyn.rnea(model, chunked(s["q"]), s["v"][:3], s["a"])
    with pytest.raises(ValueError, match=r"one B: expected \(10, 9\)"):
        cgadyn.rnea(model, chunked(s["q"]), chunked(s["v"][:6]), s["a"][0])


def _numpy_reference(model, q, v, a):
    """numpy in, numpy out, in one process: the results a cluster must reproduce."""
    return cgadyn.rnea(model, q, v, a), cgadyn.simulate(model, q, v, 1e-3, 20).q


@pytest.mark.slow
@pytest.mark.cluster
def test_local_cluster_two_processes(panda):
    """Chunks on two worker processes give exactly what numpy gives in one process. The
    numpy side runs in a worker too: code freshly compiled can differ in the last bit from
    the same code loaded from numba's disk cache (seen once, after a cold start), and the
    workers load it from the cache; in this process the results agree to 1e-14."""
    distributed = pytest.importorskip("distributed")
    model, s = panda
    here = _numpy_reference(model, s["q"], s["v"], s["a"])  # puts the code in the cache
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        tau = cgadyn.rnea(model, chunked(s["q"], 5), chunked(s["v"], 5), chunked(s["a"], 5))
        traj = cgadyn.simulate(model, chunked(s["q"], 5), chunked(s["v"], 5), 1e-3, 20)
        t, q = client.compute([tau, traj.q], sync=True)
        assert len(client.scheduler_info()["workers"]) == 2
        reference = client.submit(_numpy_reference, model, s["q"], s["v"], s["a"]).result()
    np.testing.assert_array_equal(t, reference[0])
    np.testing.assert_array_equal(q, reference[1])
    np.testing.assert_allclose(t, here[0], rtol=1e-14, atol=0)
    np.testing.assert_allclose(q, here[1], rtol=1e-14, atol=0)


def test_a_nan_is_reported_at_its_row_in_the_whole_array(panda):
    """Each chunk is computed alone, counting its rows from 0: the error names the row of
    the whole dask array (chunks (1, 7, 300, 2, 690): row 500 is row 190 of the last)."""
    model, _ = panda
    q = np.tile(oracle.sample(model, 1, 0).q, (1000, 1))
    q[500, 3] = np.nan
    qs = da.from_array(q, chunks=((1, 7, 300, 2, 690), (9,)))
    with dask.config.set(scheduler="synchronous"), \
            pytest.raises(ValueError, match=r"q contains NaN or inf at index \(500, 3\)"):
        cgadyn.crba(model, qs).compute()


def test_a_fault_names_the_sample_of_the_whole_array():
    """A batch fault (a free flyer's quaternion far from unit length) at row 7, chunks of 3."""
    solo = cgadyn.load("solo12")
    q = np.tile(cgadyn.neutral(solo), (10, 1))
    q[7, 3:7] = [0.0, 0.0, 0.0, 3.0]
    zeros = np.zeros((10, solo.nv))
    with dask.config.set(scheduler="synchronous"), \
            pytest.raises(ValueError, match=r"^q\[7, 3:7\], the quaternion"):
        cgadyn.rnea(solo, chunked(q, 3), chunked(zeros, 3), chunked(zeros, 3)).compute()


def test_a_diverging_rollout_is_named_by_its_index_in_the_batch(panda):
    """Rollout 4 of 10 blows up (torques of 1e200) in chunks of three: the warning says
    rollout 4, and that one of the chunk's rollouts 3-5 stopped."""
    model, s = panda
    taus = np.zeros((10, 20, model.nv))
    taus[4] = 1e200
    traj = cgadyn.simulate(model, s["q"][0], s["v"][0], 1e-3, 20, tau=chunked(taus, 3))
    with dask.config.set(scheduler="synchronous"), \
            pytest.warns(cgadyn.SimulationDiverged) as caught:
        diverged = traj.diverged.compute()
    assert list(np.flatnonzero(diverged)) == [4]
    (message,) = [str(w.message) for w in caught]
    assert "rollout 4 stopped" in message, message
    assert "(1 of the 3 rollouts 3-5 of this dask chunk stopped; the batch holds 10)" in message
