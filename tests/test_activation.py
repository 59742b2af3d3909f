"""Actuators with activation dynamics (``Model.actuator_dynamics``; algorithms/actuators.py,
A2): an integrator, a filter and an exact filter, read from MJCF as MuJoCo compiles them,
their activations equal MuJoCo's ``act`` step by step, their torques its ``qfrc_actuator``
at any activation, and a rollout driven by their controls equals MuJoCo's Euler rollout;
dm_control's quadruped, whose twelve servos act through filters, stands on them."""

import warnings

import numpy as np
import pytest

import cgadyn

mujoco = pytest.importorskip("mujoco")

from test_servos import ARM as SERVO_ARM  # noqa: E402

BODIES = SERVO_ARM[SERVO_ARM.index("  <worldbody>"):SERVO_ARM.index("  <tendon>")].replace(
    ' damping="0.1"', "")  # test_servos' arm, undamped: MuJoCo's Euler takes a damper implicitly
ARM = f"""
<mujoco>
  <option timestep="0.002" integrator="Euler"><flag contact="disable"/></option>
{BODIES}  <actuator>
    <general name="shoulder" joint="shoulder" dyntype="filter" dynprm="0.05" gainprm="30"
             biastype="affine" biasprm="0 -30 -3" ctrlrange="-1 1" ctrllimited="true"/>
    <general name="elbow" joint="elbow" dyntype="filterexact" dynprm="0.02" gainprm="10"
             biastype="affine" biasprm="0 -10 0"/>
    <general name="wrist" joint="wrist" dyntype="integrator" gainprm="50" biastype="affine"
             biasprm="0 -50 -5" actlimited="true" actrange="-0.05 0.05"/>
    <motor name="push" joint="elbow" gear="0.5" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""
"""An arm under each activation dynamics cgadyn models, as position servos: a filter (with
a damping term and a control range), an exact filter, an integrator with an activation
range, and a motor without dynamics beside them."""
DT, STEPS = 0.002, 250


def _arm():
    mj = mujoco.MjModel.from_xml_string(ARM)
    return cgadyn.from_mujoco(mj), mj


def _controls(steps=STEPS, seed=0):
    """Controls stepped every 50 steps, beyond the control range at times."""
    rng = np.random.default_rng(seed)
    return np.repeat(rng.uniform(-1.5, 1.5, (steps // 50 + 1, 4)), 50, axis=0)[:steps]


def test_activation_dynamics_are_read():
    model, _ = _arm()
    assert model.actuator_dynamics == ("filter", "filterexact", "integrator", "none")
    np.testing.assert_allclose(model.actuator_time_constant, [0.05, 0.02, 0.0, 0.0])
    np.testing.assert_allclose(model.actuator_actrange[2], [-0.05, 0.05])
    assert np.all(np.isinf(model.actuator_actrange[[0, 1, 3]]))


def test_activations_and_torques_are_mujocos():
    """``activations`` equals MuJoCo's ``act`` after each Euler step, and
    ``actuator_torques`` its ``qfrc_actuator`` at each state, to 1e-12."""
    model, mj = _arm()
    ctrl = _controls()
    w = cgadyn.activations(model, ctrl, DT)
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    for n, u in enumerate(ctrl):
        d.ctrl[:] = u
        mujoco.mj_forward(mj, d)
        np.testing.assert_allclose(w[n, :3], d.act, atol=1e-12)
        q, v = cgadyn.from_mujoco_state(model, d.qpos, d.qvel)
        np.testing.assert_allclose(cgadyn.actuator_torques(model, u, q, v, act=w[n]),
                                   d.qfrc_actuator, atol=1e-12)
        mujoco.mj_step(mj, d)
        if n % 60 == 0:  # anywhere: a random state and activation
            d.qpos[:] += 0.1 * rng.standard_normal(mj.nq)
            d.act[:] = w[n + 1, :3]
    np.testing.assert_allclose(w[-1, :3], d.act, atol=1e-12)
    assert np.abs(w[:, 2]).max() <= 0.05  # the integrator's range
    assert np.all(w[:, 3] == 0.0)  # the motor has no activation


def test_a_rollout_under_activations_is_mujocos_euler_rollout():
    """cgadyn's semi-implicit Euler rollout under the controls equals MuJoCo's Euler
    rollout (the same step: v⁺ from the forces at the step's start, q⁺ from v⁺) to 1e-9
    after 0.5 s; its ``activation`` is MuJoCo's ``act``; a second run from the first's
    last state and activation continues it."""
    model, mj = _arm()
    ctrl = _controls()
    rng = np.random.default_rng(2)
    q0, v0 = 0.3 * rng.standard_normal(3), rng.standard_normal(3)
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:] = q0, v0
    for u in ctrl:
        d.ctrl[:] = u
        mujoco.mj_step(mj, d)
    half = STEPS // 2
    first = cgadyn.simulate(model, q0, v0, DT, half, ctrl=ctrl[:half],
                            integrator="semi_implicit_euler")
    second = cgadyn.simulate(model, first.q[-1], first.v[-1], DT, STEPS - half,
                             ctrl=ctrl[half:], integrator="semi_implicit_euler",
                             act=first.activation[-1])
    np.testing.assert_allclose(second.q[-1], d.qpos, atol=1e-9)
    np.testing.assert_allclose(second.v[-1], d.qvel, atol=1e-9)
    np.testing.assert_allclose(second.activation[-1, :3], d.act, atol=1e-12)
    whole = cgadyn.simulate(model, q0, v0, DT, STEPS, ctrl=ctrl, record_every=50,
                            integrator="semi_implicit_euler")
    np.testing.assert_allclose(whole.activation,
                               cgadyn.activations(model, ctrl, DT)[::50], atol=0)


def test_activations_batch_and_refuse_bad_input():
    model, _ = _arm()
    ctrl = _controls(100)
    act = np.array([[0.1, 0.0, 0.01, 0.0], [-0.1, 0.2, 0.0, 0.0]])
    w = cgadyn.activations(model, ctrl, DT, act)
    assert w.shape == (2, 101, 4)
    np.testing.assert_allclose(w[1], cgadyn.activations(model, ctrl, DT, act[1]))
    batch = cgadyn.simulate(model, np.zeros(3), np.zeros(3), DT, 100, ctrl=ctrl, act=act,
                            integrator="semi_implicit_euler")
    np.testing.assert_allclose(batch.activation[:, -1], w[:, -1])
    with pytest.raises(ValueError, match="have activation dynamics: their force takes the "
                                         "activation; pass act"):
        cgadyn.actuator_torques(model, ctrl[0], np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="act must hold 4 finite activations"):
        cgadyn.activations(model, ctrl, DT, [0.0, np.nan, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"act's samples \(3,\) and ctrl's \(2,\)"):
        cgadyn.activations(model, np.zeros((2, 10, 4)), DT, np.zeros((3, 4)))
    with pytest.raises(ValueError, match="act needs ctrl"):
        cgadyn.simulate(model, np.zeros(3), np.zeros(3), DT, 10, act=act[0])
    import dataclasses

    with pytest.raises(ValueError, match="actuator 'shoulder' is a filter of time constant"):
        dataclasses.replace(model, actuator_time_constant=np.array([0.0, 0.02, 0.0, 0.0]))
    with pytest.raises(ValueError, match="actuator 'shoulder' has the dynamics 'muscle'"):
        dataclasses.replace(model, actuator_dynamics=("muscle", "filterexact",
                                                      "integrator", "none"))


def test_the_quadruped_stands_on_its_filtered_servos():
    """dm_control's quadruped: its twelve actuators (position servos of kp 1000 through
    filters of 0.1 s, on the hips' yaw joints and on fixed tendons of the legs) are read.
    Dropped onto its floor under zero controls (with the ball of its file, which falls
    from above and lands beside it), it lands and stands: after 2.5 s at rest (speeds
    below 1e-4), its torso above 0.4 m, no energy gained."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its terrain (a height field), left out
        model = cgadyn.load("dm_control:quadruped")
        collisions = cgadyn.collision_model(model)
    assert len(model.actuator_names) == 12
    assert set(model.actuator_dynamics) == {"filter"}
    np.testing.assert_allclose(model.actuator_time_constant, 0.1)
    steps = 2500
    q0 = model.home.copy()
    q0[2] += 0.1
    trajectory = cgadyn.simulate(model, q0, np.zeros(model.nv), 1e-3, steps,
                                 ctrl=np.zeros((steps, 12)), collisions=collisions,
                                 integrator="semi_implicit_euler", record_every=100)
    assert trajectory.completed == steps
    assert np.abs(trajectory.v[-1]).max() < 1e-4
    assert trajectory.q[-1, 2] > 0.4
    assert np.all(trajectory.energy[1:] <= trajectory.energy[0] + 1e-9)
    np.testing.assert_allclose(trajectory.activation, 0.0)


def test_the_command_line_carries_the_activations_from_call_to_call():
    """``cgadyn simulate`` runs a long rollout as a sequence of calls
    (``commands.simulate.simulate_chunked``): each starts from the last one's activations,
    so the whole equals one call of ``simulate`` (to the solver's warm start, which each
    call restarts)."""
    from cgadyn.commands.simulate import simulate_chunked

    model, _ = _arm()
    ctrl = _controls(1200, seed=4)
    one = cgadyn.simulate(model, np.zeros(3), np.zeros(3), DT, 1200, ctrl=ctrl,
                          integrator="semi_implicit_euler")
    calls = simulate_chunked(model, np.zeros(3), np.zeros(3), DT, 1200,
                             "semi_implicit_euler", None, progress=False, ctrl=ctrl)
    np.testing.assert_allclose(calls.q[-1], one.q[-1], atol=1e-12)
    np.testing.assert_allclose(calls.v[-1], one.v[-1], atol=1e-12)
