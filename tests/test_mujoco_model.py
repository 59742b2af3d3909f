"""MJCF through MuJoCo's compiler (``cgadyn.from_mujoco``) checked against MuJoCo itself
(``cgadyn.mujoco_oracle``): Gymnasium's and dm_control's suite models (copies under
``robots/mujoco/``), random states, contacts, limits and equalities off; body placements,
the mass matrix with armature, inverse dynamics with the passive torques, forward
dynamics, the passive torques. Also the state conversions and what is refused."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import cgadyn  # noqa: E402
from cgadyn import mujoco_oracle, oracle  # noqa: E402
from cgadyn.multibody.mujoco_model import from_mujoco  # noqa: E402

ROOT = Path(__file__).resolve().parents[1] / "robots" / "mujoco"
GYMNASIUM = ("ant", "half_cheetah", "hopper", "humanoid", "walker2d", "reacher", "swimmer",
             "inverted_pendulum", "inverted_double_pendulum", "pusher", "humanoidstandup")
DM_CONTROL = ("acrobot", "cartpole", "cheetah", "finger", "hopper", "humanoid", "walker",
              "reacher", "swimmer", "pendulum", "point_mass", "ball_in_cup", "fish",
              "manipulator", "quadruped", "humanoid_CMU", "stacker")
MODELS = [f"gymnasium/{n}" for n in GYMNASIUM] + [f"dm_control/{n}" for n in DM_CONTROL]
TOL = 1e-9


def _load(path):
    mj = mujoco.MjModel.from_xml_path(str(path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a gravity other than cgadyn's default: warned
        return from_mujoco(mj), mj


@pytest.mark.parametrize("name", MODELS)
def test_agrees_with_mujoco(name):
    model, mj = _load(ROOT / f"{name}.xml")
    states = oracle.sample(model, 4, 11)
    states = oracle.States(states.q, 3.0 * states.v, states.a, states.tau)
    refs = mujoco_oracle.references(model, mj, states)
    mine = mujoco_oracle.mine(model, mj, states)
    cond = np.linalg.cond(mine["mj_mass_matrix"])
    assert set(refs) == set(mujoco_oracle.CHECKS)
    for key, ref in refs.items():
        scale = cond if key in mujoco_oracle.SCALED else 1.0
        rel = oracle.relative_error(mine[key], ref)
        assert np.all(rel <= TOL * scale), (name, key, float((rel / scale).max()))


def test_gymnasium_humanoid_is_read_whole():
    model, mj = _load(ROOT / "gymnasium/humanoid.xml")
    assert model.floating_base and (model.nq, model.nv) == (mj.nq, mj.nv) == (24, 23)
    names = [mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(mj.njnt)]
    assert list(model.joint_names) == names  # MuJoCo's names and order
    assert "abdomen_z" in names and "abdomen_y" in names  # two joints in one body
    assert np.array_equal(model.armature, mj.dof_armature)
    assert np.array_equal(model.damping, mj.dof_damping)
    assert np.isclose(model.total_mass, mj.body_mass[1:].sum())


@pytest.mark.parametrize("name", MODELS)
def test_home_is_mujocos_qpos0(name):
    """``Model.home`` is MuJoCo's ``qpos0`` (its joints' ``ref``): the links are where
    MuJoCo puts them at ``qpos0``, to 1e-12. The hopper's home stands it up its ``rootz``
    slide, its foot above the floor, where q = 0 sinks it 1.2 m into the floor; the
    command starts there, and ``cgadyn info`` shows it."""
    from cgadyn.commands.simulate import start_configuration

    model, mj = _load(ROOT / f"{name}.xml")
    qpos, _ = cgadyn.to_mujoco_state(model, model.home, np.zeros(model.nv))
    assert np.array_equal(qpos, mj.qpos0)
    data = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, data)
    links = cgadyn.link_placements(model, model.home)
    for b in range(1, mj.nbody):
        name_b = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_BODY, b)
        if name_b in model.link_names:
            at = links[model.link_names.index(name_b)][:3, 3]
            assert np.abs(at - data.xpos[b]).max() < 1e-12, name_b
    if name == "gymnasium/hopper":
        start = start_configuration(model)
        assert start[1] == 1.25
        cm = cgadyn.collision_model(model, str(ROOT / f"{name}.xml"))
        feet = cgadyn.ground_contacts(model, cm, start, margin=10.0)
        assert feet.distance.min() > 0.0
        sunk = cgadyn.ground_contacts(model, cm, cgadyn.neutral(model), margin=10.0)
        assert sunk.distance.min() < -1.0
        from cgadyn.commands.info import format_info, model_info

        assert "home configuration (the file's qpos0" in format_info(model_info(model))


def test_load_uses_mujoco_for_mjcf():
    model = cgadyn.load(ROOT / "gymnasium/ant.xml")
    mj = mujoco.MjModel.from_xml_path(str(ROOT / "gymnasium/ant.xml"))
    assert model.name == "ant" and model.nv == mj.nv == 14
    assert np.isclose(model.total_mass, mj.body_mass.sum())  # inertiafromgeom, as compiled
    with pytest.raises(ValueError, match="floating_base=False, but the model has a free "
                                         "joint"):
        cgadyn.load(ROOT / "gymnasium/ant.xml", floating_base=False)


CHAIN = """
<mujoco model="chain">
  <compiler angle="radian"/>
  <worldbody>
    <body name="a" pos="0.1 0.2 0.3" quat="0.9 0.1 -0.3 0.2">
      <joint name="j1" type="hinge" axis="0.3 1 0.2" pos="0.05 -0.1 0.02" ref="0.4"
             armature="0.3" damping="0.7" stiffness="2" springref="0.1"/>
      <joint name="j2" type="slide" axis="1 0 0.5" pos="0.2 0 0" ref="-0.2" range="-1 1"/>
      <joint name="j3" type="hinge" axis="0 0 1" pos="-0.1 0.3 0.1" damping="0.2"/>
      <geom type="box" size="0.1 0.2 0.05" pos="0.1 0 0" euler="0.2 0.1 0.3"/>
      <body name="b" pos="0 0 -0.5" euler="0.3 0.2 0.1">
        <joint name="j4" type="hinge" axis="1 0 0" pos="0 0.1 0" stiffness="5"/>
        <geom type="capsule" fromto="0 0 0 0.3 0.1 -0.4" size="0.04"/>
        <body name="welded" pos="0.3 0.1 -0.4">
          <geom type="sphere" size="0.1" pos="0.05 0 0"/>
        </body>
      </body>
    </body>
    <body name="cart" pos="0 1 0">
      <joint name="rail" type="slide" axis="0 1 0"/>
      <geom type="box" size="0.1 0.1 0.1"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_several_joints_in_a_body_offsets_and_refs():
    """A body with three joints (offset anchors, refs, a slide between hinges), a welded
    body, two top-level bodies, springs with a spring reference: MuJoCo's numbers."""
    mj = mujoco.MjModel.from_xml_string(CHAIN)
    model = from_mujoco(mj)
    assert model.joint_names == ("j1", "j2", "j3", "j4", "rail")
    assert model.nq == mj.nq == 5
    states = oracle.sample(model, 6, 5)
    refs = mujoco_oracle.references(model, mj, states)
    mine = mujoco_oracle.mine(model, mj, states)
    cond = np.linalg.cond(mine["mj_mass_matrix"])
    for key, ref in refs.items():
        scale = cond if key in mujoco_oracle.SCALED else 1.0
        assert np.all(oracle.relative_error(mine[key], ref) <= TOL * scale), key
    assert np.any(np.abs(refs["mj_passive"]) > 0.1)  # the springs and dampers act


