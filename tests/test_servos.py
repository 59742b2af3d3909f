"""Position and velocity servos, MuJoCo's actuators of a fixed gain and an affine bias
(algorithms/actuators.py, A1): their torques are MuJoCo's ``qfrc_actuator`` at any state
and control (dm_control's fish, a servo on a fixed tendon among them), and a rollout
driven by their controls follows MuJoCo's own RK4 rollout of the same file."""

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn import mujoco_oracle, oracle

mujoco = pytest.importorskip("mujoco")

ARM = """
<mujoco>
  <option timestep="0.001" integrator="RK4"><flag contact="disable"/></option>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0" damping="0.1"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="1"/>
      <body name="lower" pos="0.4 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="0.5"/>
        <body name="hand" pos="0.3 0 0">
          <joint name="wrist" type="slide" axis="1 0 0"/>
          <geom type="sphere" size="0.04" mass="0.2"/>
        </body>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="sum"><joint joint="shoulder" coef="1"/><joint joint="elbow" coef="0.5"/></fixed>
  </tendon>
  <actuator>
    <position name="shoulder" joint="shoulder" kp="40" kv="4" gear="2" ctrlrange="-1 1"/>
    <velocity name="elbow" joint="elbow" kv="3"/>
    <position name="wrist" joint="wrist" kp="100"/>
    <position name="sum" tendon="sum" kp="5"/>
    <motor name="push" joint="elbow" gear="0.5" ctrlrange="-1 1" forcerange="-0.3 0.3"/>
  </actuator>
</mujoco>
"""
"""An arm of two hinges and a slide under every kind of actuator cgadyn models: a position
servo with a damping term, gear and control range on the shoulder, a velocity servo on
the elbow, a position servo on the slide, one pulling a fixed tendon, and a clamped motor."""


def _arm():
    mj = mujoco.MjModel.from_xml_string(ARM)
    return cgadyn.from_mujoco(mj), mj


def _mujoco_rollout(mj, q0, v0, ctrl):
    """MuJoCo's own rollout of ``mj`` from ``(q0, v0)`` under the controls ``ctrl`` (one row
    per step): its data after the last step."""
    data = mujoco.MjData(mj)
    data.qpos[:], data.qvel[:] = q0, v0
    for u in ctrl:
        data.ctrl[:] = u
        mujoco.mj_step(mj, data)
    return data


def test_the_arms_actuators_are_read_with_their_gains_and_biases():
    model, _ = _arm()
    info = {a["name"]: a for a in model.actuators}
    assert list(info) == ["shoulder", "elbow", "wrist", "sum", "push"]
    assert info["shoulder"]["gain"] == 40 and info["shoulder"]["bias"] == (0, -40, -4)
    assert info["shoulder"]["gear"] == 2 and info["shoulder"]["ctrlrange"] == (-1, 1)
    assert info["elbow"]["gain"] == 3 and info["elbow"]["bias"] == (0, 0, -3)
    assert info["sum"]["tendon"] == "sum" and info["sum"]["joint"] is None
    assert info["push"]["bias"] == (0, 0, 0) and info["push"]["forcerange"] == (-0.3, 0.3)


@pytest.mark.parametrize("name", ["arm", "dm_control:fish"])
def test_servo_torques_are_mujocos(name):
    """``actuator_torques(model, ctrl, q, v)`` equals MuJoCo's ``qfrc_actuator`` (mapped to
    cgadyn's velocity layout) at random states and controls, inside and beyond the ranges,
    to 1e-12."""
    if name == "arm":
        model, mj = _arm()
    else:
        from cgadyn.multibody.registry import robot_path

        mj = mujoco.MjModel.from_xml_path(str(robot_path(name)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # its gravity and fluid forces
            model = cgadyn.from_mujoco(mj)
    assert len(model.actuators) == mj.nu
    data = mujoco.MjData(mj)
    rng = np.random.default_rng(2)
    s = oracle.sample(model, 5, 3)
    ctrl = rng.uniform(-2.0, 2.0, (5, mj.nu))
    tau = cgadyn.actuator_torques(model, ctrl, s.q, 3.0 * s.v)
    for i in range(5):
        qpos, qvel = cgadyn.to_mujoco_state(model, s.q[i], 3.0 * s.v[i])
        data.qpos[:], data.qvel[:], data.ctrl[:] = qpos, qvel, ctrl[i]
        mujoco.mj_forward(mj, data)
        T = mujoco_oracle.velocity_map(model, s.q[i])
        np.testing.assert_allclose(tau[i], T.T @ data.qfrc_actuator, rtol=0, atol=1e-12)
        assert np.any(np.abs(data.qfrc_actuator) > 1e-6)


def test_a_rollout_under_servo_controls_follows_mujocos():
    """``simulate(..., ctrl=...)`` with RK4 from a moving start under a control sequence
    that steps halfway: the arm's states after 0.5 s equal MuJoCo's RK4 rollout of the
    same file (contacts off) to 1e-8; with ``passive=False`` the servos still act and the
    joint damper does not, as MuJoCo's rollout without the damper; a servo's torque without
    the state is refused, naming it."""
    model, mj = _arm()
    steps = 500
    ctrl = np.zeros((steps, mj.nu))
    ctrl[:, 0], ctrl[steps // 2:, 0] = 0.5, -0.8
    ctrl[:, 1], ctrl[:, 2], ctrl[:, 3], ctrl[:, 4] = 1.0, 0.05, 0.3, -1.0
    q0, v0 = np.array([0.3, -0.4, 0.02]), np.array([0.5, 0.0, -0.1])
    traj = cgadyn.simulate(model, q0, v0, 1e-3, steps, ctrl=ctrl, gravity=mj.opt.gravity)
    data = _mujoco_rollout(mj, q0, v0, ctrl)
    np.testing.assert_allclose(traj.q[-1], data.qpos, rtol=0, atol=1e-8)
    np.testing.assert_allclose(traj.v[-1], data.qvel, rtol=0, atol=1e-8)
    # passive=False: the shoulder's damper is gone, the servos act still (MuJoCo without
    # the damper)
    bare = cgadyn.simulate(model, q0, v0, 1e-3, steps, ctrl=ctrl, gravity=mj.opt.gravity,
                           passive=False)
    mj.dof_damping[:] = 0.0
    data = _mujoco_rollout(mj, q0, v0, ctrl)
    np.testing.assert_allclose(bare.q[-1], data.qpos, rtol=0, atol=1e-8)
    assert not np.allclose(bare.q[-1], traj.q[-1], atol=1e-4)
    with pytest.raises(ValueError, match="are servos, whose force depends on the state"):
        cgadyn.actuator_torques(model, ctrl[0])
