"""Rollouts with contact (sim/contact.py; docs/contact.md, "Rollouts with contact"): the
compiled loop's step equals ``contact_step``'s, a ball comes to rest carrying its weight, a
tumbling box never gains energy, solo12 stands under joint PD, a batch equals its single
runs, and bad input is named."""


import numpy as np
import pytest
from contact_cases import solo12_on_the_ground
from test_contact_step import BALL, BOX, G, _free, tilted

import cgadyn
from cgadyn.contact.step import contact_step

DT = 1e-3
SIE = "semi_implicit_euler"


def _sim(model, cm, q, v, steps, **kw):
    return cgadyn.simulate(model, q, v, DT, steps, integrator=SIE, world=cgadyn.World(),
                           collisions=cm, **kw)


def _steps(model, cm, q, v, steps, tau=lambda q, v: None):
    out = [(q, v)]
    for _ in range(steps):
        t = tau(q, v)
        s = contact_step(model, cm, q, v, np.zeros(model.nv) if t is None else t, DT)
        q, v = s.q, s.v
        out.append((q, v))
    return out


def test_the_compiled_step_is_contact_step_for_a_ball():
    """50 steps of a ball landing, spinning and sliding: q, v equal ``contact_step``'s to
    1e-10 (forces from zero each step, as ``contact_step`` starts them)."""
    model, cm = _free(BALL)
    q = cgadyn.neutral(model)
    q[2] = 0.102
    v = np.array([0.3, 0.0, -0.2, 0.0, 2.0, 0.5])
    tr = _sim(model, cm, q, v, 50, contact=cgadyn.ContactSettings(warm_start=False))
    ref = _steps(model, cm, q, v, 50)
    assert np.max(tr.contact_count) == 1
    for k, (qk, vk) in enumerate(ref):
        assert np.abs(tr.q[k] - qk).max() < 1e-10 and np.abs(tr.v[k] - vk).max() < 1e-10


@pytest.mark.parametrize("warm", [False, True])
def test_a_dropped_ball_rests_without_bouncing_carrying_its_weight(warm):
    """Dropped from 1 m: no rise after touching, at rest at the end, the ground's force its
    weight to 1e-6. From zero forces each step (as ``contact_step``) that holds at every
    step; warm-started (K25), ADMM stops as soon as the stopping rule passes, whose
    complementarity tolerance (1e-10 on λ·σ) leaves the force within 1e-4 of the weight at
    each step and to 1e-6 on average over the last 0.2 s (the ball rising < 1e-10 m a
    step, its speed < 1e-8 m/s: the correction β d / dt of a ~1e-11 m overlap)."""
    model, cm = _free(BALL)
    q = cgadyn.neutral(model)
    q[2] = 1.0
    tr = _sim(model, cm, q, np.zeros(6), 700, contact=cgadyn.ContactSettings(warm_start=warm))
    z = tr.q[:, 2]
    touch = int(np.argmax(tr.contact_count > 0))
    assert 0 < touch < 500
    assert np.all(np.diff(z[touch + 1:]) <= (1e-10 if warm else 1e-12))
    assert np.abs(tr.v[-1]).max() < (1e-8 if warm else 1e-9)
    lift = tr.contact_forces[-200:].sum(axis=1)
    assert np.all(np.abs(lift[:, :2]) < 1e-9)
    assert np.abs(lift[:, 2] - G).max() < (1e-4 if warm else 1e-6)
    assert np.mean(lift[:, 2]) == pytest.approx(G, abs=1e-6)
    assert np.all(tr.contact_forces[-1, 1:] == 0.0)  # the unused slots hold zeros


def test_a_tumbling_box_never_gains_energy():
    """A box dropped tilted onto a corner: its energy never rises by more than 1e-9 of its
    initial energy between steps, and it ends at rest on a face."""
    model, cm = _free(BOX)
    q = tilted(model)
    tr = _sim(model, cm, q, np.array([0.3, 0.0, 0.0, 0.0, 1.0, 0.5]), 800)
    energy = tr.kinetic + tr.potential
    assert np.all(np.diff(energy) <= 1e-9 * abs(energy[0]))
    assert np.abs(tr.v[-1]).max() < 1e-6
    assert tr.q[-1, 2] == pytest.approx(0.1, abs=1e-4)


def test_a_rolling_ball_stays_on_the_ground_and_goes_straight():
    """A ball rolling at 1 and 3 m/s for 1 s: it stays on the ground to 1e-12 m, travels
    v t to 1e-12 m and keeps its kinetic energy to 1e-12. The Euler step moves its centre
    straight along its world velocity (K24a), where Pinocchio's screw motion carried it on
    an arc into the ground, 25 µm deep at 1 m/s and 0.23 mm at 3 m/s."""
    model, cm = _free(BALL)
    q = cgadyn.neutral(model)
    q[2] = 0.1
    for speed in (1.0, 3.0):
        v = np.array([speed, 0.0, 0.0, 0.0, speed / 0.1, 0.0])  # rolling: v = ω r
        tr = _sim(model, cm, q, v, 1000)
        assert np.abs(tr.q[:, 2] - 0.1).max() < 1e-12
        assert np.abs(tr.q[:, 0] - speed * tr.t).max() < 1e-12
        assert np.abs(tr.kinetic - tr.kinetic[0]).max() < 1e-12 * tr.kinetic[0]


