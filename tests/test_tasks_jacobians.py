"""Jacobians of link motors and carried objects, and J̇, against Pinocchio and central
finite differences through ``integrate`` (fixed and floating bases)."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.cga.basis import motor_mv, twist_of
from cgadyn.cga.objects import Circle, Line, Plane, Point, Sphere
from cgadyn.tasks import jacobian_time_variation, motor_jacobian, object_jacobian

pin = pytest.importorskip("pinocchio")

ROBOTS = [("panda", "panda_hand"), ("solo12", "FL_FOOT")]
H = 1e-6


def _state(name, seed=2):
    model, pm = oracle.models(name)
    rng = np.random.default_rng(seed)
    return model, pm, cgadyn.random_configuration(model, rng), rng.normal(size=model.nv)


def _central(model, q, f):
    """Central differences of f through ``integrate``, one column per velocity coordinate."""
    cols = []
    for e in np.eye(model.nv):
        cols.append((f(cgadyn.integrate(model, q, H * e)) - f(cgadyn.integrate(model, q, -H * e)))
                    / (2 * H))
    return np.stack(cols, axis=-1)


def _rel(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.mark.parametrize("name, link", ROBOTS)
def test_time_variation_matches_pinocchio_and_differences(name, link):
    model, pm, q, v = _state(name)
    d = pm.createData()
    qp = oracle.pin_configuration(model, q)
    pin.computeJointJacobians(pm, d, qp)
    pin.computeJointJacobiansTimeVariation(pm, d, qp, v)
    pin.updateFramePlacements(pm, d)
    fid = pm.getFrameId(link, pin.BODY)
    for frame, ref in [("world", pin.WORLD), ("local", pin.LOCAL),
                       ("local_world_aligned", pin.LOCAL_WORLD_ALIGNED)]:
        mine = jacobian_time_variation(model, q, v, link, frame)
        assert _rel(mine, pin.getFrameJacobianTimeVariation(pm, d, fid, ref)) <= 1e-10
        fd = (cgadyn.jacobian(model, cgadyn.integrate(model, q, H * v), link, frame)
              - cgadyn.jacobian(model, cgadyn.integrate(model, q, -H * v), link, frame)) / (2 * H)
        assert _rel(fd, mine) <= 1e-7


@pytest.mark.parametrize("name, link", ROBOTS)
def test_motor_jacobian(name, link):
    model, pm, q, _ = _state(name)
    M, dM = motor_jacobian(model, q, link)
    i = model.link_index(link)
    fd = _central(model, q, lambda x: cgadyn.forward_kinematics(model, x)[1][i])
    assert _rel(dM.T, fd) <= 1e-7
    # ~M ∂M/∂q_k = ½ S_k in the link frame: Pinocchio's LOCAL frame Jacobian
    d = pm.createData()
    pin.computeJointJacobians(pm, d, oracle.pin_configuration(model, q))
    pin.updateFramePlacements(pm, d)
    JL = pin.getFrameJacobian(pm, d, pm.getFrameId(link, pin.BODY), pin.LOCAL)
    local = np.array([2.0 * twist_of(M.reverse().mv() * motor_mv(r)) for r in dM])
    assert np.abs(local - cgadyn.twist_from_motion(JL.T)).max() <= 1e-10


OBJECTS = [
    Point([0.1, 0.2, 0.3]),
    Line.through(Point([0, 0, 0.1]), Point([0.1, 0.2, 0.3])),
    Circle.through(Point([0, 0, 0.1]), Point([0.1, 0.2, 0.3]), Point([0.3, 0, 0])),
    Plane.through(Point([0, 0, 0.1]), Point([0.1, 0.2, 0.3]), Point([0.3, 0, 0])),
    Sphere.from_center_radius([0.1, 0, 0], 0.2),
    Point([0.1, 0.2, 0.3]).mv ^ Point([0.0, -0.1, 0.2]).mv,  # a point pair
]


@pytest.mark.parametrize("name, link", ROBOTS)
def test_object_jacobians(name, link):
    from cgadyn.cga.objects import Geometric

    model, _, q, _ = _state(name)
    for obj in OBJECTS:
        obj = obj if isinstance(obj, Geometric) else Geometric(obj)
        X, dX = object_jacobian(model, q, link, obj)
        assert type(X) is type(obj) and dX.shape == (32, model.nv)
        fd = _central(model, q, lambda x, o=obj: np.asarray(
            object_jacobian(model, x, link, o)[0].mv.coeffs))
        assert _rel(dX, fd) <= 1e-7
    # the point moved by the link is where the link placement puts it
    T = cgadyn.link_placements(model, q)[model.link_index(link)]
    X, _ = object_jacobian(model, q, link, Point([0.1, 0.2, 0.3]))
    assert np.allclose(X.down(), T[:3, :3] @ [0.1, 0.2, 0.3] + T[:3, 3], atol=1e-12)


def test_bad_inputs():
    model = cgadyn.load("panda")
    q = cgadyn.neutral(model)
    with pytest.raises(ValueError, match="no_such_link"):
        motor_jacobian(model, q, "no_such_link")
    with pytest.raises(ValueError, match="Point, Line"):
        object_jacobian(model, q, "panda_hand", np.zeros(32))
    with pytest.raises(ValueError, match="frame"):
        jacobian_time_variation(model, q, q, "panda_hand", "body")
