"""Fixed tendons' springs and dampers (``Model.tendon_*``, ``docs/joints.md`` P2) against
MuJoCo's ``qfrc_passive``, in ``passive_torques`` and in the compiled rollouts; what cgadyn
does not model of a tendon refused or warned of by name."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import cgadyn  # noqa: E402
from cgadyn.multibody.mujoco_model import from_mujoco  # noqa: E402

ARM = """
<mujoco model="tendon arm">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="j1" type="hinge" axis="0 1 0" damping="0.05"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="b" pos="0.3 0 0">
        <joint name="j2" type="hinge" axis="0 1 0" ref="0.2"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="c" pos="0.3 0 0">
          <joint name="j3" type="slide" axis="1 0 0"/>
          <geom type="box" size="0.05 0.05 0.05"/>
        </body>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="band" stiffness="3" damping="0.4" springlength="-0.1 0.2">
      <joint joint="j1" coef="0.7"/>
      <joint joint="j2" coef="-0.5"/>
    </fixed>
    <fixed name="cord" stiffness="5">
      <joint joint="j2" coef="0.3"/>
      <joint joint="j3" coef="1.5"/>
    </fixed>
    <fixed name="slack">
      <joint joint="j1" coef="1"/>
    </fixed>
  </tendon>
</mujoco>
"""


def _arm(text: str = ARM):
    mj = mujoco.MjModel.from_xml_string(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing of this model is left out
        return from_mujoco(mj), mj


def test_fixed_tendons_are_read():
    model, mj = _arm()
    assert model.tendon_names == ("band", "cord")  # "slack" has neither spring nor damper
    np.testing.assert_array_equal(model.tendon_coefficients, [[0.7, -0.5, 0.0],
                                                              [0.0, 0.3, 1.5]])
    np.testing.assert_array_equal(model.tendon_stiffness, [3.0, 5.0])
    np.testing.assert_array_equal(model.tendon_damping, [0.4, 0.0])
    np.testing.assert_array_equal(model.tendon_spring_length[0], [-0.1, 0.2])
    # no springlength: MuJoCo relaxes the spring at the tendon's length at qpos0
    np.testing.assert_allclose(model.tendon_spring_length[1], mj.tendon_lengthspring[1])


def test_disabled_springs_and_dampers_leave_the_tendons_too():
    model, _ = _arm(ARM.replace('<option gravity="0 0 -9.81"/>',
                                '<option><flag spring="disable"/></option>'))
    np.testing.assert_array_equal(model.tendon_stiffness, [0.0])  # "cord" has a spring only
    assert model.tendon_names == ("band",) and model.tendon_damping[0] == 0.4


def test_passive_torques_are_mujocos_inside_and_outside_the_dead_band():
    model, mj = _arm()
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(3)
    lengths = []
    for _ in range(40):
        d.qpos[:] = rng.uniform(-1.0, 1.0, 3)
        d.qvel[:] = rng.normal(size=3)
        mujoco.mj_forward(mj, d)
        lengths.append(d.ten_length[0])
        q, v = cgadyn.from_mujoco_state(model, d.qpos, d.qvel)
        np.testing.assert_allclose(cgadyn.passive_torques(model, q, v), d.qfrc_passive,
                                   rtol=0, atol=1e-12)
    lengths = np.array(lengths)  # the band's dead band crossed both ways and entered
    assert (lengths < -0.1).any() and (lengths > 0.2).any()
    assert ((lengths > -0.1) & (lengths < 0.2)).any()


def test_rollouts_apply_the_tendons():
    """One explicit Euler step of the compiled loop is ``v + dt aba(q, v, τ_passive)``;
    without ``passive`` the tendons are off."""
    model, _ = _arm()
    q0, v0 = np.array([0.6, -0.8, 0.3]), np.array([0.5, -1.0, 2.0])
    dt = 1e-3
    step = cgadyn.simulate(model, q0, v0, dt, 1, integrator="euler")
    a = cgadyn.aba(model, q0, v0, cgadyn.passive_torques(model, q0, v0))
    np.testing.assert_allclose(step.v[-1], v0 + dt * a, rtol=0, atol=1e-12)
    untied = cgadyn.simulate(model, q0, v0, dt, 1, integrator="euler", passive=False)
    np.testing.assert_allclose(untied.v[-1], v0 + dt * cgadyn.aba(model, q0, v0, np.zeros(3)),
                               rtol=0, atol=1e-12)


def test_a_tendon_spring_conserves_energy():
    """Without gravity and dampers, kinetic energy plus the springs' ``k dev² / 2`` is
    constant along an RK4 rollout (the tendons' forces derive from that potential), to
    RK4's error (a dead band's kinks would cost it its order: one spring length here)."""
    model, _ = _arm(ARM.replace('damping="0.4" ', "").replace(' damping="0.05"', "")
                    .replace('springlength="-0.1 0.2"', 'springlength="0.05"'))
    q0, v0 = np.array([0.9, -0.9, 0.4]), np.array([1.0, -2.0, 1.0])
    tr = cgadyn.simulate(model, q0, v0, 1e-3, 2000, gravity=np.zeros(3))

    def potential(q):
        length = q @ model.tendon_coefficients.T  # hinges and a slide: q adds
        lo, hi = model.tendon_spring_length.T
        dev = np.where(length > hi, length - hi, np.where(length < lo, length - lo, 0.0))
        return 0.5 * (model.tendon_stiffness * dev**2).sum(axis=-1)

    kinetic = np.array([0.5 * v @ cgadyn.crba(model, q) @ v for q, v in zip(tr.q, tr.v,
                                                                           strict=True)])
    total = kinetic + potential(tr.q)
    assert np.ptp(total) <= 1e-8 * total[0], np.ptp(total) / total[0]
    assert np.ptp(potential(tr.q)) > 0.1 * total[0]  # the springs did work


def test_what_a_tendon_cannot_be_is_refused_or_warned_by_name():
    spatial = ARM.replace("<tendon>", """<tendon>
    <spatial name="rope" stiffness="2"><site site="s1"/><site site="s2"/></spatial>""")
    spatial = spatial.replace('<body name="a" pos="0 0 1">',
                              '<site name="s1" pos="0 0 2"/><body name="a" pos="0 0 1">')
    spatial = spatial.replace('<geom type="box"', '<site name="s2"/><geom type="box"')
    with pytest.raises(ValueError, match="tendon 'rope' is a spatial tendon with a spring"):
        from_mujoco(mujoco.MjModel.from_xml_string(spatial))
    rubbing = spatial.replace('stiffness="2"', 'frictionloss="0.5"')
    with pytest.warns(UserWarning, match="tendons 'rope' are not held"):
        from_mujoco(mujoco.MjModel.from_xml_string(rubbing))
    fluid = ARM.replace('<option gravity="0 0 -9.81"/>',
                        '<option gravity="0 0 -9.81" density="1000"/>')
    with pytest.warns(UserWarning, match="fluid forces of density 1000.0"):
        from_mujoco(mujoco.MjModel.from_xml_string(fluid))
    coupled = ARM.replace("</mujoco>", """<equality><tendon name="tie" tendon1="slack"/>
      </equality></mujoco>""")
    model = from_mujoco(mujoco.MjModel.from_xml_string(coupled))
    assert model.coupling_names == ("tie",)  # the model's own (tests/test_couplings.py)
    assert cgadyn.mujoco_constraints(model, coupled) == []


def test_model_checks_its_tendons():
    model, _ = _arm()
    import dataclasses

    with pytest.raises(ValueError, match="tendon 'band' has the stiffness -3.0"):
        dataclasses.replace(model, tendon_stiffness=np.array([-3.0, 5.0]))
    with pytest.raises(ValueError, match="tendon 'cord' has the spring lengths"):
        dataclasses.replace(model, tendon_spring_length=np.array([[0.0, 0.0], [1.0, 0.0]]))
    with pytest.raises(ValueError, match=r"Model.tendon_coefficients has shape \(2, 2\)"):
        dataclasses.replace(model, tendon_coefficients=np.zeros((2, 2)))


def test_a_motor_pulls_its_tendon_and_rollouts_take_its_controls():
    text = ARM.replace("</mujoco>", """<actuator><motor name="pull" tendon="slack" gear="3"
      ctrlrange="-1 1"/><motor name="turn" joint="j2"/></actuator></mujoco>""")
    model, mj = _arm(text)
    assert model.tendon_names == ("band", "cord", "slack")  # kept: a motor pulls it
    pull, turn = model.actuators
    assert (pull["tendon"], pull["joint"], pull["dof"]) == ("slack", None, None)
    assert (turn["tendon"], turn["joint"], turn["dof"]) == (None, "j2", 1)
    d = mujoco.MjData(mj)
    d.ctrl[:] = [2.0, 0.5]  # the first clamped to 1
    mujoco.mj_forward(mj, d)
    tau = cgadyn.actuator_torques(model, [2.0, 0.5])
    np.testing.assert_allclose(tau, d.qfrc_actuator, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tau, [3.0, 0.5, 0.0], rtol=0, atol=1e-12)
    ctrl = np.tile([0.7, -0.2], (5, 1))
    by_ctrl = cgadyn.simulate(model, np.zeros(3), np.zeros(3), 1e-3, 5, ctrl=ctrl)
    by_tau = cgadyn.simulate(model, np.zeros(3), np.zeros(3), 1e-3, 5,
                             tau=cgadyn.actuator_torques(model, ctrl))
    np.testing.assert_array_equal(by_ctrl.q, by_tau.q)


FOLDING = """
<mujoco><option gravity="0 0 -9.81"/>
  <worldbody><body name="a" pos="0 0 1">
    <joint name="j1" type="hinge" axis="0 1 0" damping="0.2"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
    <body name="b" pos="0.3 0 0"><joint name="j2" type="hinge" axis="0 1 0" damping="0.2"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body>
  </body></worldbody>
  <tendon><fixed name="fold" limited="true" range="-0.2 0.6">
    <joint joint="j1" coef="1"/><joint joint="j2" coef="0.5"/></fixed></tendon>
