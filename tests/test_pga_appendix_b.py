"""Appendix B: closed-form free motions against the integrated PGA law of motion."""

import numpy as np
import pytest

from cgadyn.pga import Inertia, RigidBody, dynamics, pga
from cgadyn.pga.free_tops import (
    euler_top_coefficients,
    spherical_top,
    split_free_derivative,
    symmetric_top_motor,
)
from cgadyn.pga.simulate import simulate


def initial_3d():
    m = pga(3)
    m0 = m.motor(rotation=[0.3, -0.2, 0.5], translation=[1.0, 2.0, 3.0])
    b0 = m.translation_rate([0.4, -0.3, 0.2]) + m.rotation_rate([1.0, 0.7, -0.4])
    return m, m0, b0


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_b1_free_motion_splits_into_linear_and_angular_parts(d):
    """(B.1)-(B.2): I^-1[B × I[B]] = eps(-v . **B**) + I_C^-1[**B** × I_C[**B**]]."""
    m = pga(d)
    rng = np.random.default_rng(d)
    moments = rng.uniform(0.5, 2.0, size=len(m.eij))
    inertia = Inertia.principal(m, 1.7, moments)
    b = m.grade(rng.normal(size=(5, m.n)), 2)
    np.testing.assert_allclose(dynamics(inertia, b, m.zeros()),
                               split_free_derivative(m, moments, b), atol=1e-13)


@pytest.mark.parametrize("d", [2, 3, 4])
def test_b2_spherical_top_keeps_its_rate_bivector(d):
    """(B.3)-(B.6): equal moments; B_b constant when v0 = 0, and in general the motor is
    exp(-(eps p/m) t/2) M0 exp(-**B**0 t/2). RK4, h = 0.01 over 1 s: within 1e-9."""
    m = pga(d)
    rng = np.random.default_rng(d)
    body = RigidBody(Inertia.principal(m, 2.0, np.full(len(m.eij), 0.8)))
    m0 = m.motor(rotation=rng.normal(size=len(m.eij)), translation=rng.normal(size=d))
    rot = m.rotation_rate(rng.normal(size=len(m.eij)))
    run = simulate(body, None, m0, rot, 0.01, 100, "rk4")
    np.testing.assert_allclose(run["B"], np.broadcast_to(rot, run["B"].shape), atol=1e-12)
    b0 = rot + m.translation_rate(rng.normal(size=d))
    run = simulate(body, None, m0, b0, 0.01, 100, "rk4")
    motor, rate = spherical_top(m, m0, b0, 1.0)
    np.testing.assert_allclose(run["M"][-1], motor, atol=1e-9)
    np.testing.assert_allclose(run["B"][-1], rate, atol=1e-9)


@pytest.mark.parametrize("i3", [3.0, 0.4])
def test_b3_symmetric_top_follows_b15(i3):
    """(B.15): M = M_p M0 M_Lb M_A; RK4 with h = 0.01 over 2 s agrees within 1e-8."""
    m, m0, b0 = initial_3d()
    body = RigidBody(Inertia.principal(m, 2.0, [i3, 1.0, 1.0]))  # planes e12, e13, e23
    run = simulate(body, None, m0, b0, 0.01, 200, "rk4")
    for k in (50, 200):
        expected = symmetric_top_motor(m, 1.0, i3, m0, b0, run["t"][k])
        np.testing.assert_allclose(run["M"][k], expected, atol=1e-8)


def test_b4_euler_equations_of_the_nonsymmetric_top():
    """(B.17)-(B.18) on E1 = e23, E2 = e31 = -e13, E3 = e12; omega_2 < 0 < omega_1, omega_3."""
    m = pga(3)
    i1, i2, i3 = 3.0, 2.0, 1.0
    inertia = Inertia.principal(m, 1.0, [i3, i2, i1])
    bk = np.array([0.3, -0.7, 1.1])  # B_b1, B_b2, B_b3
    b = m.rotation_rate([bk[2], -bk[1], bk[0]])
    db = dynamics(inertia, b, m.zeros())
    _, planes = m.split_rate(db)
    dbk = np.array([planes[2], -planes[1], planes[0]])
    w = euler_top_coefficients([i1, i2, i3])
    np.testing.assert_allclose(dbk, w * np.roll(bk, -1) * np.roll(bk, -2), atol=1e-14)
    assert w[0] > 0 > w[1] and w[2] > 0


@pytest.mark.parametrize("axis, stable", [(0, True), (1, False), (2, True)])
def test_b4_middle_axis_is_unstable(axis, stable):
    """Tennis racket: spin 2 rad/s about principal axis k with a 1e-3 perturbation, 10 s
    of RK4 (h = 0.02): the other rates stay below 1e-2 about the largest and smallest axis,
    and grow to order 1 about the middle one."""
    m = pga(3)
    i = np.array([3.0, 2.0, 1.0])  # i1 > i2 > i3 about e23, e31, e12
    body = RigidBody(Inertia.principal(m, 1.0, i[::-1]))
    bk = np.full(3, 1e-3)
    bk[axis] = 2.0
    rate = m.rotation_rate([bk[2], -bk[1], bk[0]])
    run = simulate(body, None, m.scalar(), rate, 0.02, 500, "rk4")
    _, planes = m.split_rate(run["B"])
    bks = np.stack([planes[:, 2], -planes[:, 1], planes[:, 0]], 1)
    others = np.abs(np.delete(bks, axis, axis=1)).max()
    if stable:
        assert others < 1e-2
    else:
        assert others > 0.5
