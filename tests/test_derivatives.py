"""Analytic derivatives against Pinocchio (computeRNEADerivatives, computeABADerivatives,
computeMinverse) and against central differences through ``integrate``, on fixed and
floating bases, with gravity and f_ext; the identities that tie them together; batches."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from numba import njit

import cgadyn
from cgadyn import oracle
from cgadyn.algorithms._stream import STREAM_FLOATS
from cgadyn.algorithms.aba_derivatives import solve_by_factors
from cgadyn.algorithms.ltdl import supports
from cgadyn.multibody.packed import unpack
from cgadyn.multibody.registry import robot_path

ROBOTS = ["panda", "ur5", "double_pendulum_continuous", "prismatic_tree", "solo12", "talos"]
GRAVITY = (0.3, -1.0, -9.0)


def rel(x, y) -> float:
    return float(oracle.relative_error(np.asarray(x)[None], np.asarray(y)[None])[0])


@pytest.fixture(scope="module", params=ROBOTS)
def robot(request):
    model, pm = oracle.models(request.param)
    pm.gravity.linear = np.array(GRAVITY)
    return model, pm, pm.createData()


def states(model, n=2, seed=0):
    s = oracle.sample(model, n, seed)
    f = np.random.default_rng(seed + 1).normal(size=(n, model.njoints, 6))
    return [(s.q[i], s.v[i], s.a[i], s.tau[i], f[i]) for i in range(n)]


def test_rnea_derivatives_match_pinocchio(robot):
    model, pm, d = robot
    for q, v, a, _, f in states(model):
        qp = oracle.pin_configuration(model, q)
        for fe in (None, f):
            mine = cgadyn.rnea_derivatives(model, q, v, a, gravity=GRAVITY, f_ext=fe)
            args = (pm, d, qp, v, a) if fe is None else (pm, d, qp, v, a, oracle.forces(fe))
            theirs = [x.copy() for x in pin.computeRNEADerivatives(*args)]
            assert rel(mine[0], theirs[0]) < 1e-10
            assert rel(mine[1], theirs[1]) < 1e-10
            assert rel(mine[2], oracle.symmetric(theirs[2])) < 1e-10


def assert_aba_derivatives_match(model, pm, d, q, v, tau, f, tol):
    """aba_derivatives at (q, v, tau), without and with the wrenches f, against Pinocchio's
    computeABADerivatives, to ``tol`` relative."""
    qp = oracle.pin_configuration(model, q)
    for fe in (None, f):
        mine = cgadyn.aba_derivatives(model, q, v, tau, gravity=GRAVITY, f_ext=fe)
        args = (pm, d, qp, v, tau) if fe is None else (pm, d, qp, v, tau, oracle.forces(fe))
        theirs = [x.copy() for x in pin.computeABADerivatives(*args)]
        for k in range(3):
            ref = theirs[k] if k < 2 else oracle.symmetric(theirs[k])
            assert rel(mine[k], ref) < tol, k


def test_aba_derivatives_and_minverse_match_pinocchio(robot):
    model, pm, d = robot
    for q, v, _, tau, f in states(model):
        qp = oracle.pin_configuration(model, q)
        cond = np.linalg.cond(cgadyn.crba(model, q))
        assert_aba_derivatives_match(model, pm, d, q, v, tau, f, 1e-10 * cond)
        Minv = cgadyn.minverse(model, q)
        assert rel(Minv, oracle.symmetric(pin.computeMinverse(pm, d, qp))) < 1e-10 * cond


def _central(f, model, q, eps=1e-6):
    """Columns (f(q ⊕ eps e_k) - f(q ⊕ -eps e_k)) / 2 eps over the tangent space."""
    cols = []
    for k in range(model.nv):
        dq = np.zeros(model.nv)
        dq[k] = eps
        cols.append((f(cgadyn.integrate(model, q, dq)) - f(cgadyn.integrate(model, q, -dq)))
                    / (2 * eps))
    return np.stack(cols, axis=-1)


def _central_v(f, v, eps=1e-6):
    return np.stack([(f(v + eps * e) - f(v - eps * e)) / (2 * eps) for e in np.eye(v.size)],
                    axis=-1)


def test_against_central_differences(robot):
    """Derivatives with respect to the tangent space at q (the base's six columns
    included), as the direction dq of integrate(q, dq)."""
    model, _, _ = robot
    q, v, a, tau, f = states(model, 1, seed=4)[0]
    kw = {"gravity": GRAVITY, "f_ext": f}
    dtau_dq, dtau_dv, _ = cgadyn.rnea_derivatives(model, q, v, a, **kw)
    assert rel(dtau_dq, _central(lambda x: cgadyn.rnea(model, x, v, a, **kw), model, q)) < 1e-6
    assert rel(dtau_dv, _central_v(lambda x: cgadyn.rnea(model, q, x, a, **kw), v)) < 1e-6
    dqdd_dq, dqdd_dv, _ = cgadyn.aba_derivatives(model, q, v, tau, **kw)
    assert rel(dqdd_dq, _central(lambda x: cgadyn.aba(model, x, v, tau, **kw), model, q)) < 1e-6
    assert rel(dqdd_dv, _central_v(lambda x: cgadyn.aba(model, q, x, tau, **kw), v)) < 1e-6


def test_identities(robot):
    """dqdd_dtau = M⁻¹, and dqdd_dq = -M⁻¹ dtau_dq at a = aba(q, v, τ)."""
    model, _, _ = robot
    q, v, _, tau, _ = states(model, 1, seed=7)[0]
    M = cgadyn.crba(model, q)
    dqdd_dq, dqdd_dv, Minv = cgadyn.aba_derivatives(model, q, v, tau)
    assert rel(Minv @ M, np.eye(model.nv)) < 1e-9
    a = cgadyn.aba(model, q, v, tau)
    dtau_dq, dtau_dv, M2 = cgadyn.rnea_derivatives(model, q, v, a)
    assert rel(M2, M) < 1e-12
    assert rel(dqdd_dq, -Minv @ dtau_dq) < 1e-9
    assert rel(dqdd_dv, -Minv @ dtau_dv) < 1e-9


def test_batches_equal_single_calls(robot):
    model, _, _ = robot
    s = oracle.sample(model, 9, 3)
    batch = (cgadyn.rnea_derivatives(model, s.q, s.v, s.a),
             cgadyn.aba_derivatives(model, s.q, s.v, s.tau), (cgadyn.minverse(model, s.q),))
    assert batch[0][0].shape == (9, model.nv, model.nv)
    for b in (0, 4, 8):
        single = (cgadyn.rnea_derivatives(model, s.q[b], s.v[b], s.a[b]),
                  cgadyn.aba_derivatives(model, s.q[b], s.v[b], s.tau[b]),
                  (cgadyn.minverse(model, s.q[b]),))
        for many, one in zip(batch, single, strict=True):
            for x, y in zip(many, one, strict=True):
                assert rel(x[b], y) < 1e-12


def test_minverse_batches_in_groups_of_samples(robot):
    """A batch's minverse runs W samples at once (minverse_lanes) and the rest of each
    thread's chunk one at a time: every sample equals its single call, and a fault inside
    a group is reported at its own sample, as a single call reports it."""
    model, _, _ = robot
    s = oracle.sample(model, 37, 5)  # two chunks of 19 and 18: groups of 8 and tails
    batch = cgadyn.minverse(model, s.q)
    for b in range(37):
        assert rel(batch[b], cgadyn.minverse(model, s.q[b])) < 1e-12
    if model.nq > model.nv:  # a free flyer: a zero quaternion inside the second group
        q = s.q.copy()
        q[13, 3:7] = 0.0
        with pytest.raises(ValueError, match=r"q\[13, 3:7\].*norm 0"):
            cgadyn.minverse(model, q)


@pytest.mark.parametrize("name", ["rnea_derivatives", "aba_derivatives"])
def test_derivative_batches_in_groups_of_samples(robot, name):
    """A batch of derivatives runs its forward pass W samples at once
    (rnea_derivatives_lanes, aba_derivatives_lanes) and the rest of each thread's chunk
    one at a time: every sample equals its single call, with external wrenches too, and a
    fault inside a group is reported at its own sample."""
    model, _, _ = robot
    function = getattr(cgadyn, name)
    s = oracle.sample(model, 37, 6)  # two chunks of 19 and 18: groups of 8 and tails
    third = s.a if name == "rnea_derivatives" else s.tau
    f = np.random.default_rng(8).normal(size=(37, model.njoints, 6))
    for wrenches in (None, f):
        batch = function(model, s.q, s.v, third, f_ext=wrenches)
        for b in range(37):
            one = function(model, s.q[b], s.v[b], third[b],
                           f_ext=None if wrenches is None else f[b])
            for x, y in zip(batch, one, strict=True):
                assert rel(x[b], y) < 1e-12
    if model.nq > model.nv:  # a free flyer: a zero quaternion inside the second group
        q = s.q.copy()
        q[13, 3:7] = 0.0
        with pytest.raises(ValueError, match=r"q\[13, 3:7\].*norm 0"):
            function(model, q, s.v, third)


def test_large_batches_stream_their_results():
    """Results beyond STREAM_FLOATS are computed in the chunk's arrays and streamed out
    (``_stream``): every sample equals its single call, whatever the alignment of its
    matrices (talos: 1444 numbers a matrix, so their starts alternate between two offsets
    within a cache line), in groups and in the tails; a fault is still reported at its own
    sample."""
    model, _ = oracle.models("talos")
    batch = STREAM_FLOATS // (3 * model.nv * model.nv) + 8
    s = oracle.sample(model, batch, 7)
    many = cgadyn.rnea_derivatives(model, s.q, s.v, s.a)
    assert 3 * many[0].size > STREAM_FLOATS
    for b in (0, 1, batch // 2 + 1, batch - 1):
        one = cgadyn.rnea_derivatives(model, s.q[b], s.v[b], s.a[b])
        for x, y in zip(many, one, strict=True):
            assert rel(x[b], y) < 1e-12
    q = s.q.copy()
    q[batch - 3, 3:7] = 0.0
    with pytest.raises(ValueError, match=rf"q\[{batch - 3}, 3:7\].*norm 0"):
        cgadyn.rnea_derivatives(model, q, s.v, s.a)
    batch = STREAM_FLOATS // (model.nv * model.nv) + 8  # minverse, a group's eight at once
    s = oracle.sample(model, batch, 8)
    many = cgadyn.minverse(model, s.q)
    assert many.size > STREAM_FLOATS
    for b in (0, 1, batch // 2 + 1, batch - 1):
        assert rel(many[b], cgadyn.minverse(model, s.q[b])) < 1e-12
    q = s.q.copy()
    q[batch - 13, 3:7] = 0.0
    with pytest.raises(ValueError, match=rf"q\[{batch - 13}, 3:7\].*norm 0"):
        cgadyn.minverse(model, q)


@njit
def _route(packed):
    m = unpack(packed)
    return supports(m), solve_by_factors(m)


@pytest.mark.parametrize("name", ROBOTS)
def test_forward_dynamics_derivatives_route_by_the_tree(name):
    """D15: from eight coordinates on, aba_derivatives takes the product with M⁻¹ (panda,
    talos); ``supports`` is L's count below the diagonal, Σ_k d_k, checked against a walk
    of ``dof_parent``."""
    model = cgadyn.load(name)
    walk = 0
    for k in range(model.nv):
        i = model.dof_parent[k]
        while i >= 0:
            walk, i = walk + 1, model.dof_parent[i]
    count, by_factors = _route(model.packed)
    assert count == walk
    assert by_factors == {"panda": False, "ur5": False, "talos": False}.get(name, by_factors)


def test_forward_dynamics_derivatives_by_the_factors():
    """D15's other route, L5-L6 on 2nv columns: a branched tree below eight coordinates
    (the prismatic tree with its lift fixed: two arms and a head on a fixed torso, nv = 6,
    Σ_k d_k = 4) against Pinocchio, with gravity and f_ext."""
    urdf = robot_path("prismatic_tree").read_text().replace(
        '<joint name="lift" type="prismatic">', '<joint name="lift" type="fixed">')
    model, pm = oracle.models(urdf)
    pm.gravity.linear = np.array(GRAVITY)
    d = pm.createData()
    assert model.nv == 6 and _route(model.packed) == (4, True)
    for q, v, _, tau, f in states(model, 3):
        assert_aba_derivatives_match(model, pm, d, q, v, tau, f, 1e-10)


def test_bad_input_is_named():
    model = cgadyn.load("ur5")
    with pytest.raises(ValueError, match="q"):
        cgadyn.rnea_derivatives(model, np.zeros(5), np.zeros(6), np.zeros(6))
    with pytest.raises(ValueError, match="NaN|nan|finite"):
        cgadyn.aba_derivatives(model, np.full(6, np.nan), np.zeros(6), np.zeros(6))
