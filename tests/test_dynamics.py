"""Dynamics of URDF robots against Pinocchio: RNEA, ABA, CRBA, gravity, Jacobians, FK, energy."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.oracle import forces

ROBOTS = [
    "panda",  # 9 dof, a tree (two fingers, prismatic)
    "ur5",  # y axes: the sign bug class of gafro
    "double_pendulum",
    "double_pendulum_continuous",
    "kinova",
    "z1",
    "skew_arm",  # unnormalised, skew axes; fixed joints with rotated inertial frames
    "prismatic_tree",  # branching tree with prismatic joints
    "gripper",  # massless knuckle, ±y fingers, mimic joint
    "cart_pole",
]
TOL = 1e-10


def pin_model(name: str):
    pm = oracle.models(name)[1]
    return pm, pm.createData()


def rel(x, y) -> float:
    """``oracle.relative_error`` of one sample."""
    return float(oracle.relative_error(np.asarray(x)[None], np.asarray(y)[None])[0])


def random_state(model, rng, batch=None):
    s = oracle.sample(model, 1 if batch is None else batch, rng)
    return (s.q[0], s.v[0], s.a[0]) if batch is None else (s.q, s.v, s.a)


@pytest.fixture(scope="module", params=ROBOTS)
def robot(request):
    name = request.param
    return cgadyn.load(name), *pin_model(name)


def samples(model, n=4, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield random_state(model, rng)


def test_rnea_aba_crba_match_pinocchio(robot):
    model, pm, pd = robot
    for q, v, a in samples(model):
        qp = oracle.pin_configuration(model, q)
        assert rel(cgadyn.rnea(model, q, v, a), pin.rnea(pm, pd, qp, v, a)) < TOL
        assert rel(cgadyn.aba(model, q, v, a), pin.aba(pm, pd, qp, v, a)) < TOL
        H = pin.crba(pm, pd, qp)
        H = np.triu(H) + np.triu(H, 1).T
        assert rel(cgadyn.crba(model, q), H) < TOL
        g = pin.computeGeneralizedGravity(pm, pd, qp)
        assert rel(cgadyn.gravity_torques(model, q), g) < TOL
        assert rel(cgadyn.nonlinear_effects(model, q, v), pin.nonLinearEffects(pm, pd, qp, v)) < TOL


def test_external_wrenches_match_pinocchio(robot):
    model, pm, pd = robot
    rng = np.random.default_rng(7)
    for q, v, a in samples(model, 2):
        qp = oracle.pin_configuration(model, q)
        fe = rng.normal(size=(model.nv, 6))
        tau = pin.rnea(pm, pd, qp, v, a, forces(fe))
        qdd = pin.aba(pm, pd, qp, v, a, forces(fe))
        assert rel(cgadyn.rnea(model, q, v, a, f_ext=fe), tau) < TOL
        assert rel(cgadyn.aba(model, q, v, a, f_ext=fe), qdd) < TOL


def test_kinematics_jacobians_energy_match_pinocchio(robot):
    model, pm, pd = robot
    frames = [
        ("world", pin.WORLD),
        ("local", pin.LOCAL),
        ("local_world_aligned", pin.LOCAL_WORLD_ALIGNED),
    ]
    for q, v, _ in samples(model, 2):
        qp = oracle.pin_configuration(model, q)
        pin.forwardKinematics(pm, pd, qp)
        pin.updateFramePlacements(pm, pd)
        pin.computeJointJacobians(pm, pd, qp)
        T = cgadyn.link_placements(model, q)
        for i, link in enumerate(model.link_names):
            fid = pm.getFrameId(link, pin.BODY)
            assert rel(T[i], pd.oMf[fid].homogeneous) < TOL
        for link in (model.link_names[-1], model.link_names[len(model.link_names) // 2]):
            fid = pm.getFrameId(link, pin.BODY)
            for frame, pframe in frames:
                J = cgadyn.jacobian(model, q, link, frame)
                assert rel(J, pin.getFrameJacobian(pm, pd, fid, pframe)) < TOL, (link, frame)
        T_kin, U = cgadyn.energy(model, q, v)
        assert rel(T_kin, pin.computeKineticEnergy(pm, pd, qp, v)) < TOL
        assert rel(U, pin.computePotentialEnergy(pm, pd, qp)) < TOL


def test_identities(robot):
    model, _, _ = robot
    for q, v, a in samples(model, 3, seed=3):
        tau = cgadyn.rnea(model, q, v, a)
        assert rel(cgadyn.aba(model, q, v, tau), a) < TOL
        t = np.random.default_rng(1).normal(size=model.nv)
        qdd = cgadyn.aba(model, q, np.zeros(model.nv), t, gravity=(0, 0, 0))
        assert rel(cgadyn.crba(model, q) @ qdd, t) < TOL
        assert np.allclose(cgadyn.crba(model, q), cgadyn.crba(model, q).T, rtol=0, atol=0)


@pytest.mark.parametrize("batch", [9, 2])
def test_batch_equals_single(robot, batch):
    """Large batches run in parallel, tiny ones sample by sample: both equal single calls."""
    model, _, _ = robot
    q, v, a = random_state(model, np.random.default_rng(5), batch=batch)
    fe = np.random.default_rng(6).normal(size=(batch, model.nv, 6))
    tau = cgadyn.rnea(model, q, v, a, f_ext=fe)
    qdd = cgadyn.aba(model, q, v, tau)
    H = cgadyn.crba(model, q)
    J = cgadyn.jacobian(model, q, model.link_names[-1])
    for b in (0, batch // 2, batch - 1):
        assert rel(tau[b], cgadyn.rnea(model, q[b], v[b], a[b], f_ext=fe[b])) < 1e-12
        assert rel(qdd[b], cgadyn.aba(model, q[b], v[b], tau[b])) < 1e-12
        assert rel(H[b], cgadyn.crba(model, q[b])) < 1e-12
        assert rel(J[b], cgadyn.jacobian(model, q[b], model.link_names[-1])) < 1e-12


def test_gravity_is_settable():
    model = cgadyn.load("double_pendulum")
    pm, pd = pin_model("double_pendulum")
    q = np.array([0.3, -0.7])
    z = np.zeros(2)
    pm.gravity.linear = np.array([1.0, -2.0, 3.0])
    try:
        expected = pin.rnea(pm, pd, oracle.pin_configuration(model, q), z, z)
    finally:
        pm.gravity.linear = np.array([0.0, 0.0, -9.81])
    assert rel(cgadyn.rnea(model, q, z, z, gravity=(1.0, -2.0, 3.0)), expected) < TOL


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_panda_table1_accuracy(seed):
    """Over 1000 samples the mean norm of the difference is within the paper's Table 1.

    States are drawn like Eigen's ``VectorXd::Random()`` (uniform in [-1, 1] for q, q̇ and
    q̈ or τ), the paper's C++ test setting as far as we can tell.
    """
    model = cgadyn.load("panda")
    pm, pd = pin_model("panda")
    rng = np.random.default_rng(seed)
    q, v, a = (rng.uniform(-1.0, 1.0, size=(1000, model.nv)) for _ in range(3))
    tau = cgadyn.rnea(model, q, v, a)
    qdd = cgadyn.aba(model, q, v, a)
    id_err = [np.linalg.norm(tau[i] - pin.rnea(pm, pd, q[i], v[i], a[i])) for i in range(1000)]
    fd_err = [np.linalg.norm(qdd[i] - pin.aba(pm, pd, q[i], v[i], a[i])) for i in range(1000)]
    assert np.mean(id_err) <= 1.28015e-14
    assert np.mean(fd_err) <= 6.73759e-14
