"""Conventions pinned to Pinocchio: poses, motions, forces, inertias, power, exp/log."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from cgadyn import kernels as K
from cgadyn.cga import conventions as C
from cgadyn.cga.basis import NULL, e0, einf, motor_mv

N = 10


@pytest.fixture(autouse=True)
def _seed():
    pin.seed(1)
    np.random.seed(1)


def test_motor_from_matrix_moves_points_like_the_matrix():
    rng = np.random.default_rng(0)
    for _ in range(N):
        S = pin.SE3.Random()
        m = C.motor_from_matrix(S.homogeneous)
        x = rng.normal(size=3)
        X = e0 + NULL.multivector(x, ["e1", "e2", "e3"]) + 0.5 * (x @ x) * einf
        M = motor_mv(m)
        assert np.allclose(NULL.coeffs(M * X * ~M, ["e1", "e2", "e3"]), S.act(x))
        assert np.allclose(C.matrix_from_motor(m), S.homogeneous)
        q = pin.Quaternion(S.rotation).coeffs()  # (x, y, z, w)
        qm = C.quaternion_from_motor(m)
        assert np.allclose(qm, [q[3], *q[:3]]) or np.allclose(qm, -np.array([q[3], *q[:3]]))


def test_twist_and_wrench_transform_like_se3_act():
    for _ in range(N):
        S = pin.SE3.Random()
        m = C.motor_from_matrix(S.homogeneous)
        mo, f = pin.Motion.Random(), pin.Force.Random()
        out = np.empty(6)
        K.twist_sandwich(m, C.twist_from_motion(mo.vector), out)
        assert np.allclose(C.motion_from_twist(out), S.act(mo).vector)
        K.twist_sandwich_rev(m, C.twist_from_motion(mo.vector), out)
        assert np.allclose(C.motion_from_twist(out), S.actInv(mo).vector)
        K.wrench_sandwich(m, C.wrench_from_force(f.vector), out)
        assert np.allclose(C.force_from_wrench(out), S.act(f).vector)
        K.wrench_sandwich_rev(m, C.wrench_from_force(f.vector), out)
        assert np.allclose(C.force_from_wrench(out), S.actInv(f).vector)


def test_cross_products_and_power():
    for _ in range(N):
        a, b, f = pin.Motion.Random(), pin.Motion.Random(), pin.Force.Random()
        va, vb = C.twist_from_motion(a.vector), C.twist_from_motion(b.vector)
        w = C.wrench_from_force(f.vector)
        out = np.empty(6)
        K.twist_cross(va, vb, out)
        assert np.allclose(C.motion_from_twist(out), a.cross(b).vector)
        K.twist_cross_wrench(va, w, out)
        assert np.allclose(C.force_from_wrench(out), a.cross(f).vector)
        assert np.isclose(-K.dot(va, w), a.dot(f))  # p = -V · W (eq. 9)


def test_inertia_apply_transform_and_parameters():
    for _ in range(N):
        S, I, mo = pin.SE3.Random(), pin.Inertia.Random(), pin.Motion.Random()
        Ic = C.inertia_from_pinocchio(I.matrix())
        assert np.allclose(C.inertia_to_pinocchio(Ic), I.matrix())
        fromp = C.inertia_from_parameters(I.mass, I.lever, I.inertia)
        assert np.allclose(fromp, Ic)
        out = np.empty(6)
        K.inertia_apply(Ic, C.twist_from_motion(mo.vector), out)
        assert np.allclose(C.force_from_wrench(out), (I * mo).vector)
        moved = C.inertia_transform(C.motor_from_matrix(S.homogeneous), Ic)
        assert np.allclose(C.inertia_to_pinocchio(moved), S.act(I).matrix())


def test_exp_and_log_equal_exp6_log6():
    for _ in range(N):
        mo, S = pin.Motion.Random(), pin.SE3.Random()
        m = np.empty(8)
        K.twist_exp(C.twist_from_motion(mo.vector), m)
        assert np.allclose(C.matrix_from_motor(m), pin.exp6(mo).homogeneous)
        v, back = np.empty(6), np.empty(8)
        m = C.motor_from_matrix(S.homogeneous)
        K.motor_log(m, v)
        K.twist_exp(v, back)
        assert np.allclose(back, m)  # exp(log M) = M with M's own sign
        # log returns θ in [0, 2π): the motor with scalar part ≥ 0 has log6's θ ≤ π
        K.motor_log(m if m[0] >= 0 else -m, v)
        assert np.allclose(C.motion_from_twist(v), pin.log6(S).vector)


def test_axis_angle_and_joint_axes_match_pinocchio():
    rng = np.random.default_rng(2)
    for _ in range(N):
        axis, angle, t = rng.normal(size=3), rng.uniform(-3, 3), rng.normal(size=3)
        R = pin.AngleAxis(angle, axis / np.linalg.norm(axis)).matrix()
        assert np.allclose(C.matrix_from_motor(C.motor_from_axis_angle(axis, angle, t)),
                           pin.SE3(R, t).homogeneous)
        m = np.empty(8)
        K.twist_exp(angle * C.twist_from_axis("revolute", axis), m)  # exp(q B / 2)
        assert np.allclose(C.matrix_from_motor(m)[:3, :3], R)


@pytest.mark.parametrize(
    "T, match",
    [
        (np.eye(3), "shape"),
        (np.diag([1.0, 1, 1, 2]), "last row|row"),
        (np.diag([1.0, 2, 1, 1]), "rigid"),
        (np.diag([-1.0, 1, 1, 1]), "rigid"),
        (np.full((4, 4), np.nan), "NaN"),
    ],
)
def test_bad_matrices_raise(T, match):
    with pytest.raises(ValueError, match=match):
        C.motor_from_matrix(T)


def test_bad_inertia_parameters_raise():
    with pytest.raises(ValueError, match="mass"):
        C.inertia_from_parameters(-1.0, np.zeros(3), np.eye(3))
    with pytest.raises(ValueError, match="symmetric"):
        C.inertia_from_parameters(1.0, np.zeros(3), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match="positive"):
        C.inertia_from_parameters(1.0, np.zeros(3), np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="length 6"):
        C.twist_from_motion(np.zeros(5))
    with pytest.raises(ValueError, match="zero length"):
        C.twist_from_axis("revolute", np.zeros(3))
