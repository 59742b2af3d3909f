"""The physical criteria of a contact step (contact/criteria.py, sim/criteria.py;
docs/contact.md K31-K35): zero for solved steps of a box sliding down a slope, of a box
spun on the ground and of solo12 standing, positive for the criterion a wrong force breaks;
the criteria a rollout's record gives equal ``contact_step``'s at the same state; and a box
spun on the ground stops in the time Coulomb's friction at its four corners gives (K35)."""

import math

import numpy as np
import pytest
from contact_cases import solo12_on_the_ground
from test_contact_step import BOX, G, _free, _on_slope, tilted

import cgadyn
from cgadyn.contact.criteria import contact_frame_forces, step_criteria
from cgadyn.contact.problem import contact_jacobian
from cgadyn.contact.step import contact_step, ground_frame

DT = 1e-3
SIE = "semi_implicit_euler"
SOLVED = 1e-8  # the criteria of a step solved to the tolerance of TIGHT
TIGHT = cgadyn.ContactSettings(tolerance=1e-12)


def _sim(model, cm, q, v, steps, world=None, **kw):
    return cgadyn.simulate(model, q, v, DT, steps, integrator=SIE,
                           world=cgadyn.World() if world is None else world, collisions=cm,
                           **kw)


def _solved(history, traj):
    """The criteria of the steps whose solver met its tolerance."""
    ok = traj.contact_residual[:-1] <= TIGHT.tolerance
    assert ok.mean() > 0.9  # most steps solved
    return {name: float(np.nanmax(getattr(history, name)[ok]))
            for name in ("signorini", "approach", "cone", "dissipation")}


def test_each_criterion_measures_what_it_names():
    """Hand-made contacts (t₁, t₂, n): one sticking inside the cone, one sliding with the
    friction of maximal dissipation, one separating: all zero; then each criterion is the
    number its formula gives where a force or velocity breaks it."""
    mu = np.full(3, 0.5)
    f = np.array([[0.3, 0.1, 2.0], [-1.0, 0.0, 2.0], [0.0, 0.0, 0.0]])
    s = np.array([[0.0, 0.0, 0.0], [0.4, 0.0, 0.0], [0.1, 0.0, 0.3]])
    d = np.array([0.0, -1e-4, 2e-3])
    c = step_criteria(f, s, d, mu)
    assert c.maxima() == {"signorini": 0.0, "approach": 0.0, "cone": 0.0,
                          "dissipation": 0.0, "friction_direction": 0.0, "penetration": 1e-4}
    assert list(c.sliding) == [False, True, True]
    bad = step_criteria(np.array([[1.5, 0.0, 2.0]]), np.zeros((1, 3)), [0.0], [0.5])
    assert bad.cone[0] == pytest.approx(0.5) and bad.friction_direction[0] == 0.0  # outside
    turned = step_criteria(np.array([[0.0, 1.0, 2.0]]), np.array([[0.4, 0.0, 0.0]]), [0.0],
                           [0.5])  # on the cone, but across the sliding
    assert turned.cone[0] == 0.0 and turned.dissipation[0] == pytest.approx(0.4)  # μ f_N ‖σ_T‖
    assert turned.friction_direction[0] == pytest.approx(math.sqrt(2.0))
    weak = step_criteria(np.array([[-0.5, 0.0, 2.0]]), np.array([[0.4, 0.0, 0.0]]), [0.0],
                         [0.5])  # against the sliding, but less than the cone allows
    assert weak.dissipation[0] == pytest.approx(0.2) and weak.friction_direction[0] == \
        pytest.approx(0.5)
    pushed = step_criteria(np.array([[0.0, 0.0, 2.0]]), np.array([[0.0, 0.0, 0.25]]), [0.0],
                           [0.5])  # a force on a contact that opens
    assert pushed.signorini[0] == pytest.approx(0.5) and pushed.approach[0] == 0.0
    sinks = step_criteria(np.zeros((1, 3)), np.array([[0.0, 0.0, -0.1]]), [0.0], [0.5])
    assert sinks.approach[0] == pytest.approx(0.1) and sinks.signorini[0] == 0.0
    pulls = step_criteria(np.array([[0.0, 0.0, -1.0]]), np.zeros((1, 3)), [0.0], [0.0])
    assert pulls.cone[0] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="velocities must have shape"):
        step_criteria(f, s[:2], d, mu)


def _with_forces(model, step, q, forces):
    """The contact velocities after the step had its contacts' forces been ``forces``
    (contact frames): ``σ' = σ + G (λ' - λ)`` with ``G = J M⁻¹ Jᵀ`` (K11)."""
    frames = np.array([ground_frame(n) for n in step.contacts.normal])
    J = contact_jacobian(model, q, step.contacts, frames)
    Gm = J @ np.linalg.solve(cgadyn.crba(model, q), J.T)
    now = contact_frame_forces(step.forces, frames)
    change = (Gm @ (forces - now).reshape(-1)) * DT
    return step.velocities + change.reshape(-1, 3)


