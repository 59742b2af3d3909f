"""``cgadyn.simulate`` with bilateral constraints: every stage's q̈ is the constrained dynamics
(C6, C7) computed inside the compiled loop. A closed four-bar linkage keeps its loop and its
energy for 10 s, solo12 held by its four feet stands still on forces that carry its weight,
an MJCF loop closed by ``<equality connect>`` keeps ``J q̈ + γ = 0`` and ``M q̈ + h = τ + Jᵀ λ``
at every kept state, a set that becomes singular mid-run stops that rollout with a reason;
batches, controllers and the constraint-free path are unchanged."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from constraint_cases import FEET, four_bar, loop_error

import cgadyn
from cgadyn.sim import PD, SimulationDiverged, simulate


def python_rk4(model, q, v, dt, steps, acceleration):
    """The RK4 of ``sim/rollout.py`` for joints that add (q ⊕ δ = q + δ), on a Python
    ``acceleration(q, v)``: the states (steps + 1, ·)."""
    Q, V = [q], [v]
    for _ in range(steps):
        a1 = acceleration(q, v)
        v2 = v + dt / 2 * a1
        a2 = acceleration(q + dt / 2 * v, v2)
        v3 = v + dt / 2 * a2
        a3 = acceleration(q + dt / 2 * v2, v3)
        v4 = v + dt * a3
        a4 = acceleration(q + dt * v3, v4)
        q = q + dt / 6 * (v + 2 * v2 + 2 * v3 + v4)
        v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        Q.append(q)
        V.append(v)
    return np.array(Q), np.array(V)


@pytest.mark.slow
def test_four_bar_keeps_its_loop_and_energy_for_ten_seconds():
    """The planar four-bar (its loop's out-of-plane row is zero: a redundant set, solved by
    proximal iterations) under gravity, no torque, 10 s of RK4 at dt = 5 ms with the
    corrector (25, 10): the loop stays closed to 1e-8 m, the energy is kept to 1e-6; the
    violation the trajectory reports is the loop error itself; the first steps are those of
    RK4 written on ``constrained_dynamics``."""
    model, loop, q, v = four_bar()
    dt, steps = 5e-3, 2000
    traj = simulate(model, q, v, dt, steps, constraints=[loop], damping=1e-10)
    assert not traj.diverged and traj.q.shape == (steps + 1, 3)
    errors = np.array([np.linalg.norm(loop_error(model, loop, x)) for x in traj.q])
    np.testing.assert_allclose(traj.constraint_violation[:, 0, 0], errors, rtol=1e-9,
                               atol=1e-15)
    drift = traj.energy_drift()
    print(f"\nfour-bar (simulate), 10 s, RK4 dt 5 ms, corrector {loop.corrector}: loop error "
          f"max {errors.max():.3g} m, velocity error max "
          f"{traj.constraint_violation[:, 0, 1].max():.3g} m/s, energy drift {drift:.3g}")
    assert errors.max() < 1e-8
    assert traj.constraint_violation[:, 0, 1].max() < 1e-7
    assert drift < 1e-6

    def acceleration(x, y):
        return cgadyn.constrained_dynamics(model, x, y, np.zeros(3), [loop], damping=1e-10)[0]

    Q, V = python_rk4(model, q, v, dt, 20, acceleration)
    np.testing.assert_allclose(traj.q[:21], Q, rtol=0, atol=1e-13)
    np.testing.assert_allclose(traj.v[:21], V, rtol=0, atol=1e-12)


def standing_solo():
    model = cgadyn.load("solo12")
    q = cgadyn.neutral(model)
    q[2] = 0.3
    q[7:] = np.tile([0.0, 0.8, -1.6], 4)
    return model, q, [cgadyn.Constraint(model, "point", foot, q=q, corrector=(100.0, 20.0))
                      for foot in FEET]


def test_solo12_held_by_its_feet_stands_still():
    """solo12 on its four held feet with the joint torques of contact inverse dynamics for
    q̈ = 0 (C10): 1 s under gravity moves its base by less than 1e-6 m, and the feet's forces
    (Jᵀ λ) carry its weight, vertical, at every kept state."""
    model, q, cs = standing_solo()
    zero = np.zeros(model.nv)
    tau, _ = cgadyn.contact_inverse_dynamics(model, q, zero, zero, cs)
    steps = 500
    traj = simulate(model, q, zero, 2e-3, steps, tau=np.tile(tau, (steps, 1)), constraints=cs,
                    record_every=50)
    assert not traj.diverged
    assert np.abs(traj.q[:, :3] - q[:3]).max() < 1e-6
    assert np.abs(traj.q[:, 7:] - q[7:]).max() < 1e-6
    forces = traj.forces.reshape(len(traj.t), 4, 3).sum(axis=1)
    weight = 9.81 * cgadyn.total_mass(model)
    np.testing.assert_allclose(forces[:, 2], weight, rtol=1e-6)
    np.testing.assert_allclose(forces[:, :2], 0.0, atol=1e-6 * weight)
    assert traj.constraint_violation.max() < 1e-6


def test_external_forces_with_constraints():
    """A rollout's constrained dynamics takes external wrenches (on the bodies, in their
    frames, as ``aba``'s ``f_ext``): the acceleration at the first state is ABA's with
    τ + Jᵀ λ and those wrenches, and it keeps J q̈ + γ = 0 (C6, C13's bias with f)."""
    model, q, cs = standing_solo()
    rng = np.random.default_rng(3)
    v = 0.1 * rng.normal(size=model.nv)
    f = rng.normal(size=(model.njoints, 6))
    traj = simulate(model, q, v, 1e-3, 2, f_ext=f, constraints=cs, integrator="euler")
    qdd, lam = traj.a[0], traj.forces[0]
    J = cgadyn.constraint_jacobian(model, q, cs)
    expected = cgadyn.aba(model, q, v, J.T @ lam, f_ext=f)
    assert np.abs(qdd - expected).max() <= 1e-9 * max(1.0, np.abs(expected).max())
    gamma = cgadyn.constraint_drift(model, q, v, cs)
    assert np.abs(J @ qdd + gamma).max() <= 1e-9 * max(1.0, np.abs(gamma).max())
    free = simulate(model, q, v, 1e-3, 2, constraints=cs, integrator="euler")
    assert np.abs(free.a[0] - qdd).max() > 1e-3  # the wrenches act


CLOSED_CHAIN = """
<mujoco model="closed_chain">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="crank" pos="0 0 0">
      <joint name="j1" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="1"/>
      <body name="coupler" pos="0.4 0 0">
        <joint name="j2" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 -0.9" size="0.03" mass="1"/>
      </body>
    </body>
    <body name="rocker" pos="1 0 0">
      <joint name="j3" type="hinge" axis="0 1 0"/>
      <joint name="j4" type="hinge" axis="1 0 0"/>
      <geom type="capsule" fromto="0 0 0 -0.2 0 -0.9" size="0.03" mass="1"/>
    </body>
  </worldbody>
  <equality>
    <connect body1="coupler" body2="rocker" anchor="0.4 0 -0.9"/>
  </equality>
</mujoco>
"""
"""A loop closed by MuJoCo's ``connect``: a crank and coupler on one side, a rocker with a
second, out-of-plane hinge on the other (so the loop's three rows are independent)."""


def test_mjcf_connect_loop_keeps_the_constrained_dynamics():
    """The MJCF loop of ``<equality connect>`` (``mujoco_constraints``), pushed by a crank
    torque, 2 s of RK4: at every kept state ``J q̈ + γ = 0`` (γ with the corrector) and
    ``M q̈ + h = τ + Jᵀ λ``, and the loop stays closed. (MuJoCo's own ``mj_step`` holds the
    loop softly, by ``solref``/``solimp``, so its motion is not this one: no comparison.)"""
    model = cgadyn.load(CLOSED_CHAIN)  # MuJoCo compiles the MJCF text
    cs = cgadyn.mujoco_constraints(model, CLOSED_CHAIN, corrector=(100.0, 20.0))
    q = cgadyn.neutral(model)
    v = np.zeros(model.nv)
    steps = 400
    tau = np.zeros((steps, model.nv))
    tau[:, 0] = 0.5
    traj = simulate(model, q, v, 5e-3, steps, tau=tau, constraints=cs, record_every=20)
    assert not traj.diverged
    J = cgadyn.constraint_jacobian(model, traj.q, cs)
    gamma = cgadyn.constraint_drift(model, traj.q, traj.v, cs)
    residual = np.einsum("bij,bj->bi", J, traj.a) + gamma
    assert np.abs(residual).max() < 1e-9
    lhs = cgadyn.rnea(model, traj.q, traj.v, traj.a)  # M q̈ + h
    rhs = tau[0] + np.einsum("bij,bi->bj", J, traj.forces)
    np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-9)
    assert np.abs(traj.q[-1] - q).max() > 0.1  # it moved
    assert traj.constraint_violation[:, 0, 0].max() < 1e-6