def test_state_conversions_round_trip_and_free_body_accelerations():
    model, mj = _load(ROOT / "gymnasium/ant.xml")
    s = oracle.sample(model, 5, 2)
    qpos, qvel = cgadyn.to_mujoco_state(model, s.q, s.v)
    assert np.allclose(qpos[:, 3], s.q[:, 6]) and np.allclose(qpos[:, 4:7], s.q[:, 3:6])
    q, v = cgadyn.from_mujoco_state(model, qpos, qvel)
    assert np.allclose(q, s.q, atol=1e-15) and np.allclose(v, s.v, atol=1e-14)
    from cgadyn.multibody.joints import table

    qacc = cgadyn.to_mujoco_acceleration(model, s.q, s.v, s.a)
    assert np.array_equal(qacc, table.mujoco_acceleration(model, s.q, s.v, s.a))
    assert np.allclose(cgadyn.from_mujoco_acceleration(model, s.q, s.v, qacc), s.a, atol=1e-13)
    assert np.allclose(cgadyn.from_mujoco_acceleration(model, s.q[0], s.v[0], qacc[0]), s.a[0],
                       atol=1e-13)
    with pytest.raises(ValueError, match=r"qacc must have shape \(\.\.\., 14\), got \(13,\)"):
        cgadyn.from_mujoco_acceleration(model, s.q[0], s.v[0], qacc[0, :13])
    # MuJoCo's qvel of a free joint: the body origin's velocity in the world
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:] = qpos[0], qvel[0]
    mujoco.mj_forward(mj, d)
    vel = np.zeros(6)
    mujoco.mj_objectVelocity(mj, d, mujoco.mjtObj.mjOBJ_BODY, 1, vel, 0)  # world frame
    assert np.allclose(vel[3:], qvel[0, :3], atol=1e-12)
    # mj_forward's qacc is cgadyn's aba, once converted
    smooth = mujoco_oracle.smooth(mj)
    d = mujoco.MjData(smooth)
    d.qpos[:], d.qvel[:] = qpos[0], qvel[0]
    d.qfrc_applied[:] = cgadyn.to_mujoco_state(model, s.q[0], s.tau[0])[1]  # as velocities
    mujoco.mj_forward(smooth, d)
    a = cgadyn.aba(model, s.q[0], s.v[0], s.tau[0] + cgadyn.passive_torques(model, s.q[0],
                                                                             s.v[0]))
    mine = cgadyn.from_mujoco_acceleration(model, s.q[0], s.v[0], d.qacc)
    assert np.abs(mine - a).max() <= 1e-9 * np.abs(a).max()