def test_a_box_sliding_down_a_slope_meets_the_criteria_and_a_wrong_force_fails_them():
    """μ < tan θ: each step's four corners slide with friction on the cone against the
    sliding (criteria below 1e-8); the same step with its friction turned across the sliding,
    or enlarged past the cone, or its normal forces doubled, breaks maximum dissipation, the
    cone, and Signorini's condition in turn."""
    theta, mu = 0.3, 0.1
    model, cm, q, world = _on_slope(theta, mu)
    v = np.zeros(6)
    for _ in range(30):
        s = contact_step(model, cm, q, v, np.zeros(6), DT, world, contact=TIGHT)
        worst = s.criteria.maxima()
        assert max(worst["signorini"], worst["approach"], worst["cone"],
                   worst["dissipation"]) < SOLVED, worst
        q0, q, v = q, s.q, s.v
    assert len(s.contacts) == 4 and s.criteria.sliding.all()
    f = contact_frame_forces(s.forces, [ground_frame(n) for n in s.contacts.normal])
    turned = f.copy()
    turned[:, :2] = f[:, :2] @ np.array([[0.0, 1.0], [-1.0, 0.0]])
    c = step_criteria(turned, _with_forces(model, s, q0, turned), s.contacts.distance,
                      s.contacts.friction)
    assert c.maxima()["dissipation"] > 1e-3 and c.maxima()["friction_direction"] > 0.1
    assert c.maxima()["cone"] < 1e-12
    wide = f.copy()
    wide[:, :2] *= 1.5
    c = step_criteria(wide, _with_forces(model, s, q0, wide), s.contacts.distance,
                      s.contacts.friction)
    assert c.maxima()["cone"] == pytest.approx(0.5 * np.linalg.norm(f[:, :2], axis=1).max())
    pushed = f.copy()
    pushed[:, 2] *= 2.0
    c = step_criteria(pushed, _with_forces(model, s, q0, pushed), s.contacts.distance,
                      s.contacts.friction)
    assert c.maxima()["signorini"] > 1e-3


def test_a_rollout_criteria_are_contact_step_criteria():
    """A box tumbling onto its face (forces from zero each step): at every 10th step the
    contacts and forces ``Trajectory.contacts`` finds again are ``contact_step``'s from the
    same state, and the criteria ``Trajectory.contact_criteria`` gives equal its step's, to
    1e-10; the corner lands without passing into the ground (K24a: Pinocchio's screw
    motion, which the steps once took, let a turning corner end a step below the
    linearised contact's plane)."""
    model, cm = _free(BOX)
    q = tilted(model)
    v = np.array([0.3, 0.0, 0.0, 0.0, 1.0, 0.5])
    tr = _sim(model, cm, q, v, 400, contact=cgadyn.ContactSettings(warm_start=False))
    history = tr.contact_criteria()
    assert history.unmatched == 0 and np.array_equal(history.contacts, tr.contact_count[:-1])
    checked = 0
    for k in range(0, 400, 10):
        s = contact_step(model, cm, tr.q[k], tr.v[k], np.zeros(6), DT)
        found = tr.contacts(k)
        assert len(found) == len(s.contacts) == tr.contact_count[k]
        for c, point, force in zip(found, s.contacts.point, s.forces, strict=True):
            assert c.link == "box" and c.shape == cm[0].name
            assert np.abs(c.point - point).max() < 1e-12
            assert np.abs(c.force - force).max() < 1e-10
        if len(found):
            checked += 1
            worst = s.criteria.maxima()
            for name, value in worst.items():
                assert getattr(history, name)[k] == pytest.approx(value, abs=1e-10), name
    assert checked >= 15
    assert history.maxima()["penetration"] < 1e-12


def test_criteria_need_every_state_and_a_world():
    model, cm = _free(BOX)
    q = cgadyn.neutral(model)
    q[2] = 0.1
    tr = _sim(model, cm, q, np.zeros(6), 10, record_every=2)
    with pytest.raises(ValueError, match="record_every=1"):
        tr.contact_criteria()
    assert [c.link for c in tr.contacts(2)] == ["box"] * 4  # any record_every
    with pytest.raises(ValueError, match="k must index a kept state"):
        tr.contacts(99)
    free = cgadyn.simulate(model, q, np.zeros(6), DT, 5, integrator=SIE)
    with pytest.raises(ValueError, match="no contact"):
        free.contact_criteria()