@pytest.mark.parametrize("integrator", ["rk4", "semi_implicit_euler", "euler"])
def test_batch_equals_single(integrator):
    """Three four-bars turning at different speeds as one batch, states kept every 7 steps:
    each rollout is the single one, bitwise, forces and violations included."""
    model, loop, q, _ = four_bar()
    speeds = (1.0, 2.0, -3.0)
    vs = np.array([four_bar(crank_speed=s)[3] for s in speeds])
    kw = dict(integrator=integrator, constraints=[loop], damping=1e-10, record_every=7)
    batch = simulate(model, q, vs, 2e-3, 30, **kw)
    for b in range(3):
        one = simulate(model, q, vs[b], 2e-3, 30, **kw)
        for name in ("q", "v", "a", "forces", "constraint_violation"):
            np.testing.assert_array_equal(getattr(batch, name)[b], getattr(one, name))
    last = simulate(model, q, vs, 2e-3, 30, **{**kw, "final_only": True})
    np.testing.assert_array_equal(last.q[:, 0], batch.q[:, -1])


def test_constraints_with_a_pd_controller():
    """A PD law on the four-bar's crank (with gravity compensation) inside the constrained
    loop: the rollout is RK4 on ``constrained_dynamics`` of the same torque law, and the
    loop stays closed."""
    model, loop, q, v = four_bar()
    kp, kd = np.array([20.0, 0.0, 0.0]), np.array([4.0, 0.0, 0.0])
    q_ref = q + np.array([0.3, 0.0, 0.0])
    traj = simulate(model, q, v, 2e-3, 50, controller=PD(kp, kd, q_ref=q_ref),
                    constraints=[loop], damping=1e-10)

    def acceleration(x, y):
        tau = kp * (q_ref - x) - kd * y + cgadyn.rnea(model, x, np.zeros(3), np.zeros(3))
        return cgadyn.constrained_dynamics(model, x, y, tau, [loop], damping=1e-10)[0]

    Q, V = python_rk4(model, q, v, 2e-3, 50, acceleration)
    np.testing.assert_allclose(traj.q, Q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj.v, V, rtol=0, atol=1e-10)
    assert traj.constraint_violation[:, 0, 0].max() < 1e-9


