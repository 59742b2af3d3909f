"""The contact step's implicit gains (K40) and compliant contacts (K41), docs/contact.md:
the compiled step equals ``contact_step`` on the model whose armature carries ``dt D + dt²
K`` under the shifted torque; a PD far too stiff for an explicit step holds a pendulum
without gaining energy; a compliant box rests sunk by its weight over its stiffness; bad
compliance is named."""

import dataclasses

import numpy as np
import pytest
from contact_cases import solo12_on_the_ground
from test_contact_step import BOX, G, _free

import cgadyn
from cgadyn.contact.step import contact_step

DT = 1e-3
SIE = "semi_implicit_euler"
PENDULUM = ('<robot name="pendulum"><link name="base"/><link name="arm"><inertial>'
            '<origin xyz="0 0 -0.5"/><mass value="1"/>'
            '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
            '</link><joint name="hinge" type="continuous"><parent link="base"/>'
            '<child link="arm"/><axis xyz="0 1 0"/></joint></robot>')


def _sim(model, cm, q, v, steps, world=None, dt=DT, **kw):
    return cgadyn.simulate(model, q, v, dt, steps, integrator=SIE,
                           world=cgadyn.World() if world is None else world, collisions=cm,
                           **kw)


@pytest.mark.slow
def test_the_compiled_step_is_contact_step_with_the_gains_in_the_mass_matrix():
    """50 steps of solo12 landing under joint PD equal ``contact_step``'s (q, v to 1e-10)
    on the model whose armature is ``dt K_d + dt² K_p`` more, under the torque ``K_p (q_ref
    - q) - K_d v - dt K_p v`` (K40)."""
    model, cm, q = solo12_on_the_ground()
    q[2] += 0.002
    kp, kd = 20.0, 0.5
    pd = cgadyn.PD(kp=kp, kd=kd, q_ref=q, gravity_compensation=False)
    tr = _sim(model, cm, q, np.zeros(model.nv), 50, controller=pd,
              contact=cgadyn.ContactSettings(warm_start=False))
    act = np.asarray(model.actuated, dtype=float)
    stepped = dataclasses.replace(model, armature=model.armature + act * (DT * kd + DT**2 * kp))
    qk, vk = q, np.zeros(model.nv)
    assert np.max(tr.contact_count) >= 4
    for k in range(51):
        assert np.abs(tr.q[k] - qk).max() < 1e-10 and np.abs(tr.v[k] - vk).max() < 1e-10
        tau = np.zeros(model.nv)
        tau[6:] = kp * (q[7:] - qk[7:]) - kd * vk[6:] - DT * kp * vk[6:]
        s = contact_step(stepped, cm, qk, vk, tau, DT)
        qk, vk = s.q, s.v


def test_a_pd_too_stiff_for_an_explicit_step_holds_a_pendulum():
    """A pendulum under ``K_p dt² = 100`` times its inertia: the step with a world (no
    ground: the joint alone) takes the gains at its end (K40), settles on ``q_ref`` and its
    energy with the PD's spring never rises; the explicit semi-implicit Euler step without
    a world diverges."""
    model = cgadyn.load(PENDULUM)
    inertia = float(cgadyn.crba(model, np.zeros(1))[0, 0])
    dt = 1e-2
    kp, kd = 100.0 * inertia / dt**2, 0.0
    pd = cgadyn.PD(kp=kp, kd=kd, q_ref=np.array([0.3]))
    nowhere = cgadyn.World(ground=False)
    tr = _sim(model, None, np.zeros(1), np.zeros(1), 200, world=nowhere, dt=dt, controller=pd)
    assert not tr.diverged, tr.message
    spring = 0.5 * kp * (0.3 - tr.q[:, 0]) ** 2
    kinetic = 0.5 * inertia * tr.v[:, 0] ** 2  # gravity compensated by the PD: no potential
    total = spring + kinetic
    assert np.all(np.diff(total) <= 1e-9 * total[0])
    assert abs(tr.q[-1, 0] - 0.3) < 1e-6 and abs(tr.v[-1, 0]) < 1e-6
    with pytest.warns(cgadyn.SimulationDiverged):
        free = cgadyn.simulate(model, np.zeros(1), np.zeros(1), dt, 200, integrator=SIE,
                               controller=pd)
    assert free.diverged


def _compliant_box(k: float, c: float):
    model, cm = _free(BOX)
    soft = cm.compliant(k, c)
    q = cgadyn.neutral(model)
    q[2] = 0.1
    return model, soft, q


