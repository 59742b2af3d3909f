"""MJCF loop closures (``cgadyn.mujoco_constraints``, docs/constraints.md C11): MuJoCo's
``connect`` and ``weld`` equalities read as cgadyn constraints hold what MuJoCo's hold (its
constraint rows ``efc_J`` and errors ``efc_pos``), their constrained dynamics agree with
Pinocchio's ``constraintDynamics`` exactly and with MuJoCo's soft constraints made nearly
hard, and what a rigid constraint cannot hold is refused by name."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.validate import constrained_row

mujoco = pytest.importorskip("mujoco")

FOUR_BAR = """<mujoco model="four_bar">
  <worldbody>
    <body name="crank">
      <joint name="crank" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.4" size="0.02" mass="1"/>
      <body name="coupler" pos="0 0 0.4" euler="0 20 0">
        <joint name="coupler" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.6 0 0.1" size="0.02" mass="1.5"/>
      </body>
    </body>
    <body name="rocker" pos="0.6 0 0">
      <joint name="rocker" type="hinge" axis="0 1 0" range="-3 3"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.5" size="0.02" mass="1.2"/>
    </body>
  </worldbody>
  <equality><connect name="loop" body1="coupler" body2="rocker" anchor="0.6 0 0.1"/></equality>
</mujoco>"""

TETHER = """<mujoco model="tether">
  <worldbody>
    <body name="upper" pos="0 0 1" quat="0.9 0.1 0.3 0.2">
      <joint name="shoulder" type="hinge" axis="1 0 0"/>
      <joint name="shoulder_y" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="1"/>
      <body name="lower" pos="0.4 0 0">
        <joint name="elbow" type="hinge" axis="0 0 1"/>
        <joint name="wrist" type="slide" axis="1 0 0"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="0.8"/>
        <site name="tip" pos="0.4 0 0"/>
      </body>
    </body>
  </worldbody>
  <equality><connect name="tether" body1="lower" body2="world" anchor="0.4 0 0"/></equality>
</mujoco>"""

WELD = """<mujoco model="welded_arms">
  <worldbody>
    <body name="a1" pos="0 0 1">
      <joint name="a1" type="hinge" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/>
      <body name="a2" pos="0.5 0 0" euler="0 0 30">
        <joint name="a2" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/>
        <body name="a3" pos="0.5 0 0" euler="10 -20 40">
          <joint name="a3" type="hinge" axis="1 0 0"/>
          <joint name="a3b" type="hinge" axis="0 1 0"/>
          <joint name="a3c" type="hinge" axis="0 0 1"/>
          <geom type="box" size="0.05 0.05 0.05" mass="0.5"/>
          <site name="grip_a" pos="0.05 0.02 0" euler="0 90 0"/>
        </body>
      </body>
    </body>
    <body name="b1" pos="1.0 0.6 1" euler="0 0 -15">
      <joint name="b1" type="hinge" axis="0 0 1"/>
      <joint name="b1y" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 -0.3 0" size="0.03" mass="1"/>
      <body name="b2" pos="0 -0.3 0" euler="5 5 5">
        <joint name="b2" type="hinge" axis="1 0 0"/>
        <joint name="b2y" type="hinge" axis="0 1 0"/>
        <geom type="box" size="0.04 0.04 0.04" mass="0.4"/>
        <site name="grip_b" pos="0 0 0.05" euler="30 0 0"/>
      </body>
    </body>
  </worldbody>
  <equality>
    <weld name="grip" body1="a3" body2="b2" anchor="0.02 0.01 -0.03"/>
  </equality>
</mujoco>"""

WELD_SITES = WELD.replace('<weld name="grip" body1="a3" body2="b2" anchor="0.02 0.01 -0.03"/>',
                          '<weld name="grip" site1="grip_a" site2="grip_b"/>')
MODELS = {"four_bar": FOUR_BAR, "tether": TETHER, "weld": WELD, "weld_sites": WELD_SITES}


def _compiled(xml: str):
    mj = mujoco.MjModel.from_xml_string(xml)
    mj.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    return mj, cgadyn.load(xml), cgadyn.mujoco_constraints(cgadyn.load(xml), mj)


def _mujoco_rows(mj, qpos):
    """MuJoCo's equality rows at qpos: ``efc_J`` and ``efc_pos``."""
    d = mujoco.MjData(mj)
    d.qpos[:] = qpos
    mujoco.mj_forward(mj, d)
    rows = np.flatnonzero(d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    return d.efc_J.reshape(d.nefc, mj.nv)[rows], d.efc_pos[rows]


def _error(model, c, q) -> np.ndarray:
    """MuJoCo's error of a constraint: the world position of its first end minus its
    second's, and for a frame the vector part of the quaternion of R₂ᵀ R₁ (sin(θ/2) times
    the axis, in frame 2)."""
    T = cgadyn.link_placements(model, q)
    T1 = T[c.link] @ c.placement
    T2 = c.other_placement if c.other is None else T[c.other] @ c.other_placement
    out = T1[:3, 3] - T2[:3, 3]
    if c.kind == "frame":
        R = T2[:3, :3].T @ T1[:3, :3]
        w = 0.5 * np.sqrt(1.0 + np.trace(R))
        out = np.r_[out, np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0],
                                   R[1, 0] - R[0, 1]]) / (4.0 * w)]
    return out


