"""Couplings of coordinates (``Model.coupling_*``, MuJoCo's ``<equality joint>`` and
``<equality tendon>``) held by the contact step (docs/contact.md, K45, K45a): read as MuJoCo
compiles them, an analytic geared pair of sliders against the closed form and against
MuJoCo, the compiled loop against ``contact_step``, and dm_control's quadruped on the
ground with its four leg couplings."""

import dataclasses
import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.couplings import coupling_errors, coupling_rows
from cgadyn.multibody.joints import TYPES
from cgadyn.multibody.registry import robot_path

mujoco = pytest.importorskip("mujoco")

MA, MB, GEAR, FORCE = 2.0, 3.0, 2.0, 1.0
SLIDERS = f"""<mujoco><option gravity="0 0 -9.81" timestep="0.001"/>
<worldbody>
 <body name="a"><joint name="a" type="slide" axis="1 0 0"/>
  <geom type="sphere" size=".1" mass="{MA}" contype="0" conaffinity="0"/></body>
 <body name="b" pos="0 1 0"><joint name="b" type="slide" axis="1 0 0" ref="0.3"/>
  <geom type="sphere" size=".1" mass="{MB}" contype="0" conaffinity="0"/></body>
</worldbody>
<equality><joint name="gear" joint1="a" joint2="b" polycoef="0.1 {GEAR} 0 0 0"
  solref="0.002 1" solimp="0.99 0.999 0.001"/></equality>
</mujoco>"""
"""Two sliders of masses MA and MB held at ``x_a - 0.1 = GEAR (x_b - 0.3)``: a force F on
``a`` alone accelerates ``a`` by ``GEAR² F / (GEAR² MA + MB)`` (Lagrange on ``x_b``)."""
DT, STEPS = 1e-3, 100


def _sliders():
    return cgadyn.load(SLIDERS)


def _start(model):
    q = np.array([0.1, 0.3])  # on the coupling
    assert abs(coupling_errors(coupling_rows(model), q)[0]) < 1e-15
    return q


def test_a_joint_equality_is_read_as_a_linear_coupling():
    model = _sliders()
    assert model.coupling_names == ("gear",)
    np.testing.assert_allclose(model.coupling_coefficients, [[1.0, -GEAR]])
    np.testing.assert_allclose(model.coupling_offset, [0.1 - GEAR * 0.3])


@pytest.mark.parametrize("name", ["dm_control:quadruped", "dm_control:manipulator",
                                  "dm_control:stacker"])
