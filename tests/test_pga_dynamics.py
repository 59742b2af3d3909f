"""Law of motion (Table 2.1): Pinocchio agreement, energy, power, motor normalisation."""

import numpy as np
import pinocchio as pin
import pytest

from cgadyn.pga import (
    Damping,
    Forques,
    Gravity,
    Hooke,
    Inertia,
    RigidBody,
    Wrench,
    hypercube,
    kinetic_energy,
    pga,
    power,
    state_derivative,
    step,
)
from cgadyn.pga.simulate import hypercube_on_spring, simulate


def planes_3d(axis_vector):
    """Classical axial vector (x, y, z) -> plane coefficients on (e12, e13, e23)."""
    x, y, z = axis_vector
    return np.array([z, -y, x])


def axes_3d(planes):
    e12, e13, e23 = planes
    return np.array([e23, -e13, e12])


@pytest.mark.parametrize("seed", range(5))
def test_3d_body_acceleration_matches_pinocchio_aba(seed):
    """Body-frame mapping: B_b = translation_rate(v) + rotation_rate(planes(w)) with (v, w)
    Pinocchio's free-flyer velocity (local frame); dB_b/dt maps to (a, alpha) the same way.
    The applied wrench is Pinocchio's f_ext (joint frame), gravity is model.gravity (world)."""
    rng = np.random.default_rng(seed)
    m = pga(3)
    mass, com = rng.uniform(0.5, 3.0), rng.normal(size=3) * 0.4
    a = rng.normal(size=(3, 3))
    tensor = a @ a.T + 0.3 * np.eye(3)
    body = RigidBody(Inertia.from_tensor(m, mass, com, tensor))
    motor = m.motor(rotation=rng.normal(size=3), translation=rng.normal(size=3))
    v, w, f, tau = rng.normal(size=(4, 3))
    rate = m.translation_rate(v) + m.rotation_rate(planes_3d(w))
    g = np.array([0.0, 0.0, -9.81])
    forque = Forques(Gravity(body.inertia, g), Wrench(m, f, planes_3d(tau)))
    _, rate_dot = state_derivative(body, forque, motor, rate)
    lin, ang = m.split_rate(rate_dot)
    ours = np.concatenate([lin, axes_3d(ang)])

    model = pin.Model()
    j = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "ff")
    model.appendBodyToJoint(j, pin.Inertia(mass, com, tensor), pin.SE3.Identity())
    data = model.createData()
    p = m.coords(m.sandwich(motor, m.origin))
    rot = np.stack([m.coords(m.sandwich(motor, m.point(e))) - p for e in np.eye(3)], 1)
    q = pin.SE3ToXYZQUAT(pin.SE3(rot, p))
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    fext[j] = pin.Force(f, tau)
    ref = pin.aba(model, data, q, np.concatenate([v, w]), np.zeros(6), fext)
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-10)


@pytest.mark.parametrize("d", [1, 2, 3, pytest.param(4, marks=pytest.mark.slow)])
def test_rk4_conserves_energy_without_damping_and_contact(d):
    """Bound: |E(t) - E(0)| <= 1e-6 E(0) over 2 s (400 RK4 steps, h = 5 ms), hypercube on
    the spring under gravity (figs. 2.4/2.5 without damping and floor)."""
    run = hypercube_on_spring(d, steps=400, dt=0.005, integrator="rk4",
                              contact=False, damping=False)
    s = run["summary"]
    assert s["energy_max_deviation"] <= 1e-6 * s["energy_initial"]
    assert s["motor_norm_error"] < 1e-13


