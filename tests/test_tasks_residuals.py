"""Every task residual's Jacobian against central finite differences through ``integrate``,
on a fixed base (panda) and a floating base (solo12); the pose residual against Pinocchio's
``log6`` and ``Jlog6``; clear errors for bad tasks."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn.cga.objects import Circle, Line, Motor, Plane, Point, Sphere
from cgadyn.tasks import Task, evaluate

H = 1e-6
PLANE = Plane.through(Point([0, 0, 0.4]), Point([1, 0, 0.5]), Point([0, 1, 0.3]))
LINE = Line.through(Point([0, 0, 0.4]), Point([1, 0.3, 0.5]))


def _tasks(model, link, pose):
    tool = Motor.from_axis_angle([1, 2, 3], 0.7, [0.01, 0.02, 0.1])
    c = Point([0.0, 0.1, 0.0])
    return [
        Task(model, link, Point([0.3, 0.2, 0.5]), Point([0.01, 0.02, 0.03]), tool=tool),
        Task(model, link, PLANE, c),
        Task(model, link, LINE, c, weight=2.0),
        Task(model, link, Sphere.from_center_radius([0.2, 0.1, 0.3], 0.2), c),
        Task(model, link, Circle.through(Point([0, 0, 0.4]), Point([1, 0, 0.5]),
                                         Point([0, 1, 0.3])), c),
        Task(model, link, LINE, Line.through(Point([0, 0, 0.1]), Point([0, 0.1, 0.2])),
             tool=tool),
        Task(model, link, PLANE, Plane.through(Point([0, 0, 0.1]), Point([1, 0, 0.1]),
                                               Point([0, 1, 0.2]))),
        Task(model, link, pose, kind="orientation", tool=tool),
        Task(model, link, pose, tool=tool, weight=0.5),
    ]


@pytest.mark.parametrize("name, link", [("panda", "panda_hand"), ("solo12", "FL_FOOT")])
def test_residual_jacobians_match_differences(name, link):
    model = cgadyn.load(name)
    rng = np.random.default_rng(3)
    q = cgadyn.random_configuration(model, rng)
    pose = cgadyn.link_placements(model, cgadyn.random_configuration(model, rng))
    tasks = _tasks(model, link, pose[model.link_index(link)])
    r, J = evaluate(model, q, tasks)
    assert r.shape == (sum(t.dim for t in tasks),) and J.shape == (r.size, model.nv)
    fd = np.stack([(evaluate(model, cgadyn.integrate(model, q, H * e), tasks)[0]
                    - evaluate(model, cgadyn.integrate(model, q, -H * e), tasks)[0]) / (2 * H)
                   for e in np.eye(model.nv)], axis=1)
    o = 0
    for t in tasks:
        rows = slice(o, o + t.dim)
        o += t.dim
        assert np.abs(fd[rows] - J[rows]).max() <= 1e-7 * np.abs(J[rows]).max(), t.kind


def test_residual_values_have_their_geometric_meaning():
    model = cgadyn.load("panda")
    q = cgadyn.random_configuration(model, 5)
    x = cgadyn.link_placements(model, q)[model.link_index("panda_hand")][:3, 3]
    r, _ = evaluate(model, q, Task(model, "panda_hand", PLANE))
    n = np.cross([1, 0, 0.1], [0, 1, -0.1])
    n /= np.linalg.norm(n)
    assert abs(abs(r[0]) - abs(n @ (x - [0, 0, 0.4]))) <= 1e-12
    r, _ = evaluate(model, q, Task(model, "panda_hand", Sphere.from_center_radius([0, 0, 0], 0.3)))
    assert abs(r[0] - (np.linalg.norm(x) - 0.3)) <= 1e-12
    r, _ = evaluate(model, q, Task(model, "panda_hand", LINE))
    u = np.array([1, 0.3, 0.1]) / np.linalg.norm([1, 0.3, 0.1])
    e = x - [0, 0, 0.4]
    assert abs(np.linalg.norm(r) - np.linalg.norm(e - u * (u @ e))) <= 1e-12


def test_pose_residual_is_pinocchio_log6():
    pin = pytest.importorskip("pinocchio")
    from cgadyn import oracle

    model, pm = oracle.models("panda")
    d = pm.createData()
    rng = np.random.default_rng(4)
    q, q2 = (cgadyn.random_configuration(model, rng) for _ in range(2))
    fid = pm.getFrameId("panda_hand", pin.BODY)
    pin.framesForwardKinematics(pm, d, oracle.pin_configuration(model, q2))
    target = d.oMf[fid].copy()
    pin.computeJointJacobians(pm, d, oracle.pin_configuration(model, q))
    pin.updateFramePlacements(pm, d)
    err = target.actInv(d.oMf[fid])
    Jp = pin.Jlog6(err) @ pin.getFrameJacobian(pm, d, fid, pin.LOCAL)
    r, J = evaluate(model, q, Task(model, "panda_hand", target.homogeneous))
    assert np.abs(r - pin.log6(err).vector).max() <= 1e-10
    assert np.abs(J - Jp).max() <= 1e-10 * np.abs(Jp).max()


def test_bad_tasks_are_refused_clearly():
    model = cgadyn.load("panda")
    with pytest.raises(ValueError, match="no_such_link"):
        Task(model, "no_such_link", Point([0, 0, 0]))
    with pytest.raises(ValueError, match="no task puts a Sphere onto a Plane"):
        Task(model, "panda_hand", PLANE, Sphere.from_center_radius([0, 0, 0], 1.0))
    bad = np.eye(4)
    bad[0, 0] = 2.0
    with pytest.raises(ValueError, match="rigid|rotation|orthonormal"):
        Task(model, "panda_hand", bad)
    with pytest.raises(ValueError, match="weight"):
        Task(model, "panda_hand", Point([0, 0, 0]), weight=-1.0)
    with pytest.raises(ValueError, match="kind"):
        Task(model, "panda_hand", np.eye(4), kind="position")