def test_tendon_couplings_are_mujocos_tendon_lengths(name):
    """At random states, each coupling's error ``a · q - b`` is MuJoCo's ``ten_length -
    tendon_length0`` of its tendon, and ``a_k`` the length's change per unit of joint k."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the quadruped's filtered actuators
        model = cgadyn.load(name)
    mj = mujoco.MjModel.from_xml_path(str(robot_path(name)))
    d = mujoco.MjData(mj)
    assert len(model.coupling_names) == mj.neq
    rng = np.random.default_rng(3)
    rows = coupling_rows(model)
    for _ in range(5):
        d.qpos[:] = mj.qpos0 + 0.2 * rng.standard_normal(mj.nq)
        mujoco.mj_normalizeQuat(mj, d.qpos)
        mujoco.mj_forward(mj, d)
        q, _ = cgadyn.from_mujoco_state(model, d.qpos, d.qvel)
        tendons = mj.eq_obj1id[:mj.neq]
        np.testing.assert_allclose(coupling_errors(rows, q),
                                   d.ten_length[tendons] - mj.tendon_length0[tendons],
                                   atol=1e-12)
    for j, t in enumerate(model.joint_types):  # a fixed tendon's length is linear
        if not TYPES[int(t)].additive:
            continue
        jid = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_JOINT, model.joint_names[j])
        before = d.ten_length[tendons].copy()
        d.qpos[mj.jnt_qposadr[jid]] += 1.0
        mujoco.mj_forward(mj, d)
        np.testing.assert_allclose(model.coupling_coefficients[:, model.joint_dofs(j).start],
                                   d.ten_length[tendons] - before, atol=1e-12)


def test_what_a_coupling_cannot_be_is_left_out_with_a_warning():
    curved = SLIDERS.replace(f'polycoef="0.1 {GEAR} 0', 'polycoef="0 1 0.5')
    with pytest.warns(UserWarning, match="couplings 'gear' are left out"):
        assert cgadyn.load(curved).coupling_names == ()
    off = SLIDERS.replace('name="gear"', 'name="gear" active="false"')
    with pytest.warns(UserWarning, match="couplings 'gear' are left out"):
        assert cgadyn.load(off).coupling_names == ()
    model = _sliders()
    with pytest.raises(ValueError, match="coupling 'gear' has the coefficients"):
        dataclasses.replace(model, coupling_coefficients=np.zeros((1, 2)))
    with pytest.raises(ValueError, match="coupling 'gear' has the coefficients"):
        dataclasses.replace(model, coupling_offset=np.array([np.nan]))


def test_a_geared_pair_of_sliders_moves_as_one_body():
    """Under F on ``a`` alone, semi-implicit Euler's velocities are exactly ``t`` times the
    closed-form accelerations, the coupling holds to rounding, its generalised force
    (``coupling_torques``) is the closed form's and closes ``M (v⁺ - v) / dt = τ + aᵀ λ``,
    the compiled loop equals ``contact_step``, and MuJoCo's (soft, stiff) equality gives
    the same motion."""
    model = _sliders()
    world = cgadyn.World(ground=False)
    tau = np.tile([FORCE, 0.0], (STEPS, 1))
    trajectory = cgadyn.simulate(model, _start(model), np.zeros(2), DT, STEPS, tau=tau,
                                 integrator="semi_implicit_euler", world=world)
    accel_a = GEAR ** 2 * FORCE / (GEAR ** 2 * MA + MB)
    t = DT * STEPS
    np.testing.assert_allclose(trajectory.v[-1], [accel_a * t, accel_a * t / GEAR],
                               rtol=1e-12)
    rows = coupling_rows(model)
    assert max(abs(coupling_errors(rows, q)[0]) for q in trajectory.q) < 1e-15
    hold = -FORCE * MB / (GEAR ** 2 * MA + MB)  # the coupling's force: MA ẍ_a = F + λ
    np.testing.assert_allclose(trajectory.coupling_torques, np.tile([hold, -GEAR * hold],
                                                                    (STEPS + 1, 1)),
                               rtol=1e-12)  # aᵀ λ, as M (v⁺ - v) / dt = τ + aᵀ λ
    assert not trajectory.limit_torques.any() and not trajectory.friction_torques.any()
    q, v = _start(model), np.zeros(2)
    for _ in range(STEPS):
        step = cgadyn.contact_step(model, None, q, v, tau[0], DT, world=world)
        np.testing.assert_allclose(
            np.diag([MA, MB]) @ (step.v - v) / DT, tau[0] + step.coupling_torques, atol=1e-12)
        q, v = step.q, step.v
    np.testing.assert_allclose(trajectory.q[-1], q, atol=1e-15)
    np.testing.assert_allclose(trajectory.v[-1], v, atol=1e-15)
    mj = mujoco.MjModel.from_xml_string(SLIDERS)
    d = mujoco.MjData(mj)
    d.qpos[:] = _start(model)
    for _ in range(STEPS):
        d.qfrc_applied[:] = tau[0]
        mujoco.mj_step(mj, d)
    np.testing.assert_allclose(d.qvel, trajectory.v[-1], rtol=1e-6)
    free = cgadyn.simulate(model, _start(model), np.zeros(2), DT, STEPS, tau=tau,
                           integrator="semi_implicit_euler", world=world, couplings=False)
    np.testing.assert_allclose(free.v[-1], [FORCE / MA * t, 0.0], rtol=1e-12)


def test_a_start_off_the_coupling_is_taken_back_without_a_kick():
    """From 1 cm off the coupling and at rest, the position update takes the error back
    by ``stabilization`` a step (K45a) and the sliders gain no speed."""
    model = _sliders()
    q0 = _start(model) + [0.01, 0.0]
    trajectory = cgadyn.simulate(model, q0, np.zeros(2), DT, 50,
                                 integrator="semi_implicit_euler",
                                 world=cgadyn.World(ground=False), gravity=np.zeros(3))
    errors = np.array([coupling_errors(coupling_rows(model), q)[0] for q in trajectory.q])
    np.testing.assert_allclose(errors[1:4], 0.01 * 0.8 ** np.arange(1, 4), rtol=1e-9)
    assert abs(errors[-1]) < 1e-6
    assert np.abs(trajectory.v).max() == 0.0


def test_the_quadruped_keeps_its_leg_couplings_on_the_ground():
    """dm_control's quadruped dropped on its floor with random joint velocities: its four
    couplings (pitch + knee + ankle of each leg held at its length) hold to 1e-6 through
    the impacts and to 1e-9 at the end; without them the legs leave them by centimetres."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its filtered actuators and terrain, left out
        model = cgadyn.load("dm_control:quadruped")
        collisions = cgadyn.collision_model(model)  # its terrain, left out
    rng = np.random.default_rng(1)
    v0 = np.zeros(model.nv)
    v0[6:] = rng.standard_normal(model.nv - 6)
    rows = coupling_rows(model)
    held = cgadyn.simulate(model, model.home, v0, 1e-3, 400,
                           integrator="semi_implicit_euler", collisions=collisions)
    assert held.completed.all() if np.ndim(held.completed) else held.completed
    errors = np.abs([coupling_errors(rows, q) for q in held.q])
    assert errors.max() < 1e-6 and errors[-1].max() < 1e-9
    assert held.energy[-1] <= held.energy[0]
    loose = cgadyn.simulate(model, model.home, v0, 1e-3, 400,
                            integrator="semi_implicit_euler", collisions=collisions,
                            couplings=False)
    assert np.abs(coupling_errors(rows, loose.q[-1])).max() > 1e-2


def test_a_coupled_model_without_a_world_is_refused_by_name():
    model = _sliders()
    with pytest.raises(ValueError, match="has the couplings 'gear', which the contact step"):
        cgadyn.simulate(model, _start(model), np.zeros(2), DT, 10)
    with pytest.raises(ValueError, match="couplings must be True, False or None"):
        cgadyn.simulate(model, _start(model), np.zeros(2), DT, 10, couplings="yes")
    with pytest.raises(ValueError, match="couplings must be True or False"):
        cgadyn.contact_step(model, None, _start(model), np.zeros(2), np.zeros(2), DT,
                            world=cgadyn.World(ground=False), couplings=None)
    free = cgadyn.simulate(model, _start(model), np.zeros(2), DT, 10, couplings=False)
    assert free.completed


def test_the_command_line_shows_couplings_and_asks_for_the_ground(capsys):
    from cgadyn.cli import main

    assert main(["info", "dm_control:manipulator", "--json"]) == 0
    import json

    info = json.loads(capsys.readouterr().out)
    (coupling,) = info["couplings"]
    assert coupling["name"] == "coupling"
    assert coupling["joints"] == {"thumb": -0.5, "finger": 0.5}
    assert main(["simulate", "dm_control:manipulator", "--seconds", "0.01"]) == 2
    assert "couples its joints ('coupling'), which the contact step holds: add --ground" \
        in capsys.readouterr().err