</mujoco>"""
"""Two damped links released level: they fall (j1 and j2 grow) until ``j1 + 0.5 j2``
reaches the tendon's longest, 0.6, then swing on it and settle."""


def _fold(q):
    return q[0] + 0.5 * q[1]


def test_a_fixed_tendons_limit_stops_the_arm():
    """The tendon's range is read (``Model.tendon_range``); the falling arm never takes
    the tendon past 0.6 by more than 1e-4, comes to rest on it (1e-6) held by the limit
    (``limit_torques`` then ``c λ``: proportional to the tendon's coefficients), and the
    compiled loop equals ``contact_step`` (cold solver starts, without the dampers, which
    the loop takes implicitly) to 1e-12; a start past the bound is taken back by the
    fraction ``stabilization`` a step, with no kick."""
    model, _ = _arm(FOLDING)
    assert model.tendon_names == ("fold",)
    np.testing.assert_allclose(model.tendon_range, [[-0.2, 0.6]])
    world, settings = cgadyn.World(ground=False), cgadyn.ContactSettings(warm_start=False)
    run = cgadyn.simulate(model, np.zeros(2), np.zeros(2), 1e-3, 3000,
                          integrator="semi_implicit_euler", world=world, contact=settings)
    folds = np.array([_fold(q) for q in run.q])
    assert folds.max() < 0.6 + 1e-4 and abs(folds[-1] - 0.6) < 1e-6
    assert np.abs(run.v[-1]).max() < 1e-3
    torque = run.limit_torques[-2]
    assert torque[0] < 0.0
    np.testing.assert_allclose(torque[1], 0.5 * torque[0], rtol=1e-9)
    q, v = np.zeros(2), np.zeros(2)
    rigid = cgadyn.simulate(model, np.zeros(2), np.zeros(2), 1e-3, 400, passive=False,
                            integrator="semi_implicit_euler", world=world, contact=settings)
    for _ in range(400):
        step = cgadyn.contact_step(model, None, q, v, np.zeros(2), 1e-3, world=world,
                                   contact=settings, passive=False)
        q, v = step.q, step.v
    assert abs(_fold(q) - 0.6) < 1e-4  # on the bound by then
    np.testing.assert_allclose(rigid.q[-1], q, atol=1e-12)
    np.testing.assert_allclose(rigid.v[-1], v, atol=1e-12)
    past = cgadyn.simulate(model, np.array([0.7, 0.0]), np.zeros(2), 1e-3, 3,
                           integrator="semi_implicit_euler", world=world,
                           gravity=np.zeros(3), passive=False)
    np.testing.assert_allclose([_fold(x) - 0.6 for x in past.q],
                               0.1 * 0.8 ** np.arange(4), rtol=1e-9)
    assert np.abs(past.v).max() == 0.0