def _spinning_box(a: float, b: float, c: float, mass: float):
    """A free box of half extents (a, b, c) lying on its face."""
    sides = f"{2 * a} {2 * b} {2 * c}"
    ixx, iyy, izz = (mass * (y * y + z * z) / 3.0 for y, z in ((b, c), (a, c), (a, b)))
    urdf = (f'<robot name="slab"><link name="slab"><inertial><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" iyz="0" izz="{izz}"/>'
            f'</inertial><collision><geometry><box size="{sides}"/></geometry></collision>'
            f'</link></robot>')
    model, cm = _free(urdf)
    q = cgadyn.neutral(model)
    q[2] = c
    return model, cm, q, izz


def test_a_box_spun_on_the_ground_stops_when_coulomb_says():
    """K35: a box on its four bottom corners (each carrying m g / 4 at r = √(a² + b²) from
    the axis) spun at ω₀ about the vertical slows at μ m g r / I_zz: ω(t) is linear (to
    1e-3 of ω₀), stops within two steps of t* = I_zz ω₀ / (μ m g r) and never turns back,
    its centre stays put (1e-6 m), and every step meets the criteria (sliding corners: the
    maximum-dissipation criterion at work)."""
    a, b, c, mass, mu, w0 = 0.2, 0.1, 0.05, 2.0, 0.1, 5.0
    model, cm, q, izz = _spinning_box(a, b, c, mass)
    r = math.hypot(a, b)
    stop = izz * w0 / (mu * mass * G * r)
    steps = int(stop / DT) + 100
    tr = _sim(model, cm, q, np.array([0, 0, 0, 0, 0, w0]), steps,
              world=cgadyn.World(friction=mu), contact=TIGHT)
    assert not tr.diverged, tr.message
    w = tr.v[:, 5]
    moving = tr.t < stop - 2 * DT
    assert np.abs(w[moving] - (w0 - mu * mass * G * r / izz * tr.t[moving])).max() < 1e-3 * w0
    stopped = int(np.argmax(np.abs(w) < 1e-9))
    assert stopped > 0 and abs(tr.t[stopped] - stop) <= 2 * DT
    assert np.abs(w[stopped:]).max() < 1e-9 and w.min() > -1e-9
    assert np.abs(tr.q[:, :3] - q[:3]).max() < 1e-6
    assert np.all(tr.contact_count == 4)
    history = tr.contact_criteria()
    assert max(_solved(history, tr).values()) < SOLVED
    corners = tr.contacts(10)
    assert {round(np.hypot(*p.point[:2]), 12) for p in corners} == {round(r, 12)}


def test_a_box_sliding_down_a_slope_in_a_rollout_meets_the_criteria():
    """The compiled loop's steps of a box sliding down a slope (μ < tan θ, forces warm
    started): every solved step's criteria below 1e-8, with its corners sliding."""
    theta, mu = 0.3, 0.1
    model, cm, q, world = _on_slope(theta, mu)
    tr = _sim(model, cm, q, np.zeros(6), 300, world=world, contact=TIGHT)
    history = tr.contact_criteria()
    assert max(_solved(history, tr).values()) < SOLVED
    assert np.all(history.contacts == 4)


@pytest.mark.slow
def test_solo12_standing_meets_the_criteria():
    """solo12 standing on its feet under joint PD for 1 s: every solved step's criteria
    below 1e-8, and it does not sink into the ground by more than 1e-4 m."""
    model, cm, q = solo12_on_the_ground()
    tr = _sim(model, cm, q, np.zeros(model.nv), 1000,
              controller=cgadyn.PD(kp=20.0, kd=0.5, q_ref=q, gravity_compensation=False),
              contact=TIGHT)
    history = tr.contact_criteria()
    assert history.unmatched == 0
    assert max(_solved(history, tr).values()) < SOLVED
    assert history.maxima()["penetration"] < 1e-4


def test_slots_are_matched_to_their_points_by_the_momentum():
    """The loop keeps forces by slot; with the slots of a spinning box's four corners
    (each sliding its own way) rotated in its record, the criteria found again are those of
    the record as kept: each force is put back at its corner by the step's momentum (K24),
    where left as found every corner's friction would point across its sliding."""
    import dataclasses

    model, cm, q, _ = _spinning_box(0.2, 0.1, 0.05, 2.0)
    tr = _sim(model, cm, q, np.array([0, 0, 0, 0, 0, 5.0]), 100,
              world=cgadyn.World(friction=0.1), contact=TIGHT)
    turned = tr.contact_forces.copy()
    turned[:, [0, 1, 2, 3]] = tr.contact_forces[:, [1, 2, 3, 0]]
    other = dataclasses.replace(tr, contact_forces=turned)
    a, b = tr.contact_criteria(), other.contact_criteria()
    assert b.reordered > 90
    for name in ("signorini", "cone", "dissipation"):
        assert np.abs(getattr(a, name) - getattr(b, name)).max() < 1e-10, name
    assert a.maxima()["dissipation"] < SOLVED
    found, again = tr.contacts(50), other.contacts(50)
    assert all(np.array_equal(x.force, y.force) for x, y in zip(found, again, strict=True))