def test_constraint_free_simulate_is_unchanged():
    """Without constraints (None or an empty list) the loop is ABA's, bitwise; the
    trajectory reports no constraint rows."""
    model, _, q, v = four_bar()
    a = simulate(model, q, v, 2e-3, 40)
    b = simulate(model, q, v, 2e-3, 40, constraints=[])
    for name in ("q", "v", "a"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.forces.shape == (41, 0) and a.constraint_violation.shape == (41, 0, 2)

    def acceleration(x, y):
        return cgadyn.aba(model, x, y, np.zeros(3))

    Q, V = python_rk4(model, q, v, 2e-3, 40, acceleration)
    np.testing.assert_allclose(a.q, Q, rtol=0, atol=1e-13)


SLIDERS = """<robot name="sliders"><link name="world_link"/>
<link name="rotor"><inertial><mass value="1"/>
  <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
<link name="radial"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<link name="cx"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<link name="cz"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="phi" type="continuous"><parent link="world_link"/><child link="rotor"/>
  <axis xyz="0 0 1"/></joint>
<joint name="s" type="prismatic"><parent link="rotor"/><child link="radial"/>
  <axis xyz="1 0 0"/><limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
<joint name="u" type="prismatic"><parent link="world_link"/><child link="cx"/>
  <axis xyz="1 0 0"/><limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
<joint name="w" type="prismatic"><parent link="cx"/><child link="cz"/>
  <axis xyz="0 0 1"/><limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
</robot>"""
"""A slider ``s`` on a rotor ``phi`` held on a carriage (``u`` along x, ``w`` along z): the
rotor moves the held point along y by ``s φ̇`` alone, so the y row of J vanishes where the
slider passes the rotor's axis (s = 0): the Delassus matrix is singular there."""


def test_a_set_that_becomes_singular_mid_run_stops_with_a_reason():
    """Without gravity the slider and the carriage glide together along x at 1 m/s from
    x = -1: at step 8 of dt = 1/8 s the slider reaches the rotor's axis, where the set is
    singular; the rollout stops there with the constraint named, its states finite up to
    there, a second rollout of the batch (gliding away from the axis) unaffected."""
    model = cgadyn.load(SLIDERS)
    assert model.joint_names == ("phi", "s", "u", "w")
    c = cgadyn.Constraint(model, "point", "radial", other="cz")
    q0 = np.array([[0.0, -1.0, -1.0, 0.0], [0.0, 1.0, 1.0, 0.0]])
    v0 = np.array([0.0, 1.0, 1.0, 0.0])
    with pytest.warns(SimulationDiverged, match=r"rollout 0 stopped after 8 of 12 steps.*"
                      r"constraints became singular: constraint 0 \(point radial on cz\)"):
        traj = simulate(model, q0, v0, 0.125, 12, integrator="euler", gravity=np.zeros(3),
                        constraints=[c])
    assert list(traj.completed) == [8, 12] and list(traj.diverged) == [True, False]
    assert np.isfinite(traj.q[0, :9]).all() and np.isfinite(traj.q[1]).all()
    np.testing.assert_allclose(traj.q[0, 8], [0.0, 0.0, 0.0, 0.0], atol=1e-12)
    assert "damping > 0" in traj.message
    with warnings.catch_warnings():  # with damping: least-norm forces, no stop
        warnings.simplefilter("error", SimulationDiverged)
        damped = simulate(model, q0[0], v0, 0.125, 12, integrator="euler",
                          gravity=np.zeros(3), constraints=[c], damping=1e-8)
    assert damped.q[-1, 1] == pytest.approx(0.5)


@pytest.mark.parametrize("constraints, match", [
    ("loop", r"constraints\[0\] must be a cgadyn.Constraint, got str"),
    (42, r"constraints must be a list of cgadyn.Constraint, got int"),
    ("other", r"constraints\[0\] \(point FL_FOOT on the world\) was made for the model "
              r"'solo12', not for this one \('four_bar'\)"),
])
def test_bad_constraints(constraints, match):
    model, loop, q, v = four_bar()
    if constraints == "other":
        constraints = standing_solo()[2]
    with pytest.raises(ValueError, match=match):
        simulate(model, q, v, 1e-3, 2, constraints=constraints)
    with pytest.raises(ValueError, match="damping must be a finite number >= 0"):
        simulate(model, q, v, 1e-3, 2, constraints=[loop], damping=-1.0)
