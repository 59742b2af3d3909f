"""The free-flyer joint in every compiled algorithm, against Pinocchio's JointModelFreeFlyer:
rnea, aba, crba, Jacobians, placements and energy on legged robots and on an arm given a
floating base, at random configurations with random unit quaternions."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import cgadyn
from cgadyn.multibody import load_urdf
from cgadyn.multibody.registry import example_robot_data_dir

ERD = example_robot_data_dir()
ROBOTS = {
    "anymal": "anymal_b_simple_description/robots/anymal.urdf",
    "talos_reduced": "talos_data/robots/talos_reduced.urdf",
    "panda": "panda_description/urdf/panda.urdf",
}
TOL = 1e-12


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def robot(request):
    path = str(ERD / ROBOTS[request.param])
    pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    return load_urdf(path, name=request.param, floating_base=True), pm, pm.createData()


def states(pm, rng, count=3):
    for _ in range(count):
        q = rng.uniform(-1.0, 1.0, pm.nq)
        quat = rng.normal(size=4)
        q[3:7] = quat / np.linalg.norm(quat)
        yield q, rng.normal(size=pm.nv), rng.normal(size=pm.nv)


def rel(x, y) -> float:
    return float(np.abs(np.asarray(x) - y).max() / max(np.abs(y).max(), 1e-300))


def test_layout_is_pinocchios(robot):
    m, pm, _ = robot
    assert (m.nq, m.nv, m.floating_base) == (pm.nq, pm.nv, True)
    assert m.joint_names == tuple(pm.names[1:])
    assert m.joint_names[0] == "root_joint"


def test_dynamics_match_pinocchio(robot):
    m, pm, pd = robot
    rng = np.random.default_rng(4)
    for q, v, a in states(pm, rng):
        fe = rng.normal(size=(m.njoints, 6))
        forces = [pin.Force.Zero()] + [pin.Force(f) for f in fe]
        assert rel(cgadyn.rnea(m, q, v, a), pin.rnea(pm, pd, q, v, a)) < TOL
        assert rel(cgadyn.rnea(m, q, v, a, f_ext=fe), pin.rnea(pm, pd, q, v, a, forces)) < TOL
        assert rel(cgadyn.aba(m, q, v, a), pin.aba(pm, pd, q, v, a)) < TOL
        assert rel(cgadyn.aba(m, q, v, a, f_ext=fe), pin.aba(pm, pd, q, v, a, forces)) < TOL
        H = pin.crba(pm, pd, q)
        assert rel(cgadyn.crba(m, q), np.triu(H) + np.triu(H, 1).T) < TOL


def test_kinematics_and_energy_match_pinocchio(robot):
    m, pm, pd = robot
    rng = np.random.default_rng(5)
    for q, v, _ in states(pm, rng, 2):
        pin.computeJointJacobians(pm, pd, q)
        pin.updateFramePlacements(pm, pd)
        T = cgadyn.link_placements(m, q)
        for i, link in enumerate(m.link_names):
            fid = pm.getFrameId(link)
            assert np.abs(T[i] - pd.oMf[fid].homogeneous).max() < TOL
        link = m.link_names[-1]
        for frame, ref in (("world", pin.WORLD), ("local", pin.LOCAL),
                           ("local_world_aligned", pin.LOCAL_WORLD_ALIGNED)):
            J = pin.getFrameJacobian(pm, pd, pm.getFrameId(link), ref)
            assert np.abs(cgadyn.jacobian(m, q, link, frame) - J).max() < TOL
        T_kin, U = cgadyn.energy(m, q, v)
        assert T_kin == pytest.approx(pin.computeKineticEnergy(pm, pd, q, v), rel=TOL)
        assert U == pytest.approx(pin.computePotentialEnergy(pm, pd, q), rel=TOL, abs=TOL)


def test_batches_equal_single_calls(robot):
    m, pm, _ = robot
    rng = np.random.default_rng(6)
    q, v, a = (np.array(x) for x in zip(*states(pm, rng, 5), strict=True))
    for f, args in ((cgadyn.rnea, (q, v, a)), (cgadyn.aba, (q, v, a)), (cgadyn.crba, (q,))):
        rows = np.array([f(m, *(x[b] for x in args)) for b in range(5)])
        np.testing.assert_allclose(f(m, *args), rows, rtol=1e-13, atol=1e-13)


def test_quaternion_far_from_unit_is_refused_near_unit_normalised(robot):
    m, pm, pd = robot
    q, v, a = next(states(pm, np.random.default_rng(7)))
    slightly = q.copy()
    slightly[3:7] *= 1 + 1e-6
    np.testing.assert_allclose(cgadyn.rnea(m, slightly, v, a), cgadyn.rnea(m, q, v, a),
                               rtol=1e-12, atol=1e-12)
    far = q.copy()
    far[3:7] *= 0.5
    for call in (lambda: cgadyn.rnea(m, far, v, a), lambda: cgadyn.crba(m, far),
                 lambda: cgadyn.aba(m, np.stack([q, far]), np.stack([v, v]), np.stack([a, a]))):
        with pytest.raises(ValueError, match="quaternion.*'root_joint'.*norm 0.5"):
            call()
