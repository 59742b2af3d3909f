"""``cgadyn.simulate`` against the same integrators written on Pinocchio's ``aba`` and
``integrate``; energy drift of the passive double pendulum; batches, the sampling-MPC
pattern, controllers, blow-ups and bad input."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.sim import PD, GravityCompensation, SimulationDiverged, simulate

Q0, V0 = np.array([1.0, -0.5]), np.array([0.3, 0.0])


def pin_rollout(pm, q, v, dt, steps, method="rk4", tau=None, pd=None, fext=None,
                damped=True):
    """The integrators of ``cgadyn.sim.rollout`` on Pinocchio, with the joint damping
    Pinocchio's parser read (``model.damping``), which ``simulate`` applies by default:
    states (steps+1, ...) and energies. ``pd``: (kp, kd, q_ref) of a PD law with gravity
    compensation."""
    d = pm.createData()
    zero = np.zeros(pm.nv)

    def acc(q, v, u):
        u = u - damped * pm.damping * v  # the joints' dampers (URDF <dynamics damping>)
        if pd is not None:
            kp, kd, q_ref = pd
            u += kp * pin.difference(pm, q, q_ref) - kd * v
            u += pin.computeGeneralizedGravity(pm, d, q)
        if fext is not None:
            return pin.aba(pm, d, q, v, u, fext).copy()
        return pin.aba(pm, d, q, v, u).copy()

    Q, V, E = [q], [v], []
    for i in range(steps + 1):
        E.append(pin.computeKineticEnergy(pm, d, q, v) + pin.computePotentialEnergy(pm, d, q))
        if i == steps:
            break
        u = zero if tau is None else tau[i]
        a1 = acc(q, v, u)
        if method == "euler":
            q, v = pin.integrate(pm, q, dt * v), v + dt * a1
        elif method == "semi_implicit_euler":
            v = v + dt * a1
            q = pin.integrate(pm, q, dt * v)
        else:
            v2 = v + 0.5 * dt * a1
            a2 = acc(pin.integrate(pm, q, 0.5 * dt * v), v2, u)
            v3 = v + 0.5 * dt * a2
            a3 = acc(pin.integrate(pm, q, 0.5 * dt * v2), v3, u)
            v4 = v + dt * a3
            a4 = acc(pin.integrate(pm, q, dt * v3), v4, u)
            q = pin.integrate(pm, q, dt / 6 * (v + 2 * v2 + 2 * v3 + v4))
            v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        Q.append(q)
        V.append(v)
    return np.array(Q), np.array(V), np.array(E)


def rel(x, y) -> float:
    return float(np.max(np.abs(x - y)) / np.max(np.abs(y)))


@pytest.fixture(scope="module")
def pendulum():
    return oracle.models("double_pendulum")


@pytest.mark.parametrize("method", ["rk4", "semi_implicit_euler", "euler"])
def test_double_pendulum_one_second_matches_pinocchio(pendulum, method):
    model, pm = pendulum
    traj = simulate(model, Q0, V0, 1e-3, 1000, integrator=method)
    Q, V, E = pin_rollout(pm, Q0, V0, 1e-3, 1000, method)
    assert traj.q.shape == (1001, 2) and traj.t[-1] == pytest.approx(1.0)
    assert rel(traj.q[-1], Q[-1]) <= 1e-9 and rel(traj.v[-1], V[-1]) <= 1e-9
    assert rel(traj.energy, E) <= 1e-9
    assert not traj.diverged and traj.completed == 1000


def test_double_pendulum_energy_drift_ten_seconds(pendulum):
    """RK4 at dt = 1e-3 over 10 s drifts no more than Pinocchio's RK4 (3.2e-6 at the end)
    and falls by at least 15x when dt halves (fourth order)."""
    model, pm = pendulum
    *_, E = pin_rollout(pm, Q0, V0, 1e-3, 10_000, damped=False)  # conservative
    reference = abs(E[-1] - E[0]) / abs(E[0])
    drift = {}
    for dt in (1e-3, 5e-4):
        traj = simulate(model, Q0, V0, dt, round(10 / dt), passive=False)
        drift[dt] = abs(traj.energy[-1] - traj.energy[0]) / abs(traj.energy[0])
        assert traj.energy_drift() >= drift[dt]
    assert reference == pytest.approx(3.2e-6, rel=0.01)
    assert drift[1e-3] <= reference * (1 + 1e-6)
    assert drift[1e-3] / drift[5e-4] >= 15


def test_panda_pd_and_torques_match_pinocchio():
    """An open-loop torque sequence plus a PD law with gravity compensation, 1 s."""
    model, pm = oracle.models("panda")
    rng = np.random.default_rng(1)
    q0 = oracle.sample(model, 1, 2).q[0]
    v0 = 0.3 * rng.standard_normal(model.nv)
    steps, dt = 500, 2e-3
    tau = rng.standard_normal((steps, model.nv))
    kp, kd = np.linspace(20, 60, model.nv), 5.0
    q_ref = oracle.sample(model, 1, 3).q[0]
    traj = simulate(model, q0, v0, dt, steps, tau=tau, controller=PD(kp, kd, q_ref=q_ref))
    Q, V, _ = pin_rollout(pm, q0, v0, dt, steps, tau=tau, pd=(kp, kd, q_ref))
    assert rel(traj.q[-1], Q[-1]) <= 1e-9 and rel(traj.v[-1], V[-1]) <= 1e-9


def test_free_flyer_falling_matches_pinocchio():
    """solo12 thrown spinning in gravity, 1 s: the base moves through ``integrate``."""
    model, pm = oracle.models("solo12")
    q0 = oracle.sample(model, 1, 4).q[0]
    v0 = np.random.default_rng(5).standard_normal(model.nv)
    traj = simulate(model, q0, v0, 4e-3, 250)
    Q, V, E = pin_rollout(pm, q0, v0, 4e-3, 250)
    assert rel(traj.q[-1], Q[-1]) <= 1e-9 and rel(traj.v[-1], V[-1]) <= 1e-9
    assert rel(traj.energy, E) <= 1e-9
    # free fall: the base's height drops by g t² / 2 on top of its initial velocity
    assert traj.q[-1, 2] < q0[2]


def test_f_ext_matches_pinocchio(pendulum):
    model, pm = pendulum
    f = np.array([[0.5, -1.0, 2.0, 0.1, 0.2, -0.3], [1.0, 0.0, -2.0, 0.0, 0.4, 0.1]])
    traj = simulate(model, Q0, V0, 1e-3, 300, integrator="semi_implicit_euler", f_ext=f)
    Q, V, _ = pin_rollout(pm, Q0, V0, 1e-3, 300, "semi_implicit_euler",
                          fext=oracle.forces(f))
    assert rel(traj.q[-1], Q[-1]) <= 1e-9 and rel(traj.v[-1], V[-1]) <= 1e-9


def test_batch_equals_single(pendulum):
    model, _ = pendulum
    rng = np.random.default_rng(0)
    q0, v0 = rng.uniform(-1, 1, (5, 2)), rng.standard_normal((5, 2))
    tau = 0.1 * rng.standard_normal((5, 200, 2))
    batch = simulate(model, q0, v0, 1e-3, 200, tau=tau, controller=PD(3.0, [0.5, 0.2]))
    assert batch.q.shape == (5, 201, 2) and batch.energy.shape == (5, 201)
    assert list(batch.completed) == [200] * 5 and not batch.diverged.any()
    for b in range(5):
        one = simulate(model, q0[b], v0[b], 1e-3, 200, tau=tau[b],
                       controller=PD(3.0, [0.5, 0.2]))
        for name in ("q", "v", "a", "kinetic", "potential", "energy"):
            np.testing.assert_array_equal(getattr(batch, name)[b], getattr(one, name))


def test_sampling_mpc_pattern(pendulum):
    """B perturbed torque sequences from one state and their costs, in one call."""
    model, _ = pendulum
    H, B, dt = 100, 16, 1e-2
    rng = np.random.default_rng(7)
    taus = rng.normal(0.0, 0.5, (B, H, model.nv))
    traj = cgadyn.simulate(model, Q0, V0, dt, H, tau=taus)  # q0 (nq,) shared by all
    assert traj.q.shape == (B, H + 1, model.nq)
    cost = (traj.q ** 2).sum(axis=(1, 2)) + 1e-3 * (taus ** 2).sum(axis=(1, 2))
    best = int(np.argmin(cost))
    again = cgadyn.simulate(model, Q0, V0, dt, H, tau=taus[best])
    np.testing.assert_array_equal(again.q, traj.q[best])
    assert len(set(np.round(cost, 12))) == B  # the perturbations change the outcome


def test_gravity_compensation_holds_the_panda():
    model = cgadyn.load("panda")
    q0 = oracle.sample(model, 1, 8).q[0]
    still = simulate(model, q0, np.zeros(model.nv), 1e-3, 300,
                     controller=GravityCompensation())
    falls = simulate(model, q0, np.zeros(model.nv), 1e-3, 300)
    assert np.max(np.abs(still.q - q0)) < 1e-9
    assert np.max(np.abs(falls.q[-1] - q0)) > 1e-2


def test_pd_reaches_its_reference():
    model = cgadyn.load("panda")
    q0, q_ref = oracle.sample(model, 2, 9).q
    kp = [100.0] * 4 + [20.0] * 3 + [5.0] * 2
    kd = [20.0] * 4 + [2.0] * 3 + [0.5] * 2
    traj = simulate(model, q0, np.zeros(model.nv), 1e-3, 3000,
                    controller=PD(kp, kd, q_ref=q_ref))
    assert np.max(np.abs(traj.q[-1] - q_ref)) < 1e-3
    assert np.max(np.abs(traj.q[0] - q_ref)) > 0.1


def test_gravity_argument(pendulum):
    model, _ = pendulum
    none = simulate(model, Q0, np.zeros(2), 1e-3, 100, gravity=(0.0, 0.0, 0.0))
    np.testing.assert_array_equal(none.q, np.broadcast_to(Q0, none.q.shape))
    assert np.all(none.potential == 0.0)


def test_blow_up_stops_and_says_so(pendulum):
    model, _ = pendulum
    tau = np.full((50, 2), 1e305)
    with pytest.warns(SimulationDiverged, match=r"stopped after \d+ of 50 steps"):
        traj = simulate(model, Q0, V0, 1e-3, 50, tau=tau, integrator="euler")
    assert traj.diverged and traj.completed < 50 and "diverged" in traj.message
    assert traj.q.shape == (traj.completed + 1, 2) and traj.t.shape == (traj.completed + 1,)
    assert np.isfinite(traj.q).all() and np.isfinite(traj.v).all()
    batch_tau = np.stack([tau, np.zeros((50, 2))])
    with pytest.warns(SimulationDiverged, match="1 of 2 rollouts"):
        batch = simulate(model, Q0, V0, 1e-3, 50, tau=batch_tau, integrator="euler")
    assert list(batch.diverged) == [True, False]
    assert list(batch.completed) == [traj.completed, 50]
    np.testing.assert_array_equal(batch.q[0, :traj.completed + 1], traj.q)
    assert np.isnan(batch.q[0, traj.completed + 1:]).all()
    assert np.isfinite(batch.q[1]).all()


def test_no_warning_when_fine(pendulum):
    model, _ = pendulum
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert simulate(model, Q0, V0, 1e-3, 10).message == ""


@pytest.mark.parametrize("kwargs, match", [
    ({"dt": 0.0}, "dt must be a positive"),
    ({"dt": -1e-3}, "dt must be a positive"),
    ({"dt": float("nan")}, "dt must be a positive"),
    ({"steps": 0}, "steps must be a positive integer"),
    ({"steps": -2}, "steps must be a positive integer"),
    ({"steps": 2.5}, "steps must be a positive integer"),
    ({"tau": np.zeros((9, 2))}, r"tau must have shape \(steps, nv\) = \(10, 2\)"),
    ({"tau": np.zeros((10, 3))}, "tau must have shape"),
    ({"tau": np.full((10, 2), np.nan)}, "tau contains NaN"),
    ({"q0": np.array([np.nan, 0.0])}, "NaN"),
    ({"v0": np.array([0.0, np.inf])}, "inf"),
    ({"q0": np.zeros(3)}, r"q0 must have shape \(2,\)"),
    ({"integrator": "leapfrog"}, "integrator must be one of"),
    ({"controller": "pd"}, "controller must be None"),
    ({"controller": PD(np.ones(3), 1.0)}, r"kp must be a number or have shape \(2,\)"),
    ({"q0": np.zeros((3, 2)), "v0": np.zeros((4, 2))}, "disagree on the number of rollouts"),
    ({"gravity": (0, 0)}, "gravity must be 3 finite numbers"),
])
def test_bad_input(pendulum, kwargs, match):
    model, _ = pendulum
    args = {"q0": Q0, "v0": V0, "dt": 1e-3, "steps": 10, **kwargs}
    with pytest.raises(ValueError, match=match):
        simulate(model, **args)


@pytest.mark.parametrize("gains, match", [
    ((float("nan"), 1.0), "kp must be finite"),
    ((1.0, -2.0), "kd must be non-negative"),
    ((np.ones((2, 2)), 1.0), "kp must be a number or a 1-d array"),
])
def test_bad_gains(gains, match):
    with pytest.raises(ValueError, match=match):
        PD(*gains)




def _one_body(joint, lever):
    """One body on ``joint`` (a Pinocchio joint model) with an asymmetric inertia, its
    centre of mass at ``lever``."""
    pm = pin.Model()
    j = pm.addJoint(0, joint, pin.SE3.Identity(), "base")
    pm.appendBodyToJoint(j, pin.Inertia(1.5, np.array(lever), np.diag([0.1, 0.2, 0.3])),
                         pin.SE3.Identity())
    pm.addBodyFrame("body", j, pin.SE3.Identity(), 0)
    return cgadyn.from_pinocchio(pm), pm


def _free_body(lever):
    return _one_body(pin.JointModelFreeFlyer(), lever)


def _planar_body(lever):
    return _one_body(pin.JointModelPlanar(), lever)


def _euler_move(pm, q, dq, linear: int):
    """K24a with Pinocchio: the body turns about its origin by the rotation of ``dq``
    (``integrate`` of the rotation alone), and the origin goes straight along the world
    vector of the ``linear`` first coordinates of ``dq`` (in the frame at the start)."""
    rotation = dq.copy()
    rotation[:linear] = 0.0
    R = pin.XYZQUATToSE3(q).rotation if linear == 3 else \
        np.array([[q[2], -q[3]], [q[3], q[2]]]) / np.hypot(q[2], q[3])
    out = pin.integrate(pm, q, rotation)
    out[:linear] = q[:linear] + R @ dq[:linear]
    return out


@pytest.mark.parametrize("method", ["semi_implicit_euler", "euler"])
def test_euler_steps_keep_a_free_bodys_linear_velocity_in_the_world(method):
    """K24: the base's linear velocity is integrated in the frame the step starts from and
    moved into the next one, ``v' = exp(-h ω̂') (v + h (v̇ + ω × v))`` (ω' the rotation of
    ``q ⊕ h ·``), and its origin moves straight along that world vector (K24a), written here
    with Pinocchio's ``aba``, ``exp3`` and ``integrate``. A body spinning about a principal
    axis with nothing acting keeps its kinetic energy to rounding and goes straight, where
    the screw motion of ``integrate`` took it 5 mm aside in 1 s; the plain ``v + h v̇`` in
    the body's turning frame gains 10 % of its linear energy in 1 s there."""
    model, pm = _free_body([0.05, -0.02, 0.01])
    d = pm.createData()
    q = pin.neutral(pm)
    v = np.array([1.0, 0.2, -0.3, 0.4, -0.2, 3.0])
    steps, h = 200, 2e-3
    traj = simulate(model, q, v, h, steps, integrator=method, gravity=np.zeros(3))
    pm.gravity.setZero()
    for _ in range(steps):
        a = pin.aba(pm, d, q, v, np.zeros(6))
        vt = v + h * a
        vt[:3] += h * np.cross(v[3:], v[:3])
        w = vt if method == "semi_implicit_euler" else v
        q = _euler_move(pm, q, h * w, 3)
        vt[:3] = pin.exp3(-h * w[3:]) @ vt[:3]
        v = vt
    assert rel(traj.q[-1], q) <= 1e-12 and rel(traj.v[-1], v) <= 1e-12
    model, _ = _free_body([0.0, 0.0, 0.0])  # spun about a principal axis at 10 rad/s
    v0 = np.array([1.0, 0.0, 0.0, 0.0, 0.0, 10.0])
    still = simulate(model, pin.neutral(pm), v0, 1e-3, 1000, integrator=method,
                     gravity=np.zeros(3))
    e = still.kinetic
    assert np.max(np.abs(e - e[0])) <= 1e-12 * e[0]
    world = [pin.XYZQUATToSE3(x).rotation @ u[:3] for x, u in zip(still.q, still.v, strict=True)]
    assert np.max(np.abs(np.array(world) - v0[:3])) <= 1e-12
    assert np.max(np.abs(still.q[:, :3] - np.outer(still.t, v0[:3]))) <= 1e-12  # straight


