"""Ropes (``Model.rope_*``: MuJoCo's limited spatial tendons of two sites) held by the
contact step (docs/contact.md, K46, K46a): read as MuJoCo measures them, a ball on a rope
swinging as a pendulum of the rope's length, the compiled loop against ``contact_step``,
and dm_control's ball_in_cup, whose ball stays on its string."""

import dataclasses

import numpy as np
import pytest

import cgadyn
from cgadyn.multibody.registry import robot_path

mujoco = pytest.importorskip("mujoco")

LENGTH, ANGLE = 0.3, 0.2
PENDULUM = f"""<mujoco><option gravity="0 0 -9.81" timestep="0.001"/>
<worldbody>
 <site name="anchor" pos="0 0 1"/>
 <body name="ball" pos="0 0 1">
  <joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
  <geom type="sphere" size="0.02" mass="0.1" contype="0" conaffinity="0"/>
  <site name="knot"/>
 </body>
</worldbody>
<tendon><spatial name="rope" limited="true" range="0 {LENGTH}">
  <site site="anchor"/><site site="knot"/></spatial></tendon>
</mujoco>"""
"""A ball moving in the xz-plane on a rope of LENGTH from a fixed anchor."""


def _length(model, q, i=0):
    T = cgadyn.link_placements(model, q)
    p = [x if link < 0 else T[link, :3, :3] @ x + T[link, :3, 3]
         for link, x in zip(model.rope_links[i], model.rope_points[i], strict=True)]
    return float(np.linalg.norm(p[0] - p[1]))


def test_a_rope_is_read_and_measured_as_mujoco_measures_it():
    """ball_in_cup's string: its length at random states is MuJoCo's ``ten_length``."""
    model = cgadyn.load("dm_control:ball_in_cup")
    assert model.rope_names == ("string",)
    assert [model.link_names[k] for k in model.rope_links[0]] == ["ball", "cup"]
    np.testing.assert_allclose(model.rope_range, [[0.0, 0.3]])
    mj = mujoco.MjModel.from_xml_path(str(robot_path("dm_control:ball_in_cup")))
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(0)
    for _ in range(5):
        d.qpos[:] = rng.uniform(-0.3, 0.3, mj.nq)
        mujoco.mj_forward(mj, d)
        assert abs(_length(model, d.qpos) - d.ten_length[0]) < 1e-12


def test_a_ball_on_a_rope_swings_as_a_pendulum():
    """Released from rest with the rope taut at 0.2 rad, the ball swings on the circle
    (its distance from the anchor within 1e-5 of the rope's length), with the period of a
    pendulum of that length (``2π sqrt(L / g) (1 + θ₀² / 16)``) to 0.3 %, its energy within
    semi-implicit Euler's own oscillation (0.5 % of the swing's up, 1 % down after three
    swings); without the rope it falls away."""
    model = cgadyn.load(PENDULUM)
    q0 = np.array([LENGTH * np.sin(ANGLE), -LENGTH * np.cos(ANGLE)])
    steps = 3300
    trajectory = cgadyn.simulate(model, q0, np.zeros(2), 1e-3, steps,
                                 integrator="semi_implicit_euler",
                                 world=cgadyn.World(ground=False))
    lengths = np.array([_length(model, q) for q in trajectory.q])
    assert np.abs(lengths - LENGTH).max() < 1e-5
    x = trajectory.q[:, 0]
    crossings = trajectory.t[1:][(x[:-1] > 0.0) & (x[1:] <= 0.0)]  # once a period
    period = 2 * np.pi * np.sqrt(LENGTH / 9.81) * (1 + ANGLE ** 2 / 16)
    assert len(crossings) == 3
    np.testing.assert_allclose(np.diff(crossings), period, rtol=3e-3)
    swing = 0.1 * 9.81 * LENGTH * (1 - np.cos(ANGLE))  # the energy the ball swings with
    energy = trajectory.energy  # semi-implicit Euler's own oscillation: a fraction of dt ω
    assert energy.max() <= energy[0] + 0.005 * swing
    assert energy[-1] >= energy[0] - 0.01 * swing
    free = cgadyn.simulate(model, q0, np.zeros(2), 1e-3, 300,
                           integrator="semi_implicit_euler",
                           world=cgadyn.World(ground=False), joint_limits=False)
    assert _length(model, free.q[-1]) > LENGTH + 0.1  # without it, the ball falls away


