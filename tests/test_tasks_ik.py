"""Inverse kinematics: reachable poses on the panda, the ur5 (y-axis joints) and baxter's two
arms, judged by Pinocchio's log6; primitives as targets; unreachable targets; the
cooperative dual-arm task space on baxter; clear errors."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.cga.objects import Line, Motor, Plane, Point, Sphere
from cgadyn.tasks import Task, evaluate, inverse_kinematics, solve
from cgadyn.tasks.dual_arm import CooperativeTask, _log6, cooperative_space, solve_cooperative
from cgadyn.tasks.ik import middle_configuration

pin = pytest.importorskip("pinocchio")


def _poses(model, link, n, seed):
    rng = np.random.default_rng(seed)
    Q = np.array([cgadyn.random_configuration(model, rng) for _ in range(n)])
    return cgadyn.link_placements(model, Q)[:, model.link_index(link)]


def _pin_error(pm, q, link, T):
    d = pm.createData()
    pin.framesForwardKinematics(pm, d, q)
    f = pm.getFrameId(link, pin.BODY)
    return np.linalg.norm(pin.log6(pin.SE3(T).actInv(d.oMf[f])).vector)


@pytest.mark.parametrize("name, links", [("panda", ["panda_hand"]), ("ur5", ["tool0"]),
                                         ("baxter", ["left_gripper", "right_gripper"])])
def test_reachable_poses_converge_within_limits(name, links):
    model, pm = oracle.models(name)
    for link in links:
        T = _poses(model, link, 12, seed=len(link))
        res = inverse_kinematics(model, link, T)  # one compiled batch
        assert res.q.shape == (12, model.nq) and res.residual.shape == (12, 6)
        assert res.converged.all() and (res.error <= 1e-10).all()
        assert np.all(res.q >= model.lower) and np.all(res.q <= model.upper)
        for b in range(12):
            assert _pin_error(pm, res.q[b], link, T[b]) <= 1e-10
        one = inverse_kinematics(model, link, T[0])  # the single-target path, the same answer
        assert one.converged and np.allclose(one.q, res.q[0], atol=1e-8)
        assert np.allclose(np.linalg.norm(one.residual), one.error)


def test_primitive_targets_on_the_panda():
    model = cgadyn.load("panda")
    tool = np.eye(4)
    tool[2, 3] = 0.1034  # the tool centre point of the hand
    plane = Plane.through(Point([0.4, 0, 0.2]), Point([0.6, 0.1, 0.2]), Point([0.5, -0.2, 0.2]))
    res = inverse_kinematics(model, "panda_hand", plane, tool=tool)
    x = (cgadyn.link_placements(model, res.q)[model.link_index("panda_hand")] @ tool)[:3, 3]
    assert res.converged and abs(x[2] - 0.2) <= 1e-10
    res = inverse_kinematics(model, "panda_hand", Sphere.from_center_radius([0.5, 0, 0.4], 0.1))
    x = cgadyn.link_placements(model, res.q)[model.link_index("panda_hand")][:3, 3]
    assert res.converged and abs(np.linalg.norm(x - [0.5, 0, 0.4]) - 0.1) <= 1e-10
    line = Line.through(Point([0.5, 0.0, 0.0]), Point([0.5, 0.0, 1.0]))
    res = inverse_kinematics(model, "panda_hand", line,
                             carried=Line.through(Point([0, 0, 0]), Point([0, 0, 1])))
    T = cgadyn.link_placements(model, res.q)[model.link_index("panda_hand")]
    assert res.converged
    assert np.allclose(T[:3, 2], [0, 0, 1], atol=1e-10)  # the hand's z axis along the line
    assert np.allclose(T[:2, 3], [0.5, 0.0], atol=1e-10)


def test_task_stack_and_floating_base():
    model = cgadyn.load("solo12")
    q0 = cgadyn.neutral(model)
    tasks = [Task(model, "FL_FOOT", Point([0.3, 0.2, -0.2])),
             Task(model, "HR_FOOT", Point([-0.2, -0.15, -0.25]), weight=2.0)]
    res = solve(model, tasks, q0)
    assert res.converged and res.error <= 1e-10
    r, _ = evaluate(model, res.q, tasks)
    assert np.linalg.norm(r) <= 1e-10


def test_unreachable_target_returns_the_best_configuration():
    model = cgadyn.load("panda")
    res = inverse_kinematics(model, "panda_hand", Point([3.0, 0.0, 0.5]), restarts=2)
    assert not res.converged
    assert np.isfinite(res.error) and 1.5 < res.error < 3.0
    assert np.all(res.q >= model.lower) and np.all(res.q <= model.upper)
    assert res.restarts == 2


def test_bad_input_is_refused_clearly():
    model = cgadyn.load("panda")
    with pytest.raises(ValueError, match="no_such_link"):
        inverse_kinematics(model, "no_such_link", np.eye(4))
    bad = np.eye(4)
    bad[:3, :3] *= 1.5
    with pytest.raises(ValueError, match="not a rigid transform"):
        inverse_kinematics(model, "panda_hand", bad)
    with pytest.raises(ValueError, match="target pose 1 is not a rigid"):
        inverse_kinematics(model, "panda_hand", np.stack([np.eye(4), bad]))
    with pytest.raises(ValueError, match="no task puts a Sphere onto a Line"):
        inverse_kinematics(model, "panda_hand", Line.through(Point([0, 0, 0]), Point([1, 0, 0])),
                           carried=Sphere.from_center_radius([0, 0, 0], 1.0))
    with pytest.raises(ValueError, match="q0"):
        inverse_kinematics(model, "panda_hand", np.eye(4), q0=np.zeros(3))
    with pytest.raises(ValueError, match="restarts"):
        inverse_kinematics(model, "panda_hand", np.eye(4), restarts=-1)


def test_cooperative_dual_arm_on_baxter():
    model = cgadyn.load("baxter")
    a, b = "left_gripper", "right_gripper"
    q = middle_configuration(model)
    Ma, Ja, Mr, Jr = cooperative_space(model, q, a, b)
    H = 1e-6
    for k, (M, J) in enumerate([(Ma, Ja), (Mr, Jr)]):
        fd = np.stack([(_log6(M.reverse() * cooperative_space(
            model, cgadyn.integrate(model, q, H * e), a, b)[2 * k])
            - _log6(M.reverse() * cooperative_space(
                model, cgadyn.integrate(model, q, -H * e), a, b)[2 * k])) / (2 * H)
            for e in np.eye(model.nv)], axis=1)
        assert np.abs(fd - J).max() <= 1e-7 * np.abs(J).max()
    # the hands keep their relative pose while the absolute pose rises and moves forward
    target = Motor.translator([0.05, 0.0, 0.05]) * Ma
    res = solve_cooperative(model, [CooperativeTask(a, b, "relative", Mr),
                                    CooperativeTask(a, b, "absolute", target)], q)
    Ma2, _, Mr2, _ = cooperative_space(model, res.q, a, b)
    assert res.converged
    assert np.linalg.norm(_log6(Mr.reverse() * Mr2)) <= 1e-10
    assert np.linalg.norm(_log6(target.reverse() * Ma2)) <= 1e-10
    assert np.all(res.q >= model.lower) and np.all(res.q <= model.upper)