@pytest.mark.parametrize("method", ["semi_implicit_euler", "euler"])
def test_euler_steps_keep_a_planar_bodys_velocity_in_its_plane(method):
    """K24 on a planar joint ``(vx, vy, ω)``: ``v' = R(-h ω') (v + h (v̇ + ω × v))``, the
    origin straight along ``R(θ) h v`` (K24a), written with Pinocchio's planar joint.
    Spinning at 10 rad/s and sliding at 1 m/s (gravity normal to the plane), a body whose
    origin is its centre of mass keeps its kinetic energy to rounding; one whose origin is
    11 cm off it wobbles by under 0.2 % over 5 s, where ``v + h v̇`` in its turning frame
    would add 10 % a second."""
    model, pm = _planar_body([0.1, -0.05, 0.0])
    d = pm.createData()
    q, v, h = pin.neutral(pm), np.array([0.8, -0.4, 6.0]), 2e-3
    traj = simulate(model, q, v, h, 200, integrator=method)
    for _ in range(200):
        a = pin.aba(pm, d, q, v, np.zeros(3))
        vt = v + h * a
        vt[:2] += h * v[2] * np.array([-v[1], v[0]])  # ω × v in the plane
        w = vt if method == "semi_implicit_euler" else v
        q = _euler_move(pm, q, h * w, 2)
        c, s = np.cos(h * w[2]), np.sin(h * w[2])
        vt[:2] = np.array([[c, s], [-s, c]]) @ vt[:2]
        v = vt
    assert rel(traj.q[-1], q) <= 1e-12 and rel(traj.v[-1], v) <= 1e-12
    for lever, steps, bound in (([0.0, 0.0, 0.0], 1000, 1e-12), ([0.1, -0.05, 0.0], 5000, 2e-3)):
        model, pm = _planar_body(lever)
        v0 = np.array([1.0, 0.0, 10.0])
        v0[:2] -= 10.0 * np.array([-lever[1], lever[0]])  # the centre of mass at 1 m/s
        e = simulate(model, pin.neutral(pm), v0, 1e-3, steps, integrator=method).kinetic
        assert np.max(np.abs(e - e[0])) <= bound * e[0]
