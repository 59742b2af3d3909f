"""The velocity-level contact step (contact/step.py; docs/contact.md K23-K24) checked by
physics: a ball dropped comes to rest without bouncing, a box on a tilted plane sticks or
slides as Coulomb's law says, a dropped box never gains energy, and solo12 stands on its
feet with the ground carrying its weight."""

import math

import numpy as np
import pytest
from contact_cases import solo12_on_the_ground

import cgadyn
from cgadyn.contact.step import contact_step, ground_frame
from cgadyn.contact.world import World

G = 9.81


def _body(name: str, geometry: str, mass: float, inertia) -> str:
    ixx, iyy, izz = inertia
    return (f'<robot name="{name}"><link name="{name}"><inertial><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" iyz="0" izz="{izz}"/>'
            f'</inertial><collision><geometry>{geometry}</geometry></collision></link>'
            f'</robot>')


def _free(urdf: str):
    model = cgadyn.load(urdf, floating_base=True)
    return model, cgadyn.collision_model(model, urdf)


BALL = _body("ball", '<sphere radius="0.1"/>', 1.0, [0.004] * 3)
BOX = _body("box", '<box size="0.2 0.2 0.2"/>', 2.0, [2.0 * 0.08 / 12] * 3)


def _run(model, cm, q, v, steps, dt=1e-3, world=None, tau=None):
    tau = np.zeros(model.nv) if tau is None else tau
    out = []
    for _ in range(steps):
        s = contact_step(model, cm, q, v, tau, dt, world)
        q, v = s.q, s.v
        out.append(s)
    return out


def test_a_dropped_ball_comes_to_rest_without_bouncing():
    """A ball dropped from 1 m (restitution 0, dt = 1e-3): once it touches it never rises
    again, it penetrates the ground by at most 1e-4 m, and it ends at rest with the ground
    carrying its weight."""
    model, cm = _free(BALL)
    q = cgadyn.neutral(model)
    q[2] = 1.0
    steps = _run(model, cm, q, np.zeros(6), 700)
    z = np.array([s.q[2] for s in steps])
    touch = int(np.argmax(z < 0.1 + 1e-3))
    assert 0 < touch < 500
    assert np.all(np.diff(z[touch:]) <= 1e-12)  # no bounce
    assert z.min() >= 0.1 - 1e-4
    assert np.abs(steps[-1].v).max() < 1e-9
    assert steps[-1].forces.sum(axis=0) == pytest.approx([0.0, 0.0, G], abs=1e-6)


def tilted(model):
    """A free body's configuration 0.4 m up, tilted so that it lands on a corner."""
    q = cgadyn.neutral(model)
    q[2] = 0.4
    q[3:7] = [math.sin(0.2), math.sin(0.1), 0.0, 1.0]
    q[3:7] /= np.linalg.norm(q[3:7])
    return q


def test_a_dropped_box_never_gains_energy():
    """A box dropped tilted onto a corner tumbles onto a face: its total energy never rises
    (by more than 1e-9 of its initial energy) from one step to the next."""
    model, cm = _free(BOX)
    q = tilted(model)
    steps = _run(model, cm, q, np.array([0.3, 0.0, 0.0, 0.0, 1.0, 0.5]), 800)
    energy = np.array([cgadyn.kinetic_energy(model, s.q, s.v) + cgadyn.potential_energy(
        model, s.q) for s in steps])
    assert np.all(np.diff(energy) <= 1e-9 * abs(energy[0]))
    assert np.abs(steps[-1].v).max() < 1e-6  # at rest on a face
    assert steps[-1].q[2] == pytest.approx(0.1, abs=1e-4)


def _on_slope(theta: float, mu: float):
    n = np.array([0.0, -math.sin(theta), math.cos(theta)])
    world = World(ground_normal=n, friction=mu)
    model, cm = _free(BOX)
    q = cgadyn.neutral(model)
    q[:3] = 0.1 * n  # the box's bottom face on the slope
    q[3:7] = [math.sin(theta / 2), 0.0, 0.0, math.cos(theta / 2)]
    return model, cm, q, world