def test_rk4_is_fourth_order_and_euler_first_order():
    d = 3
    body = hypercube(d, 1.0, [1.0, 2.0, 0.5])
    m = body.model
    rate = m.rotation_rate([1.0, 1.3, 0.5]) + m.translation_rate([0.2, 0.0, 0.1])
    forque = Forques(Gravity(body.inertia, [0, 0, -9.81]), Hooke(m, [0.5, 1, 0.25], [0, 0, 2], 12))

    def final(h, n, integ):
        out = simulate(body, forque, m.scalar(), rate, h, n, integ)
        return np.concatenate([out["M"][-1], out["B"][-1]])

    ref = final(0.0025, 400, "rk4")
    e1, e2 = (np.abs(final(h, n, "rk4") - ref).max() for h, n in ((0.02, 50), (0.01, 100)))
    assert 12 < e1 / e2 < 20
    ref = final(0.0025, 80, "rk4")
    e1, e2 = (np.abs(final(h, n, "euler") - ref).max() for h, n in ((0.004, 50), (0.002, 100)))
    assert 1.6 < e1 / e2 < 2.4


@pytest.mark.parametrize("d", [2, 3, 4])
def test_power_is_rate_of_kinetic_energy(d):
    """dT/dt = Π = B ∨ F (section 2.7.3), along an RK4 trajectory (central differences,
    h = 1 ms, so within O(h²) ~ 1e-6 of the scale), with damping and a user forque."""
    body = hypercube(d, 1.5, np.linspace(0.5, 1.5, d))
    m = body.model
    user = Wrench(m, np.linspace(1, -1, d), point=np.full(d, 0.3), frame="world")
    forque = Forques(Gravity(body.inertia, -9.81 * np.eye(d)[0]),
                     Hooke(m, np.full(d, 0.5), np.ones(d), 5.0), Damping(m, 0.3), user)
    b0 = m.grade(np.random.default_rng(d).normal(size=m.n), 2)
    h = 1e-3
    run = simulate(body, forque, m.scalar(), b0, h, 40, "rk4")
    t = run["kinetic"]
    dt_dt = (t[2:] - t[:-2]) / (2 * h)
    pi = np.array([power(m, b, forque(mm, b, 0.0)) for mm, b in zip(run["M"], run["B"],
                                                                    strict=True)])[1:-1]
    np.testing.assert_allclose(dt_dt, pi, atol=2e-5 * np.abs(pi).max())
    # And exactly at one instant: dT/dt = B ∨ I[dB/dt] = B ∨ F.
    _, db = state_derivative(body, forque, run["M"][5], run["B"][5])
    exact = m.vee(run["B"][5], body.inertia.apply(db))[0]
    assert exact == pytest.approx(power(m, run["B"][5], forque(run["M"][5], run["B"][5])),
                                  rel=1e-12)


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
def test_motor_stays_normalised(integrator):
    body = hypercube(4)
    m = body.model
    b = m.grade(np.random.default_rng(0).normal(size=m.n), 2) * 3
    run = simulate(body, None, m.scalar(), b, 0.01, 100, integrator)
    err = np.abs(m.gp(run["M"], m.reverse(run["M"])) - m.scalar()).max()
    assert err < 1e-13
    assert kinetic_energy(body.inertia, run["B"][-1]) > 0


def test_bad_state_and_integrator_are_rejected():
    body = hypercube(3)
    m = body.model
    b = m.zeros()
    with pytest.raises(ValueError, match="unknown integrator 'rk5'; expected one of euler, rk4"):
        step(body, None, m.scalar(), b, 0.01, integrator="rk5")
    with pytest.raises(ValueError, match="unknown integrator"):
        hypercube_on_spring(3, steps=1, integrator="verlet")
    bad = m.scalar()
    bad[3] = np.inf
    with pytest.raises(ValueError, match="motor M must be finite"):
        step(body, None, bad, b, 0.01)
    b_bad = b.copy()
    b_bad[5] = np.nan
    with pytest.raises(ValueError, match="rate bivector B must be finite"):
        simulate(body, None, m.scalar(), b_bad, 0.01, 3)
    with pytest.raises(ValueError, match="last axis 16"):
        step(body, None, np.ones(8), b, 0.01)
    with pytest.raises(ValueError, match="step size h must be finite and > 0"):
        step(body, None, m.scalar(), b, 0.0)
    with pytest.raises(ValueError, match="dimension must be an integer in 1..4"):
        hypercube_on_spring(5, steps=1)
    with pytest.raises(ValueError, match="mass must be finite and positive"):
        hypercube(2, mass=0.0)
