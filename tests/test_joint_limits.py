"""Joint limits and friction loss as constraints of the contact step (contact/limits.py,
contact/sets.py; docs/contact.md, "Joint limits", "Friction loss", K26-K30): a pendulum
falls onto its stop and rests there with the stop carrying gravity's torque, a slider
dropped on its stop never gains energy, the panda hanging under gravity stays within its
limits, a joint's dry friction holds a torque below it and lets a larger one through less
it, the compiled loop's step equals ``contact_step``'s, an MJCF's ranges and friction losses
are MuJoCo's, and bad input is named."""

from pathlib import Path

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.step import contact_step

DT = 1e-3
SIE = "semi_implicit_euler"
NOWHERE = cgadyn.World(ground=False)
UPPER = 0.3


def _one_link(kind: str, axis: str, com: str, lower: float, upper: float,
              friction: float = 0.0) -> cgadyn.Model:
    """A 1 kg link on one joint of ``kind`` about or along ``axis``, its centre of mass at
    ``com`` in the joint frame, with a dry ``friction``."""
    return cgadyn.load(
        f'<robot name="one"><link name="base"/><link name="arm"><inertial>'
        f'<origin xyz="{com}"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" '
        f'iyy="0.01" iyz="0" izz="0.01"/></inertial></link><joint name="j" type="{kind}">'
        f'<parent link="base"/><child link="arm"/><axis xyz="{axis}"/><limit lower="{lower}" '
        f'upper="{upper}" effort="10" velocity="10"/><dynamics friction="{friction}"/></joint>'
        f'</robot>')


def _pendulum(friction: float = 0.0) -> cgadyn.Model:
    """A pendulum about y, horizontal at q = 0, its mass 0.5 m out: gravity turns it towards
    +q (down), onto its upper stop at 0.3 rad."""
    return _one_link("revolute", "0 1 0", "0.5 0 0", -1.5, UPPER, friction)


@pytest.mark.parametrize("solver", ["admm", "pgs"])
@pytest.mark.parametrize(("g", "bounds", "expected"), [
    (-3.0, [0.0, np.inf], 1.5), (3.0, [0.0, np.inf], 0.0),  # a limit: λ = max(0, -g / G)
    (-3.0, [-1.0, 1.0], 1.0), (3.0, [-1.0, 1.0], -1.0), (-1.0, [-1.0, 1.0], 0.5)])  # a box
def test_an_interval_row_is_solved_in_closed_form(solver, g, bounds, expected):
    """One row, G = 2: λ = P_[lo, hi](-g / G) (K26-K29), by both solvers."""
    lam, info = cgadyn.solve_contacts([[2.0]], [g], np.zeros(0), solver=solver,
                                      bounds=[bounds])
    assert info.converged and abs(lam[0] - expected) < 1e-9


def test_cones_and_intervals_together_agree_between_solvers():
    """A contact (3 rows) with a limit row and a box row, random positive definite G: ADMM
    and PGS give the same λ to 1e-7, within the sets, with K28's residuals below 1e-9."""
    rng = np.random.default_rng(3)
    for _ in range(5):
        A = rng.normal(size=(5, 5))
        G = A @ A.T + 0.1 * np.eye(5)
        g = rng.normal(size=5)
        bounds = [[0.0, np.inf], [-0.2, 0.2]]
        a, ia = cgadyn.solve_contacts(G, g, [0.7], bounds=bounds)
        b, ib = cgadyn.solve_contacts(G, g, [0.7], bounds=bounds, solver="pgs",
                                      max_iterations=100000)
        assert ia.converged and ib.converged and np.abs(a - b).max() < 1e-7
        assert a[3] >= 0.0 and abs(a[4]) <= 0.2
        assert max(ia.dual, ia.complementarity) < 1e-9


@pytest.mark.parametrize("c", [1.0, -1.0, 2.5])
@pytest.mark.parametrize(("w_free", "gap", "friction", "stop"), [
    (-1.0, -2e-7, 1e-3, True),  # pressed into the stop: it holds, friction opposes the exit
    (0.5, 0.05, 1.0, False),  # leaving an open stop: friction holds the joint
    (0.5, 0.05, 0.05, False)])  # leaving it faster than friction can hold