def test_a_box_sticks_on_a_slope_within_its_friction_cone():
    """μ ≥ tan θ: the box stays put (moves less than 1e-9 m in 1 s)."""
    theta = 0.2
    model, cm, q, world = _on_slope(theta, mu=1.2 * math.tan(theta))
    steps = _run(model, cm, q, np.zeros(6), 1000, world=world)
    assert np.linalg.norm(steps[-1].q[:3] - q[:3]) < 1e-9


def test_a_box_slides_down_a_slope_as_coulomb_says():
    """μ < tan θ: the box slides with acceleration g (sin θ - μ cos θ) down the slope (to
    1e-3 relative), without leaving it."""
    theta, mu = 0.3, 0.1
    model, cm, q, world = _on_slope(theta, mu)
    dt, steps = 1e-3, 500
    run = _run(model, cm, q, np.zeros(6), steps, dt=dt, world=world)
    down = np.array([0.0, -math.cos(theta), -math.sin(theta)])  # along the slope, down
    R = cgadyn.link_placements(model, run[-1].q)[0][:3, :3]
    speed = (R @ run[-1].v[:3]) @ down  # the base's linear velocity is in its frame
    assert speed / (steps * dt) == pytest.approx(G * (math.sin(theta) - mu * math.cos(theta)),
                                                 rel=1e-3)
    n = np.asarray(world.ground_normal)
    assert abs((run[-1].q[:3] - q[:3]) @ n) < 1e-6


def test_the_ground_frame_is_orthonormal_with_the_normal_last():
    for n in ([0, 0, 1], [0.6, 0.0, 0.8], [1, 0, 0]):
        F = ground_frame(np.asarray(n, float) / np.linalg.norm(n))
        assert np.allclose(F @ F.T, np.eye(3)) and np.isclose(np.linalg.det(F), 1.0)
        assert np.allclose(F[2], np.asarray(n) / np.linalg.norm(n))


@pytest.mark.slow
def test_solo12_stands_on_its_feet():
    """solo12 lowered onto the ground in its standing posture, its joints held by PD: its
    base is steady (moves less than 1 mm in the last 0.2 s of 0.6 s), only its feet touch,
    and the ground's forces, averaged over that time, carry its weight (to 1e-2: the PD
    posture still sways slowly)."""
    model, cm, q = solo12_on_the_ground()
    q_ref = q[7:].copy()
    v = np.zeros(model.nv)
    heights, lift = [], []
    for _ in range(600):
        tau = np.zeros(model.nv)
        tau[6:] = 20.0 * (q_ref - q[7:]) - 0.5 * v[6:]
        s = contact_step(model, cm, q, v, tau, 1e-3)
        q, v = s.q, s.v
        heights.append(q[2])
        lift.append(s.forces[:, 2].sum())
    assert np.ptp(heights[-200:]) < 1e-3
    assert {cm[k].name for k in s.contacts.collision} <= {"FL_FOOT_0", "FR_FOOT_0",
                                                           "HL_FOOT_0", "HR_FOOT_0"}
    weight = G * cgadyn.total_mass(model)
    assert np.mean(lift[-200:]) == pytest.approx(weight, rel=1e-2)


def test_bad_input_is_named():
    model, cm = _free(BALL)
    q = cgadyn.neutral(model)
    with pytest.raises(ValueError, match="dt must be"):
        contact_step(model, cm, q, np.zeros(6), np.zeros(6), 0.0)
    with pytest.raises(ValueError, match="tau: expected shape"):
        contact_step(model, cm, q, np.zeros(6), np.zeros(5), 1e-3)
    with pytest.raises(ValueError, match="stabilization"):
        contact_step(model, cm, q, np.zeros(6), np.zeros(6), 1e-3,
                     contact=cgadyn.ContactSettings(stabilization=2.0))