def test_the_compiled_loop_is_contact_step_with_a_rope():
    """ball_in_cup's ball thrown sideways from under its cup pulls its string taut and
    swings; the compiled loop equals ``contact_step`` to 1e-12 over 600 steps (cold solver
    starts in both; without the joints' dampers, which the loop takes implicitly), and the
    string is never longer than its range by 1e-4; the same for the pendulum, whose rope's
    first end is fixed in the world, and whose rope's pull (``limit_torques``, the same in
    both) points to the anchor and closes ``m (v⁺ - v) / dt = m g + pull``."""
    model = cgadyn.load("dm_control:ball_in_cup")
    collisions = cgadyn.collision_model(model)
    settings = cgadyn.ContactSettings(warm_start=False)
    q, v = model.home.copy(), np.array([0.0, 0.0, 2.0, 0.0])
    trajectory = cgadyn.simulate(model, q, v, 1e-3, 600, integrator="semi_implicit_euler",
                                 collisions=collisions, contact=settings, passive=False)
    for _ in range(600):
        step = cgadyn.contact_step(model, collisions, q, v, np.zeros(4), 1e-3,
                                   contact=settings, passive=False)
        q, v = step.q, step.v
    np.testing.assert_allclose(trajectory.q[-1], q, atol=1e-12)
    np.testing.assert_allclose(trajectory.v[-1], v, atol=1e-12)
    lengths = [_length(model, x) for x in trajectory.q]
    assert max(lengths) > 0.2999 and max(lengths) < 0.3 + 1e-4
    pendulum, world = cgadyn.load(PENDULUM), cgadyn.World(ground=False)  # its first end
    q, v = np.array([LENGTH * np.sin(ANGLE), -LENGTH * np.cos(ANGLE)]), np.zeros(2)  # fixed
    swing = cgadyn.simulate(pendulum, q, v, 1e-3, 200, integrator="semi_implicit_euler",
                            world=world, contact=settings)
    gravity = np.array([0.0, -0.1 * 9.81])
    for k in range(200):
        step = cgadyn.contact_step(pendulum, None, q, v, np.zeros(2), 1e-3, world=world,
                                   contact=settings)
        pull = step.limit_torques  # the rope's tension: a limit of its tendon's length
        np.testing.assert_allclose(0.1 * (step.v - v) / 1e-3, gravity + pull, atol=1e-9)
        np.testing.assert_allclose(swing.limit_torques[k], pull, atol=1e-9)
        assert np.dot(pull, q) <= 0.0  # towards the anchor
        q, v = step.q, step.v
    assert np.linalg.norm(swing.limit_torques[:200], axis=1).min() > 0.9  # ≈ m g cos θ
    np.testing.assert_allclose(swing.q[-1], q, atol=1e-12)
    np.testing.assert_allclose(swing.v[-1], v, atol=1e-12)


def test_a_rope_is_checked_by_the_model():
    model = cgadyn.load(PENDULUM)
    with pytest.raises(ValueError, match="rope 'rope' has the range"):
        dataclasses.replace(model, rope_range=np.array([[0.0, np.inf]]))
    with pytest.raises(ValueError, match="rope 'rope' joins the links"):
        dataclasses.replace(model, rope_links=np.array([[1, 1]]))


def test_info_lists_the_ropes(capsys):
    import json

    from cgadyn.cli import main

    assert main(["info", "dm_control:ball_in_cup", "--json"]) == 0
    (rope,) = json.loads(capsys.readouterr().out)["ropes"]
    assert rope == {"name": "string", "links": ["ball", "cup"],
                    "points": [[0.0, 0.0, 0.0], [0.0, 0.0, -0.108]], "range": [0.0, 0.3]}
