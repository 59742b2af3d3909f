"""A ball joint's cone limit (``Model.cone_limit``, MuJoCo's ``ball`` ``range``) as a
unilateral row of the contact step (contact/limits.py; docs/contact.md, K26'): a rod hung
on a limited ball joint falls onto the cone and rests there with the limit carrying
gravity's torque, the compiled loop's step equals ``contact_step``'s, and the limit is read
from MJCF and checked by the model."""

import dataclasses

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.step import contact_step

mujoco = pytest.importorskip("mujoco")

DT = 1e-3
NOWHERE = cgadyn.World(ground=False)
CONE = 0.5
ROD = f"""
<mujoco model="rod">
  <compiler angle="radian"/>
  <worldbody>
    <body name="rod" pos="0 0 1">
      <joint name="ball" type="ball" range="0 {CONE}"/>
      <inertial pos="0.5 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
    </body>
  </worldbody>
</mujoco>
"""


def _rod() -> cgadyn.Model:
    return cgadyn.from_mujoco(mujoco.MjModel.from_xml_string(ROD))


def _angle(q: np.ndarray) -> float:
    """The rotation angle of the ball's quaternion ``(x, y, z, w)``."""
    return 2.0 * np.arctan2(np.linalg.norm(q[:3]), abs(q[3]))


def test_the_cone_limit_is_read_from_mjcf_and_checked():
    model = _rod()
    assert model.cone_limit.tolist() == [CONE]
    assert np.isinf(cgadyn.from_mujoco(mujoco.MjModel.from_xml_string(
        ROD.replace(f' range="0 {CONE}"', ""))).cone_limit).all()
    arm = cgadyn.load("panda")
    with pytest.raises(ValueError, match=r"cone_limit\[0\].*expected inf, or an angle > 0"):
        dataclasses.replace(arm, cone_limit=np.r_[0.5, np.full(arm.njoints - 1, np.inf)])


def test_a_rod_falls_onto_its_cone_and_rests_there():
    """Released horizontal, the rod swings down about y onto the cone: its angle never
    passes the limit by more than 1e-4 rad, it comes to rest there (|ω| < 1e-6), turned
    about y alone, and the limit's torque at rest is the gravity torque to 1e-6."""
    model = _rod()
    q, v = cgadyn.neutral(model), np.zeros(3)
    angles = []
    for _ in range(800):
        s = contact_step(model, None, q, v, np.zeros(3), DT, NOWHERE)
        q, v = s.q, s.v
        angles.append(_angle(q))
    assert max(angles) <= CONE + 1e-4 and abs(angles[-1] - CONE) < 1e-4
    assert np.abs(v).max() < 1e-6 and abs(q[0]) < 1e-9 and abs(q[2]) < 1e-9
    hold = cgadyn.rnea(model, q, np.zeros(3), np.zeros(3))  # the torque holding it
    assert abs(hold[1]) > 1.0 and np.abs(s.limit_torques - hold).max() < 1e-6
    free = contact_step(model, None, q, np.zeros(3), np.zeros(3), DT, NOWHERE,
                        joint_limits=False)
    assert _angle(free.q) > CONE  # the cone, not the step, holds it


def test_the_compiled_step_is_contact_step_with_a_cone():
    """300 steps of the rod thrown down and sideways onto its cone: the compiled loop's q
    and v equal ``contact_step``'s to 1e-10, its limit torques to 1e-7, and without limits
    the rod passes the cone."""
    model = _rod()
    q0, v0 = cgadyn.neutral(model), np.array([0.5, 2.0, -1.0])
    q, v, ref = q0, v0, []
    for _ in range(300):
        s = contact_step(model, None, q, v, np.zeros(3), DT, NOWHERE)
        ref.append((s.q, s.v, s.limit_torques))
        q, v = s.q, s.v
    tr = cgadyn.simulate(model, q0, v0, DT, 300, integrator="semi_implicit_euler",
                         world=NOWHERE, contact=cgadyn.ContactSettings(warm_start=False))
    assert np.abs(np.array([r[2] for r in ref])).max() > 1.0  # the cone acted
    for k, (qk, vk, tk) in enumerate(ref):
        assert np.abs(tr.q[k + 1] - qk).max() < 1e-10
        assert np.abs(tr.v[k + 1] - vk).max() < 1e-10
        assert np.abs(tr.limit_torques[k] - tk).max() < 1e-7
    assert max(_angle(x) for x in tr.q) <= CONE + 1e-3
    off = cgadyn.simulate(model, q0, v0, DT, 300, integrator="semi_implicit_euler",
                          world=NOWHERE, joint_limits=False)
    assert max(_angle(x) for x in off.q) > CONE + 0.1


def test_a_ball_started_past_its_cone_turns_back_without_a_kick():
    """Without gravity, the rod started 0.2 rad past its cone about y: the position update
    turns it back about its own axis by ``β`` of its overshoot a step (K26a), its angle
    ``CONE + 0.2 (1 - β)^k`` to 1e-12, and it keeps no velocity (a velocity ``β d / dt``
    would have sent it on across the cone at 40 rad/s); ``contact_step``, under gravity
    that the cone holds, takes the same first step."""
    model = _rod()
    q0 = cgadyn.neutral(model)
    q0[1], q0[3] = np.sin(0.5 * (CONE + 0.2)), np.cos(0.5 * (CONE + 0.2))  # about y
    tr = cgadyn.simulate(model, q0, np.zeros(3), DT, 40, integrator="semi_implicit_euler",
                         world=NOWHERE, gravity=np.zeros(3))
    beta = cgadyn.ContactSettings().stabilization
    angles = np.array([_angle(x) for x in tr.q])
    assert np.abs(angles - (CONE + 0.2 * (1 - beta) ** np.arange(41))).max() < 1e-12
    assert np.abs(tr.v).max() < 1e-12
    assert np.abs(tr.q[:, [0, 2]]).max() < 1e-15  # about y alone
    s = contact_step(model, None, q0, np.zeros(3), np.zeros(3), DT, NOWHERE)
    assert abs(_angle(s.q) - angles[1]) < 1e-12  # gravity pushes it out: the cone holds
    assert np.abs(s.v).max() < 1e-9