def test_a_limit_and_a_friction_loss_on_one_coordinate_are_solved_together(
        c, w_free, gap, friction, stop):
    """A limit row ``J_r = e`` (``λ_r >= 0``, ``σ_r = w + gap``) and a friction loss row
    ``J_s = c e`` (``|λ_s| <= f``) on one coordinate of velocity ``w = w_free + a (λ_r + c
    λ_s)``: ``G`` is singular and PGS row by row moves the two impulses against each other
    by the gap's term a sweep; solved together (K29a) it ends in one sweep on the solution
    built here, which ADMM finds too (its power iteration for ``ρ`` restarting where the
    uniform vector lies in ``G``'s null space, ``c = -1``)."""
    a = 2.0
    G = a * np.array([[1.0, c], [c, c * c]])
    g = np.array([w_free + gap, c * w_free])
    if stop:  # the stop holds: w = -gap, friction at the bound opposing w > 0
        lam_s = -np.sign(c) * friction
        lam_r = (-gap - w_free) / a - c * lam_s
    else:  # the stop is open: friction alone, λ_s = P(-w_free / (a c)) (a c² on its row)
        lam_r = 0.0
        lam_s = float(np.clip(-w_free / (a * c), -friction, friction))
    bounds = [[0.0, np.inf], [-friction, friction]]
    lam, info = cgadyn.solve_contacts(G, g, np.zeros(0), solver="pgs", bounds=bounds)
    assert info.converged and info.iterations <= 3
    assert np.abs(lam - [lam_r, lam_s]).max() < 1e-12
    other, info = cgadyn.solve_contacts(G, g, np.zeros(0), solver="admm", bounds=bounds,
                                        max_iterations=10000)  # it crawls: 2812 for c = 2.5
    assert info.converged and np.abs(other - lam).max() < 1e-7


def _steps(model, q, v, steps, **kw):
    out = [(q, v, None, None)]
    for _ in range(steps):
        s = contact_step(model, None, q, v, np.zeros(model.nv), DT, NOWHERE, **kw)
        q, v = s.q, s.v
        out.append((q, v, s.limit_torques, s.friction_torques))
    return out


def test_a_pendulum_falls_onto_its_stop_and_rests_there():
    """Released 0.8 rad above its stop: it never passes the stop by more than 1e-4 rad, comes
    to rest (|v| < 1e-6), and the stop's torque at rest is the gravity torque to 1e-6."""
    model = _pendulum()
    run = _steps(model, np.array([-0.5]), np.zeros(1), 700)
    q = np.array([s[0][0] for s in run])
    assert q.max() <= UPPER + 1e-4
    assert abs(q[-1] - UPPER) < 1e-4 and abs(run[-1][1][0]) < 1e-6
    hold = cgadyn.rnea(model, run[-1][0], np.zeros(1), np.zeros(1))  # the torque holding it
    assert hold[0] < -1.0 and abs(run[-1][2][0] - hold[0]) < 1e-6
    without = contact_step(model, None, run[-1][0], np.zeros(1), np.zeros(1), DT, NOWHERE,
                           joint_limits=False)
    assert without.q[0] > UPPER  # the stop, not the step, holds it


def test_a_slider_dropped_on_its_stop_never_gains_energy():
    """A vertical slide dropped 0.1 m onto its lower stop: the total energy never rises (to
    1e-9 relative) and the stop is never passed. A vertical slide, where a pendulum's swing
    would not do: semi-implicit Euler's own energy error on a swing (O(dt)) is far above
    1e-9, while in free fall it only loses energy (½ m g² dt² a step)."""
    model = _one_link("prismatic", "0 0 1", "0 0 0", 0.0, 1.0)
    run = _steps(model, np.array([0.1]), np.array([0.0]), 400)
    q = np.array([s[0][0] for s in run])
    e = np.array([cgadyn.energy(model, s[0], s[1]).sum() for s in run])
    assert q.min() >= -1e-9
    assert np.all(np.diff(e) <= 1e-9 * np.abs(e).max())
    assert abs(q[-1]) < 1e-9 and abs(run[-1][1][0]) < 1e-9


