"""Typed CGA objects: Pinocchio agreement, batches, geometry, repr, bad input."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cgadyn.cga import Circle, Inertia, Line, Motor, Plane, Point, Sphere, Twist, Wrench

seeds = st.integers(0, 2**32 - 1)


@pytest.fixture(autouse=True)
def _seed():
    pin.seed(3)


def test_motor_moves_twists_wrenches_inertias_points_like_pinocchio():
    rng = np.random.default_rng(0)
    for _ in range(5):
        S, mo, f = pin.SE3.Random(), pin.Motion.Random(), pin.Force.Random()
        I = pin.Inertia.Random()
        M = Motor.from_matrix(S.homogeneous)
        V, W, J = Twist.from_pinocchio(mo), Wrench.from_pinocchio(f), Inertia.from_pinocchio(I)
        assert np.allclose(M(V).to_pinocchio(), S.act(mo).vector)
        assert np.allclose(M.apply(W).to_pinocchio(), S.act(f).vector)
        assert np.allclose(M(J).to_pinocchio(), S.act(I).matrix())
        assert np.allclose(J(V).to_pinocchio(), (I * mo).vector)
        assert np.isclose(V.power(W), mo.dot(f)) and np.isclose(V.dot(W), -mo.dot(f))
        assert np.isclose(W.power(V), mo.dot(f))
        assert np.allclose(V.cross(Twist.from_pinocchio(f.vector)).to_pinocchio(),
                           mo.cross(pin.Motion(f.vector)).vector)
        assert np.allclose(V.cross(W).to_pinocchio(), mo.cross(f).vector)
        x = rng.normal(size=3)
        assert np.allclose(M(Point(x)).down(), S.act(x))
        assert np.allclose(M.matrix(), S.homogeneous)
        assert np.allclose(M.translation(), S.translation)
        assert np.isclose(J.mass, I.mass)


def test_constructors_agree():
    rng = np.random.default_rng(1)
    axis, angle, t = rng.normal(size=3), 0.7, rng.normal(size=3)
    M = Motor.from_axis_angle(axis, angle, t)
    assert M.allclose(Motor.translator(t) * Motor.rotor(axis, angle))
    q = M.quaternion()
    assert Motor.from_quaternion(q, t).allclose(M)
    assert Motor.from_matrix(M.matrix()).allclose(M) or Motor.from_matrix(M.matrix()).allclose(
        Motor(-M.values))
    assert (M * M.inverse()).allclose(Motor.identity(), atol=1e-12)
    assert (M * ~M).allclose(Motor.identity(), atol=1e-12)
    assert Motor.exp(M.log()).allclose(M) and M.log().exp().allclose(M)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_equivariance_eq17_on_objects(seed):
    rng = np.random.default_rng(seed)
    M = Motor.exp(Twist(rng.normal(size=6)))
    A = rng.normal(size=(3, 3))
    J = Inertia.from_parameters(rng.uniform(0.1, 5), rng.normal(size=3), A @ A.T)
    V = Twist(rng.normal(size=6))
    assert M(J(V)).allclose(M(J)(M(V)), atol=1e-9)
    assert (J + J)(V).allclose(2 * J(V))


def test_batches_broadcast_and_match_single_samples():
    rng = np.random.default_rng(2)
    Ms = Motor.from_matrix(np.stack([pin.SE3.Random().homogeneous for _ in range(4)]))
    Vs = Twist(rng.normal(size=(4, 6)))
    one = Twist(rng.normal(size=6))
    assert Ms.batch_shape == (4,) and len(Ms) == 4
    for out, single in ((Ms(Vs), lambda n: Ms[n](Vs[n])), (Ms(one), lambda n: Ms[n](one)),
                        (Ms * Ms[0], lambda n: Ms[n] * Ms[0])):
        for n in range(4):
            assert out[n].allclose(single(n))
    assert Ms.matrix().shape == (4, 4, 4) and Ms.quaternion().shape == (4, 4)
    assert Ms.log().batch_shape == (4,) and Motor.exp(Ms.log()).allclose(Ms)
    W = Wrench(rng.normal(size=(2, 4, 6)))
    assert np.shape(Vs.dot(W)) == (2, 4)
    assert Motor.identity((2, 3)).batch_shape == (2, 3)


def test_geometric_objects_are_moved_and_keep_incidence():
    rng = np.random.default_rng(4)
    M = Motor.from_matrix(pin.SE3.Random().homogeneous)
    a, b, c, d = (Point(rng.normal(size=3)) for _ in range(4))
    mid = Point(0.5 * (a.down() + b.down()))
    line, plane = Line.through(a, b), Plane.through(a, b, c)
    circle, sphere = Circle.through(a, b, c), Sphere.through(a, b, c, d)
    assert line.contains(mid) and plane.contains(mid) and not circle.contains(mid)
    assert not line.contains(c) and not sphere.contains(mid)
    for obj, p in ((line, a), (plane, c), (circle, b), (sphere, d)):
        moved = M(obj)
        assert type(moved) is type(obj) and obj.contains(p) and moved.contains(M(p))
    center = rng.normal(size=3)
    s = Sphere.from_center_radius(center, 2.0)
    u = rng.normal(size=3)
    assert s.contains(Point(center + 2.0 * u / np.linalg.norm(u)))
    assert not s.contains(Point(center + u / np.linalg.norm(u)))
    assert M(s).contains(M(Point(center - [0, 0, 2.0])))


def test_repr_uses_null_basis_names():
    assert repr(Motor([1, 0.5, 0, 0, -2, 0, 0, 0])) == "Motor(1 + 0.5 e12 - 2 e1∞)"
    assert repr(Twist([0, 0, 1, 0, 0, -1])) == "Twist(e12 - e3∞)"
    assert repr(Wrench([0, 0, 0, 3, 0, 0])) == "Wrench(3 e01)"
    assert "e∞" in repr(Point([1.0, 0, 0])) and "e0" in repr(Point([1.0, 0, 0]))
    assert repr(Motor.identity((3,))) == "Motor(batch (3,))"
    assert repr(Inertia(np.eye(6))).startswith("Inertia(")


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Motor(np.zeros(7)), "shape"),
        (lambda: Twist(np.zeros((3, 5))), "shape"),
        (lambda: Wrench([np.nan] * 6), "NaN"),
        (lambda: Inertia(np.zeros((6, 5))), "shape"),
        (lambda: Motor.from_matrix(np.diag([1.0, 2.0, 1.0, 1.0])), "rigid"),
        (lambda: Motor.from_matrix(np.diag([1.0, 1.0, 1.0, np.inf])), "NaN or inf"),
        (lambda: Motor.from_matrix(np.eye(3)), "shape"),
        (lambda: Inertia.from_parameters(-2.0, np.zeros(3), np.eye(3)), "mass"),
        (lambda: Inertia.from_parameters(1.0, np.zeros(3), np.triu(np.ones((3, 3)))),
         "symmetric"),
        (lambda: Inertia.from_parameters(1.0, np.zeros(3), -np.eye(3)), "positive"),
        (lambda: Inertia(np.triu(np.ones((6, 6)))), "symmetric"),
        (lambda: Inertia(-np.eye(6)), "positive"),
        (lambda: Motor(np.zeros(8)).normalized(), "zero rotor"),
        (lambda: Motor.translator([1.0, 2.0]), "length 3"),
        (lambda: Point(np.zeros(2)), "length 3"),
        (lambda: Sphere.from_center_radius(np.zeros(3), -1.0), "radius"),
    ],
)
def test_bad_input_raises_value_error(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_wrong_types_raise_type_error():
    V, W = Twist(np.ones(6)), Wrench(np.ones(6))
    with pytest.raises(TypeError):
        V.dot(V)
    with pytest.raises(TypeError):
        Inertia(np.eye(6)).apply(W)
    with pytest.raises(TypeError):
        Motor.identity().apply(np.ones(6))
    with pytest.raises(TypeError):
        Motor.identity() * V