RUBBING = """
<mujoco><option gravity="0 0 -9.81"/>
  <worldbody><body name="a" pos="0 0 1">
    <joint name="j1" type="hinge" axis="0 1 0"/>
    <geom type="sphere" pos="0.5 0 0" size="0.01" mass="1"/>
  </body></worldbody>
  <tendon><fixed name="brake" frictionloss="FRICTION"><joint joint="j1" coef="2"/></fixed>
  </tendon>
</mujoco>"""
"""A point mass 0.5 m out on a horizontal hinge (gravity's torque 4.905 N m, inertia about
0.25 kg m²) and a fixed tendon ``2 j1`` with a friction loss f: a force of at most f along
the tendon, a torque of at most 2 f on the hinge."""


def test_a_fixed_tendons_friction_loss_holds_below_it():
    """``Model.tendon_friction`` is MuJoCo's ``tendon_frictionloss``; a tendon friction of
    3 N (6 N m on the hinge) holds the hinge still, its torque the holding one to 1e-6, in
    ``contact_step`` and in the compiled loop; one of 1 N (2 N m) lets it go at ``(4.905 -
    2) / I``, its torque -2 N m (gravity turns it towards +q)."""
    held = from_mujoco(mujoco.MjModel.from_xml_string(RUBBING.replace("FRICTION", "3")))
    assert held.tendon_names == ("brake",)
    np.testing.assert_allclose(held.tendon_friction, [3.0])
    world = cgadyn.World(ground=False)
    step = cgadyn.contact_step(held, None, np.zeros(1), np.zeros(1), np.zeros(1), 1e-3,
                               world=world)
    assert abs(step.v[0]) < 1e-9
    hold = cgadyn.rnea(held, np.zeros(1), np.zeros(1), np.zeros(1))
    np.testing.assert_allclose(step.friction_torques, hold, rtol=1e-6)
    run = cgadyn.simulate(held, np.zeros(1), np.zeros(1), 1e-3, 100, world=world,
                          integrator="semi_implicit_euler")
    assert np.abs(run.v).max() < 1e-9
    going = from_mujoco(mujoco.MjModel.from_xml_string(RUBBING.replace("FRICTION", "1")))
    step = cgadyn.contact_step(going, None, np.zeros(1), np.zeros(1), np.zeros(1), 1e-3,
                               world=world)
    inertia = cgadyn.crba(going, np.zeros(1))[0, 0]
    np.testing.assert_allclose(step.v[0], 1e-3 * (-hold[0] - 2.0) / inertia, rtol=1e-9)
    np.testing.assert_allclose(step.friction_torques, [-2.0], rtol=1e-9)