@pytest.mark.parametrize(("q0", "bound"), [(0.0, 0.5), (1.4, 1.0)])
def test_a_joint_started_past_its_stop_is_taken_back_without_a_kick(q0, bound):
    """A link turning about the vertical (gravity does no work on it) started at rest 0.5 or
    0.4 rad past a stop: the position update takes it back, a fraction ``stabilization`` of
    the overshoot a step (K26a), and its velocity stays zero, so it gains no energy and
    never swings on through its range (with K23's term it left at 0.2 · 0.5 / dt = 100
    rad/s); the compiled loop and ``contact_step`` agree."""
    model = _one_link("revolute", "0 0 1", "0.5 0 0", 0.5, 1.0)
    tr = cgadyn.simulate(model, np.array([q0]), np.zeros(1), DT, 100, integrator=SIE,
                         world=NOWHERE)
    assert np.abs(tr.v).max() < 1e-12
    overshoot = np.abs(tr.q[:, 0] - bound)
    assert np.all(np.diff(overshoot) <= 0.0) and overshoot[-1] < 1e-8
    np.testing.assert_allclose(overshoot[1:4], abs(q0 - bound) * 0.8 ** np.arange(1, 4),
                               rtol=1e-12)
    assert np.abs(np.diff(tr.energy)).max() < 1e-12
    ref = _steps(model, np.array([q0]), np.zeros(1), 100)
    np.testing.assert_allclose([s[0][0] for s in ref], tr.q[:, 0], atol=1e-14)


@pytest.mark.parametrize("friction", [0.0, 2.0])
def test_the_compiled_step_is_contact_step_with_limits(friction):
    """300 steps of the pendulum across its impact on the stop, without and with a friction
    loss: the compiled loop's q and v equal ``contact_step``'s to 1e-10 (forces from zero
    each step, as ``contact_step``), and so do the limit's and the friction's torques of
    each step (``Trajectory.limit_torques``, ``friction_torques``: row k the step from state
    k) to 1e-7 (λ / dt)."""
    model = _pendulum(friction)
    q0, v0 = np.array([0.2]), np.array([-1.0])  # up, then down onto the stop
    ref = _steps(model, q0, v0, 300)
    tr = cgadyn.simulate(model, q0, v0, DT, 300, integrator=SIE, world=NOWHERE,
                         contact=cgadyn.ContactSettings(warm_start=False))
    assert max(s[0][0] for s in ref) > UPPER - 1e-6  # the stop was reached
    for k, (qk, vk, _, _) in enumerate(ref):
        assert np.abs(tr.q[k] - qk).max() < 1e-10 and np.abs(tr.v[k] - vk).max() < 1e-10
    limit = np.array([s[2] for s in ref[1:]])
    friction_torques = np.array([s[3] for s in ref[1:]])
    assert np.abs(limit).max() > 1.0  # the stop acted
    assert friction == 0.0 or np.abs(friction_torques).max() > 1.0
    assert np.abs(tr.limit_torques[:300] - limit).max() < 1e-7
    assert np.abs(tr.friction_torques[:300] - friction_torques).max() < 1e-7
    for k in range(300):  # the step's momentum: M (v⁺ - v) / dt + h = τ_limit + τ_friction
        M = cgadyn.crba(model, tr.q[k])
        h = cgadyn.rnea(model, tr.q[k], tr.v[k], np.zeros(1))
        joint = tr.limit_torques[k] + tr.friction_torques[k]
        assert np.abs(M @ (tr.v[k + 1] - tr.v[k]) / DT + h - joint).max() < 1e-8
    off = cgadyn.simulate(model, q0, v0, DT, 300, integrator=SIE, world=NOWHERE,
                          joint_limits=False)
    assert off.q[:, 0].max() > UPPER + 0.1


@pytest.mark.slow
def test_the_panda_hanging_under_gravity_stays_within_its_limits():
    """The panda from the middle of its joints' ranges (its neutral q = 0 is outside joint
    4's), no torque, 2 s under gravity in a world without ground: every joint within
    [lower - 1e-3, upper + 1e-3], and the rollout completed; without limits it leaves them."""
    model = cgadyn.load("panda")
    q0 = 0.5 * (model.lower + model.upper)
    tr = cgadyn.simulate(model, q0, np.zeros(model.nv), DT, 2000, integrator=SIE,
                         world=NOWHERE)
    assert not tr.diverged
    assert np.all(tr.q >= model.lower - 1e-3) and np.all(tr.q <= model.upper + 1e-3)
    free = cgadyn.simulate(model, q0, np.zeros(model.nv), DT, 2000, integrator=SIE)
    assert np.any(free.q < model.lower - 1e-2) or np.any(free.q > model.upper + 1e-2)


