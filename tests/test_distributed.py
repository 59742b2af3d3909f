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


def test_dask_bad_input(panda):
    model, s = panda
    with pytest.raises(ValueError, match="every other state must be"):
        cgadyn.rnea(model, chunked(s["q"]), s["v"][:3], s["a"])
    with pytest.raises(ValueError, match=r"one B: expected \(10, 9\)"):
        cgadyn.rnea(model, chunked(s["q"]), chunked(s["v"][:6]), s["a"][0])


def test_local_cluster_two_processes(panda):
    distributed = pytest.importorskip("distributed")
    model, s = panda
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        tau = cgadyn.rnea(model, chunked(s["q"], 5), chunked(s["v"], 5), chunked(s["a"], 5))
        traj = cgadyn.simulate(model, chunked(s["q"], 5), chunked(s["v"], 5), 1e-3, 20)
        t, q = client.compute([tau, traj.q], sync=True)
        assert len(client.scheduler_info()["workers"]) == 2
    np.testing.assert_array_equal(t, cgadyn.rnea(model, s["q"], s["v"], s["a"]))
    np.testing.assert_array_equal(q, cgadyn.simulate(model, s["q"], s["v"], 1e-3, 20).q)