@pytest.mark.parametrize("name", MODELS)
def test_equalities_hold_what_mujoco_holds(name):
    """The constraints read are MuJoCo's: kinds and links, MuJoCo's errors (``efc_pos``:
    0 at ``qpos0`` where the compiler placed the second end; the sites of a weld as the
    file put them), a connect's rows equal to ``efc_J`` at any configuration, and a weld's,
    where it holds, to ``efc_J``'s translation and ``½ R₂ᵀ`` of its rotation (MuJoCo's
    rows of the orientation error in frame 2)."""
    mj, model, cs = _compiled(MODELS[name])
    assert [c.kind for c in cs] == (["point"] if "weld" not in name else ["frame"])
    J_mj, pos = _mujoco_rows(mj, mj.qpos0)
    np.testing.assert_allclose(_error(model, cs[0], mj.qpos0), pos, atol=1e-12)
    if name == "weld_sites":
        assert np.abs(pos).max() > 0.01  # apart at qpos0: MuJoCo's rows hold elsewhere
        return
    np.testing.assert_allclose(pos, 0.0, atol=1e-12)
    J = cgadyn.constraint_jacobian(model, mj.qpos0, cs)
    np.testing.assert_allclose(J[:3], J_mj[:3], atol=1e-12)
    if cs[0].kind == "frame":
        T = cgadyn.link_placements(model, mj.qpos0)
        R2 = (T[cs[0].other] @ cs[0].other_placement)[:3, :3]
        assert np.abs(R2 - np.eye(3)).max() > 0.1  # a turned frame: the rotation matters
        np.testing.assert_allclose(0.5 * R2.T @ J[3:], J_mj[3:], atol=1e-12)
    else:
        rng = np.random.default_rng(3)
        for _ in range(3):
            q = mj.qpos0 + 0.5 * rng.standard_normal(mj.nq)
            J_mj, pos = _mujoco_rows(mj, q)
            np.testing.assert_allclose(_error(model, cs[0], q), pos, atol=1e-12)
            np.testing.assert_allclose(cgadyn.constraint_jacobian(model, q, cs), J_mj,
                                       atol=1e-12)


@pytest.mark.parametrize("name", MODELS)
def test_constrained_dynamics_agrees_with_pinocchio(name):
    """q̈ and λ against Pinocchio's ``constraintDynamics`` on the same constraints
    (``cgadyn validate``'s check), to 1e-10 × cond(M)."""
    model, pm = oracle.models(MODELS[name])
    states = oracle.sample(model, 4, 1)
    label, row = constrained_row(MODELS[name], model, pm, states,
                                 1e-10 * oracle.conditioning(model, states.q))
    assert "MJCF equalities" in label
    assert row["pass"], row


@pytest.mark.parametrize("name", ["four_bar", "tether", "weld"])  # held at qpos0
def test_mujoco_agrees_where_its_constraints_are_nearly_hard(name):
    """MuJoCo's constraints are soft; made as hard as it allows (``solimp`` 0.9999) at a
    state that satisfies them, its qacc is cgadyn's to its softness."""
    mj, model, cs = _compiled(MODELS[name])
    mj.eq_solimp[:] = [0.9999, 0.9999, 0.001, 0.5, 2.0]
    mj.opt.tolerance, mj.opt.iterations = 1e-15, 1000
    q = mj.qpos0
    J = cgadyn.constraint_jacobian(model, q, cs)
    rank = np.linalg.matrix_rank(J)
    null = np.linalg.svd(J)[2][rank:].T
    rng = np.random.default_rng(0)
    v, tau = null @ rng.standard_normal(null.shape[1]), rng.standard_normal(model.nv)
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:], d.qfrc_applied[:] = q, v, tau
    mujoco.mj_forward(mj, d)
    a, _ = cgadyn.constrained_dynamics(model, q, v, tau, cs, damping=1e-10, iterations=200)
    assert np.abs(d.qacc - a).max() <= 1e-2 * np.abs(a).max()
    assert np.abs(J @ a + cgadyn.constraint_drift(model, q, v, cs)).max() < 1e-8


def _equality(xml: str, line: str) -> str:
    return xml.replace("</worldbody>", "</worldbody>\n  <equality>" + line + "</equality>", 1) \
        .replace("</equality>\n  <equality>", "")


def test_what_a_rigid_constraint_cannot_hold_is_refused_by_name():
    line = '<weld name="soft" body1="a3" body2="b2" torquescale="0.5"/>'
    xml = _equality(WELD.split("<equality>")[0] + "</mujoco>", line)
    model = cgadyn.load(xml)
    with pytest.raises(ValueError, match="weld 'soft' has torquescale 0.5"):
        cgadyn.mujoco_constraints(model, xml)


def test_joint_couplings_are_left_to_the_model():
    """A joint equality is the model's coupling (``Model.coupling_*``, K45), which the
    contact step holds: ``mujoco_constraints`` leaves it out."""
    line = '<joint name="couple" joint1="a1" joint2="b1"/>'
    xml = _equality(WELD.split("<equality>")[0] + "</mujoco>", line)
    model = cgadyn.load(xml)
    assert model.coupling_names == ("couple",)
    assert cgadyn.mujoco_constraints(model, xml) == []


def test_inactive_equalities_are_left_out_and_other_models_refused():
    xml = WELD.replace('<weld name="grip"', '<weld name="grip" active="false"')
    model = cgadyn.load(xml)
    assert cgadyn.mujoco_constraints(model, xml) == []
    other = cgadyn.load(TETHER)
    with pytest.raises(ValueError, match="not a link of 'tether'"):
        cgadyn.mujoco_constraints(other, WELD)
