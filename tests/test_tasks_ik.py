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
from cgadyn.tasks.dual_arm import CooperativeTask, cooperative_space
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


def _log6m(T) -> np.ndarray:
    """Pinocchio's log6 of a 4x4 rigid transform, as (v, ω)."""
    return pin.log6(pin.SE3(T)).vector


def test_cooperative_space_on_baxter():
    """C1-C4 against the links' placements and central differences through integrate."""
    model = cgadyn.load("baxter")
    a, b = "left_gripper", "right_gripper"
    q = middle_configuration(model) + 0.2
    tools = (Motor.translator([0.0, 0.0, 0.1]), np.eye(4))
    Ma, Ja, Mr, Jr = cooperative_space(model, q, a, b, tools=tools)
    T = cgadyn.link_placements(model, q)
    T1 = T[model.link_index(a)] @ tools[0].matrix()
    T2 = T[model.link_index(b)]
    assert np.allclose(Mr.matrix(), np.linalg.inv(T1) @ T2, atol=1e-14)  # C1
    half = np.linalg.inv(T1) @ Ma.matrix()
    assert np.allclose(half @ half, Mr.matrix(), atol=1e-13)  # C2: (~F_1 M_a)² = M_r
    h = 1e-6
    for k, (M, J) in enumerate([(Ma, Ja), (Mr, Jr)]):
        inv = np.linalg.inv(M.matrix())
        fd = np.stack([(_log6m(inv @ cooperative_space(
            model, cgadyn.integrate(model, q, h * e), a, b, tools)[2 * k].matrix())
            - _log6m(inv @ cooperative_space(
                model, cgadyn.integrate(model, q, -h * e), a, b, tools)[2 * k].matrix()))
            / (2 * h) for e in np.eye(model.nv)], axis=1)
        assert np.abs(fd - J).max() <= 1e-7 * np.abs(J).max()  # C3, C4
        assert np.abs(J).max() > 0.1


def test_cooperative_tasks_on_baxter():
    """Keep the hands' relative pose while the absolute pose rises and moves forward: the
    cooperative tasks stacked and solved in compiled code, also with a pose task."""
    model = cgadyn.load("baxter")
    a, b = "left_gripper", "right_gripper"
    q = middle_configuration(model)
    Ma, _, Mr, _ = cooperative_space(model, q, a, b)
    target = Motor.translator([0.05, 0.0, 0.05]) * Ma
    tasks = [CooperativeTask(model, a, b, "relative", Mr),
             CooperativeTask(model, a, b, "absolute", target.matrix(), weight=2.0)]
    r, J = evaluate(model, q, tasks)
    assert np.allclose(r[:6], 0.0, atol=1e-14)
    assert np.allclose(r[6:], 2.0 * _log6m(np.linalg.inv(target.matrix()) @ Ma.matrix()))
    fd = np.stack([(evaluate(model, cgadyn.integrate(model, q, 1e-6 * e), tasks)[0]
                    - evaluate(model, cgadyn.integrate(model, q, -1e-6 * e), tasks)[0])
                   / 2e-6 for e in np.eye(model.nv)], axis=1)
    assert np.abs(fd - J).max() <= 1e-7 * np.abs(J).max()
    res = solve(model, tasks, q)
    Ma2, _, Mr2, _ = cooperative_space(model, res.q, a, b)
    assert res.converged and res.error <= 1e-10
    assert np.linalg.norm(_log6m(np.linalg.inv(Mr.matrix()) @ Mr2.matrix())) <= 1e-10
    assert np.linalg.norm(_log6m(np.linalg.inv(target.matrix()) @ Ma2.matrix())) <= 1e-10
    assert np.all(res.q >= model.lower) and np.all(res.q <= model.upper)
    # the relative pose held while the left hand alone goes to a pose (7 + 6 rows)
    goal = cgadyn.link_placements(model, res.q)[model.link_index(a)]
    goal = Motor.translator([0.0, 0.03, 0.0]).matrix() @ goal
    res2 = solve(model, [tasks[0], Task(model, a, goal)], res.q)
    assert res2.converged
    T = cgadyn.link_placements(model, res2.q)
    assert np.linalg.norm(_log6m(np.linalg.inv(goal) @ T[model.link_index(a)])) <= 1e-10


def test_cooperative_task_errors():
    model = cgadyn.load("baxter")
    a, b = "left_gripper", "right_gripper"
    with pytest.raises(ValueError, match="which must be 'absolute' or 'relative'"):
        CooperativeTask(model, a, b, "middle", np.eye(4))
    with pytest.raises(ValueError, match="must differ"):
        CooperativeTask(model, a, a, "relative", np.eye(4))
    with pytest.raises(ValueError, match="tools must be a pair"):
        CooperativeTask(model, a, b, "relative", np.eye(4), tools=(None,))
    with pytest.raises(ValueError, match="target"):
        CooperativeTask(model, a, b, "relative", np.ones((4, 4)))
    with pytest.raises(ValueError, match="link"):
        CooperativeTask(model, a, "no_such_link", "relative", np.eye(4))
    panda = cgadyn.load("panda")
    with pytest.raises(ValueError, match="built for another model"):
        solve(panda, CooperativeTask(model, a, b, "relative", np.eye(4)))


def test_cooperative_space_names_a_nan_in_q():
    """A NaN in q is the caller's: named as q's, with its index and joint (it was blamed
    on a Motor)."""
    model = cgadyn.load("baxter")
    q = cgadyn.neutral(model)
    q[5] = np.nan
    with pytest.raises(ValueError, match=r"^q contains NaN or inf at index \(5,\) \(joint "):
        cooperative_space(model, q, "left_gripper", "right_gripper")