def test_a_batch_equals_its_single_runs():
    """8 balls from different states in one call equal 8 calls of one, bit for bit."""
    model, cm = _free(BALL)
    rng = np.random.default_rng(3)
    q0 = np.tile(cgadyn.neutral(model), (8, 1))
    q0[:, 2] = 0.1 + 0.01 * rng.random(8)
    v0 = rng.normal(size=(8, 6))
    batch = _sim(model, cm, q0, v0, 60)
    for b in range(8):
        one = _sim(model, cm, q0[b], v0[b], 60)
        assert np.array_equal(batch.q[b], one.q) and np.array_equal(batch.v[b], one.v)
        assert np.array_equal(batch.contact_forces[b], one.contact_forces)


def test_bad_input_is_named():
    model, cm = _free(BALL)
    q, v = cgadyn.neutral(model), np.zeros(6)
    with pytest.raises(ValueError, match="collision shapes"):
        cgadyn.simulate(model, q, v, DT, 2, integrator=SIE, world=cgadyn.World())
    with pytest.raises(ValueError, match="semi_implicit_euler"):
        cgadyn.simulate(model, q, v, DT, 2, world=cgadyn.World(), collisions=cm)
    with pytest.raises(ValueError, match="without a world"):
        cgadyn.simulate(model, q, v, DT, 2, integrator=SIE, collisions=cm)
    with pytest.raises(ValueError, match="cgadyn.World"):
        cgadyn.simulate(model, q, v, DT, 2, integrator=SIE, world="ground", collisions=cm)


def test_a_step_short_of_the_tolerance_is_kept_within_accept_and_stops_above_it():
    """The tumbling box with one iteration per solver: with ``accept`` at the tolerance the
    first hard step stops the rollout, naming its residuals; with a loose ``accept`` the run
    completes, each kept residual within it, and ``contact_iterations`` counts both
    solvers (at most 2)."""
    model, cm = _free(BOX)
    q, v = tilted(model), np.array([0.3, 0.0, 0.0, 0.0, 1.0, 0.5])
    strict = cgadyn.ContactSettings(max_iterations=1, tolerance=1e-10, accept=1e-10)
    with pytest.warns(cgadyn.SimulationDiverged):
        tr = _sim(model, cm, q, v, 300, contact=strict)
    assert tr.diverged and tr.completed < 300
    assert "the contact solvers did not converge in 2 iterations" in tr.message
    assert "above ContactSettings.accept" in tr.message
    loose = cgadyn.ContactSettings(max_iterations=1, accept=1e6)
    tr = _sim(model, cm, q, v, 300, contact=loose)
    assert not tr.diverged and tr.completed == 300
    hard = tr.contact_residual > 1e-10
    assert hard.any() and np.all(tr.contact_residual <= 1e6)
    assert set(np.unique(tr.contact_iterations)) <= {0, 1, 2}
    with pytest.raises(ValueError, match="accept"):
        cgadyn.ContactSettings(tolerance=1e-6, accept=1e-8)
    with pytest.raises(ValueError, match="solver must be one of"):
        cgadyn.ContactSettings(solver="newton")
    with pytest.raises(ValueError, match="ContactSettings"):
        cgadyn.simulate(model, q, v, DT, 2, integrator=SIE, world=cgadyn.World(),
                        collisions=cm, contact={"solver": "pgs"})


@pytest.mark.slow
def test_solo12_stands_for_five_seconds():
    """solo12 on its feet under joint PD for 5 s: its base moves less than 1e-6 m over the
    last second, only the feet touch, and the ground carries its weight."""
    model, cm, q = solo12_on_the_ground()
    tr = _sim(model, cm, q, np.zeros(model.nv), 5000,
              controller=cgadyn.PD(kp=20.0, kd=0.5, q_ref=q, gravity_compensation=False))
    assert not tr.diverged, tr.message
    base = tr.q[-1001:, :3]
    assert np.max(np.linalg.norm(base - base[-1], axis=1)) < 1e-6
    feet = [k for k, c in enumerate(cm) if c.name.endswith("_FOOT_0")]
    slots = [4 * k + i for k in feet for i in range(4)]
    others = np.setdiff1d(np.arange(tr.contact_forces.shape[1]), slots)
    assert np.all(tr.contact_forces[-1, others] == 0.0)
    weight = G * cgadyn.total_mass(model)
    assert tr.contact_forces[-1, :, 2].sum() == pytest.approx(weight, rel=1e-6)