def test_a_compliant_box_rests_sunk_by_its_weight_over_its_stiffness():
    """A 2 kg box on four compliant corners (k = 2e4 N/m each, critically damped) settles
    with each corner ``m g / (4 k)`` deep to 1e-9 m, the ground carrying its weight to
    1e-6 relative (K41)."""
    k = 2e4
    c = 2.0 * np.sqrt(4 * k * 2.0) / 4
    model, cm, q = _compliant_box(k, c)
    tr = _sim(model, cm, q, np.zeros(6), 3000)
    assert not tr.diverged, tr.message
    weight = 2.0 * G
    assert tr.contact_forces[-1, :, 2].sum() == pytest.approx(weight, rel=1e-6)
    depth = -cgadyn.ground_contacts(model, cm, tr.q[-1], margin=1e-3).distance
    assert np.allclose(depth, weight / (4 * k), atol=1e-9)
    assert abs(tr.q[-1, 2] - (0.1 - weight / (4 * k))) < 1e-9


def test_a_compliant_step_is_contact_step():
    """A box dropped on compliant corners: 80 steps of the compiled loop equal
    ``contact_step``'s (q, v to 1e-10)."""
    model, cm, q = _compliant_box(5e3, 20.0)
    q[2] = 0.103
    v = np.array([0.2, 0.0, -0.3, 0.0, 0.5, 0.0])
    tr = _sim(model, cm, q, v, 80, contact=cgadyn.ContactSettings(warm_start=False))
    assert np.max(tr.contact_count) >= 2
    for k in range(81):
        assert np.abs(tr.q[k] - q).max() < 1e-10 and np.abs(tr.v[k] - v).max() < 1e-10
        s = contact_step(model, cm, q, v, np.zeros(6), DT)
        q, v = s.q, s.v


def test_bad_compliance_is_named():
    model, cm = _free(BOX)
    with pytest.raises(ValueError, match="stiffness must be a finite number >= 0"):
        cm.compliant(-1.0)
    with pytest.raises(ValueError, match="damping must be a finite number >= 0"):
        cm.compliant(1.0, float("nan"))
    with pytest.raises(ValueError, match="no link 'foot'"):
        cm.compliant(1.0, links=["foot"])
    assert np.all(cm.compliant(3.0, 4.0).compliance == [3.0, 4.0])
    assert np.all(cm.compliant(3.0).compliant(0.0).compliance == 0.0)


def _uneven_sole(k: float, c: float):
    """A 2 kg plate whose sole is the convex hull of a 5 x 3 grid of points a fraction of a
    millimetre apart in height (a mesh foot's), compliant, resting level on the ground."""
    model = cgadyn.load('<robot name="plate"><link name="plate"><inertial><mass value="2"/>'
                        '<inertia ixx="0.002" ixy="0" ixz="0" iyy="0.007" iyz="0" izz="0.008"/>'
                        '</inertial></link></robot>', floating_base=True)
    rise = np.array([[0.0, 0.21, 0.05, 0.3, 0.12], [0.17, 0.02, 0.26, 0.08, 0.23],
                     [0.09, 0.28, 0.14, 0.01, 0.19]]) * 1e-3
    xs, ys = np.linspace(-0.1, 0.1, 5), np.linspace(-0.05, 0.05, 3)
    bottom = [[x, y, rise[j, i]] for j, y in enumerate(ys) for i, x in enumerate(xs)]
    top = [[x, y, 0.02] for x in (-0.1, 0.1) for y in (-0.05, 0.05)]
    sole = cgadyn.Collision("sole", cgadyn.ConvexMesh(np.array(bottom + top)), 0, np.eye(4))
    cm = cgadyn.CollisionModel([sole], model).compliant(k, c)
    q = cgadyn.neutral(model)
    q[2] -= cgadyn.ground_contacts(model, cm, q, margin=1.0).distance.min()
    return model, cm, q


def test_an_uneven_compliant_sole_is_solved_every_step_and_rests():
    """A plate on a compliant sole uneven by 0.3 mm (K41), pushed sideways for a moment,
    then left: every step's contact problem meets the tolerance (PGS in tens of sweeps:
    held on the plane, K42, the sole's self-balanced friction is no nearly-null direction
    of ``G + R``), the patch's points stay the same from step to step (K22'), and the plate
    comes to rest on the ground, which carries its weight to 1e-6."""
    k = 2e4
    model, cm, q = _uneven_sole(k, 2.0 * np.sqrt(k * 2.0))
    tau = np.zeros((2000, 6))
    tau[:200, 0] = 5.0  # 5 N along x for 0.2 s: less than friction's 19.6 N
    tr = _sim(model, cm, q, np.zeros(6), 2000, tau=tau)
    assert not tr.diverged, tr.message
    assert np.all(tr.contact_residual <= 1e-10)
    assert np.mean(tr.contact_iterations) < 50
    assert np.all(tr.contact_count[1000:] == tr.contact_count[-1]) and tr.contact_count[-1] >= 3
    ends = [cgadyn.ground_contacts(model, cm, x, margin=1e-3).point for x in tr.q[-500:]]
    assert all(p.shape == ends[-1].shape and np.abs(p - ends[-1]).max() < 1e-6 for p in ends)
    assert np.abs(tr.v[-1]).max() < 1e-6
    assert tr.contact_forces[-1, :, 2].sum() == pytest.approx(2.0 * G, rel=1e-6)