def test_what_cgadyn_cannot_model_is_refused_by_name():
    with pytest.raises(ValueError, match="expects a mujoco.MjModel, got str"):
        from_mujoco("ant")


def test_passive_torques_checks_its_arguments():
    model, _ = _load(ROOT / "gymnasium/half_cheetah.xml")
    with pytest.raises(ValueError, match=r"v must have shape \(9,\)"):
        cgadyn.passive_torques(model, np.zeros(9), np.zeros(8))
    q = np.full(9, 0.3)
    tau = cgadyn.passive_torques(model, q, np.zeros(9))
    assert np.allclose(tau, -model.stiffness * (q - model.spring_reference))


@pytest.mark.parametrize("name", ["gymnasium/ant", "gymnasium/humanoid", "gymnasium/hopper",
                                  "dm_control/cheetah", "dm_control/humanoid",
                                  "dm_control/point_mass", "dm_control/manipulator"])
def test_motor_torques_are_mujocos(name):
    """``actuator_torques`` of controls inside and outside ``ctrlrange`` against MuJoCo's
    ``qfrc_actuator`` (clamped as MuJoCo clamps): joint motors, and motors pulling fixed
    tendons (point_mass's two, manipulator's grasp)."""
    model, mj = _load(ROOT / f"{name}.xml")
    assert len(model.actuators) == mj.nu > 0
    assert [a["name"] for a in model.actuators] == [
        mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or f"actuator{a}"
        for a in range(mj.nu)]  # MuJoCo's names, ``actuator<id>`` for an unnamed one
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    ctrl = rng.uniform(-2.0, 2.0, (4, mj.nu))  # beyond the ranges too
    s = oracle.sample(model, 4, 1)
    tau = cgadyn.actuator_torques(model, ctrl)
    for i in range(4):
        qpos, qvel = cgadyn.to_mujoco_state(model, s.q[i], s.v[i])
        d.qpos[:], d.qvel[:], d.ctrl[:] = qpos, qvel, ctrl[i]
        mujoco.mj_forward(mj, d)
        T = mujoco_oracle.velocity_map(model, s.q[i])
        np.testing.assert_allclose(tau[i], T.T @ d.qfrc_actuator, rtol=0, atol=1e-12)


def test_actuator_torques_checks_its_arguments():
    model, _ = _load(ROOT / "gymnasium/ant.xml")
    with pytest.raises(ValueError, match="ctrl must have 8 entries per sample"):
        cgadyn.actuator_torques(model, np.zeros(7))
    with pytest.raises(ValueError, match="not finite"):
        cgadyn.actuator_torques(model, np.full(8, np.nan))
    info = model.actuators[0]
    assert info["gear"] == 150.0 and info["ctrlrange"] == (-1.0, 1.0)
    assert info["joint"] == model.joint_names[model.dof_joint[info["dof"]]]


def test_simulate_takes_controls_and_passive_torques():
    model, _ = _load(ROOT / "gymnasium/half_cheetah.xml")
    q0, v0 = cgadyn.neutral(model), np.full(model.nv, 0.5)
    ctrl = np.tile(np.linspace(-1.5, 1.5, len(model.actuators)), (20, 1))
    by_ctrl = cgadyn.simulate(model, q0, v0, 1e-3, 20, ctrl=ctrl, passive=False)
    by_tau = cgadyn.simulate(model, q0, v0, 1e-3, 20, tau=cgadyn.actuator_torques(model, ctrl),
                             passive=False)
    np.testing.assert_array_equal(by_ctrl.q, by_tau.q)
    # one explicit Euler step with the passive torques equals aba with them added
    step = cgadyn.simulate(model, q0, v0, 1e-3, 1, integrator="euler")
    a = cgadyn.aba(model, q0, v0, cgadyn.passive_torques(model, q0, v0))
    np.testing.assert_allclose(step.v[-1], v0 + 1e-3 * a, rtol=0, atol=1e-12)
    free = cgadyn.simulate(model, q0, v0, 1e-3, 1, integrator="euler", passive=False)
    assert not np.allclose(free.v[-1], step.v[-1])


def test_validate_checks_an_mjcf_model_against_both_engines():
    from cgadyn.commands.validate import format_result
    from cgadyn.validate import validate_robot

    result = validate_robot(str(ROOT / "gymnasium/inverted_double_pendulum.xml"), samples=4)
    assert set(mujoco_oracle.CHECKS) < set(result["checks"])
    assert result["pass"], {k: r["max_rel"] for k, r in result["checks"].items()}
    text = format_result(result)
    assert "against Pinocchio and MuJoCo" in text and "MuJoCo: mass matrix (mj_fullM)" in text