def test_solo12_held_by_its_base_stands_on_the_ground():
    """A world and constraints in one rollout (docs/constraints.md, C14): solo12 on the
    ground under joint PD, its base held where it starts by a point constraint. Over 1 s the
    held point stays within 1e-6 m, the feet touch the ground, and at rest the ground and the
    constraint together carry the weight (to 1e-6), with no net horizontal force. Without
    the constraint the base sinks by millimetres."""
    model, cm, q = solo12_on_the_ground()
    hold = [cgadyn.Constraint(model, "point", "base_link", q=q, corrector=(100.0, 20.0))]
    pd = cgadyn.PD(kp=20.0, kd=0.5, q_ref=q, gravity_compensation=False)
    zero = np.zeros(model.nv)
    tr = _sim(model, cm, q, zero, 1000, controller=pd, constraints=hold)
    assert not tr.diverged, tr.message
    assert tr.constraint_violation[:, 0, 0].max() < 1e-6
    weight = G * cgadyn.total_mass(model)
    for k in (-2, -1):  # the last state's: of the one more step the loop solves from it
        ground = tr.contact_forces[k, :, 2].sum()
        assert ground > 0.05 * weight  # the feet carry part of it
        assert ground + tr.forces[k, 2] == pytest.approx(weight, rel=1e-6)
        assert np.abs(tr.forces[k, :2] + tr.contact_forces[k, :, :2].sum(axis=0)).max() \
            < 1e-6 * weight
    free = _sim(model, cm, q, zero, 1000, controller=pd)
    assert q[2] - free.q[-1, 2] > 1e-3


def _talos_on_its_soles(stiffness: float = 0.0):
    """talos_reduced with its lowest vertex on the ground, its soles (the links within 1 cm
    of it) compliant where ``stiffness`` > 0 (critically damped for its mass on one
    point), and the command's joint PD about that posture."""
    import warnings

    from cgadyn.commands.simulate import pd_gains
    from cgadyn.multibody import registry

    model = cgadyn.load("talos_reduced")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        cm = cgadyn.collision_model(model, registry.robot_path("talos_reduced"))
    q = cgadyn.neutral(model)
    found = cgadyn.ground_contacts(model, cm, q, margin=1e9)
    q[2] -= found.distance.min()  # the lowest vertex on the ground
    support = tuple({int(link) for link, d in zip(found.link, found.distance, strict=True)
                     if d <= found.distance.min() + 0.01})
    if stiffness > 0.0:
        mass = cgadyn.total_mass(model)
        cm = cm.compliant(stiffness, 2.0 * np.sqrt(stiffness * mass), links=support)
    kp, kd = pd_gains(model, q, 10.0, support)
    return model, cm, q, cgadyn.PD(kp, kd, q_ref=q)


def test_talos_stands_still_on_its_soles():
    """talos_reduced on its soles (their mesh hulls, uneven by a fraction of a millimetre)
    under the command's joint PD for 3 s: it settles onto a face of each sole's hull and
    stays there (K22's choice keeps the vertices it rests on, TILT), its base moving less
    than 1 mm over the run and less than 1e-6 m over the last second, every velocity below
    1e-5 at the end, the ground carrying its weight to 1e-6; every step's contact problem
    meets the tolerance (its knees' limit and friction rows solved together, K29a)."""
    model, cm, q, pd = _talos_on_its_soles()
    tr = _sim(model, cm, q, np.zeros(model.nv), 3000, controller=pd)
    assert not tr.diverged, tr.message
    assert np.all(tr.contact_residual <= 1e-10)
    assert np.max(np.abs(tr.q[:, 2] - q[2])) < 1e-3
    base = tr.q[-1001:, :3]
    assert np.max(np.linalg.norm(base - base[-1], axis=1)) < 1e-6
    assert np.abs(tr.v[-1]).max() < 1e-5
    weight = G * cgadyn.total_mass(model)
    assert tr.contact_forces[-1, :, 2].sum() == pytest.approx(weight, rel=1e-6)


def test_talos_stands_on_soft_soles():
    """talos_reduced on compliant soles (k = 1e5 N/m a point) under the same PD for 5 s:
    every step's contact problem meets the tolerance, in tens of PGS sweeps (K42, K29a;
    before, the rollout stopped within 0.3 s, neither solver reaching ``accept``), the
    soles' corners stay the same, mirror images of each other (K22'), and talos settles,
    sunk about a millimetre and not drifting sideways, the ground carrying its weight to
    1e-6."""
    model, cm, q, pd = _talos_on_its_soles(1e5)
    tr = _sim(model, cm, q, np.zeros(model.nv), 5000, controller=pd)
    assert not tr.diverged, tr.message
    assert np.all(tr.contact_residual <= 1e-10)
    assert np.mean(tr.contact_iterations) < 100
    assert 2e-4 < q[2] - tr.q[-1, 2] < 5e-3
    assert abs(tr.q[-1, 1] - q[1]) < 1e-3
    assert np.abs(tr.v[-1]).max() < 1e-4
    weight = G * cgadyn.total_mass(model)
    assert tr.contact_forces[-1, :, 2].sum() == pytest.approx(weight, rel=1e-6)