def test_friction_loss_holds_below_it_and_opposes_above_it():
    """The pendulum horizontal, at rest, gravity's torque m g l = 4.905 N m: a friction loss
    of 6 N m holds it (|v| < 1e-9 over 100 steps, the solver's tolerance; the friction
    torque the holding one to 1e-6); one of 2 N m lets it go at (m g l - 2) / I, I = 0.26
    kg m² (to 1e-9), the friction torque -2 N m against the motion."""
    q0, v0 = np.zeros(1), np.zeros(1)
    held = _pendulum(6.0)
    run = _steps(held, q0, v0, 100)
    assert max(abs(s[1][0]) for s in run) < 1e-9 and abs(run[-1][0][0]) < 1e-9
    s = contact_step(held, None, q0, v0, np.zeros(1), DT, NOWHERE)
    hold = cgadyn.rnea(held, q0, v0, np.zeros(1))
    assert abs(s.friction_torques[0] - hold[0]) < 1e-6
    going = _pendulum(2.0)
    s = contact_step(going, None, q0, v0, np.zeros(1), DT, NOWHERE)
    assert abs(s.v[0] - DT * (0.5 * 9.81 - 2.0) / 0.26) < 1e-9
    assert abs(s.friction_torques[0] + 2.0) < 1e-9
    off = contact_step(held, None, q0, v0, np.zeros(1), DT, NOWHERE, friction_loss=False)
    assert off.v[0] > 0.0


def test_friction_losses_are_read_from_urdf_and_mjcf():
    """URDF's ``<dynamics friction>`` and MJCF's ``frictionloss`` (MuJoCo's
    ``dof_frictionloss``, every dof of the joint) are ``Model.friction``."""
    mujoco = pytest.importorskip("mujoco")
    assert _pendulum(0.7).friction.tolist() == [0.7]
    mj = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body><joint type="hinge" frictionloss="0.3" range="-1 1" '
        'limited="true"/><geom size="0.1" mass="1"/><body pos="0 0 -0.5"><joint type="ball" '
        'frictionloss="0.2"/><geom size="0.1" mass="1"/></body></body></worldbody></mujoco>')
    model = cgadyn.from_mujoco(mj)
    assert model.friction.tolist() == pytest.approx(list(mj.dof_frictionloss), abs=0)
    assert model.friction.tolist() == [0.3, 0.2, 0.2, 0.2]


def test_an_mjcf_reads_mujocos_ranges():
    """Gymnasium's walker2d and ant: each limited hinge's [lower, upper] is MuJoCo's
    ``jnt_range``, an unlimited one's ±inf, and those are the limits a step enforces."""
    mujoco = pytest.importorskip("mujoco")
    from cgadyn.contact.limits import joint_limits

    root = Path(__file__).resolve().parents[1] / "robots" / "mujoco" / "gymnasium"
    for name in ("walker2d", "ant"):
        mj = mujoco.MjModel.from_xml_path(str(root / f"{name}.xml"))
        model = cgadyn.load(root / f"{name}.xml")
        limited = 0
        for j in range(mj.njnt):
            if mj.jnt_type[j] != mujoco.mjtJoint.mjJNT_HINGE:
                continue
            i = model.idx_q[model.joint_names.index(mj.joint(j).name)]
            want = mj.jnt_range[j] if mj.jnt_limited[j] else [-np.inf, np.inf]
            assert [model.lower[i], model.upper[i]] == pytest.approx(list(want), abs=1e-12)
            limited += bool(mj.jnt_limited[j])
        assert limited > 0 and len(joint_limits(model)) == limited


def test_bad_input_is_named():
    model = _pendulum()
    with pytest.raises(ValueError, match="joint_limits=True needs a world"):
        cgadyn.simulate(model, np.zeros(1), np.zeros(1), DT, 5, integrator=SIE,
                        joint_limits=True)
    with pytest.raises(ValueError, match="collisions is None but the world has a ground"):
        contact_step(model, None, np.zeros(1), np.zeros(1), np.zeros(1), DT)
    with pytest.raises(ValueError, match="needs the robot's collision shapes"):
        cgadyn.simulate(model, np.zeros(1), np.zeros(1), DT, 5, integrator=SIE,
                        world=cgadyn.World())
    with pytest.raises(ValueError, match="friction_loss=True needs a world"):
        cgadyn.simulate(model, np.zeros(1), np.zeros(1), DT, 5, integrator=SIE,
                        friction_loss=True)
    with pytest.raises(ValueError, match="joint_limits must be"):
        contact_step(model, None, np.zeros(1), np.zeros(1), np.zeros(1), DT, NOWHERE,
                     joint_limits="yes")
