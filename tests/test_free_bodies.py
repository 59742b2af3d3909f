"""Several free bodies in one model: a robot and the objects beside it, each free body the
root of its own tree (Pinocchio's free flyers that are children of the universe, MuJoCo's
free joints of top-level bodies). Every algorithm treats each free root as it treats a
floating base; checked against Pinocchio and MuJoCo."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn import mujoco_oracle, oracle

pin = pytest.importorskip("pinocchio")


def _pinocchio_model():
    """Two floating trees (a free body with a hinge child; a free body with a hinge and a
    ball below it) and a fixed hinge between them, in Pinocchio's depth-first order."""
    pin.seed(7)
    pm = pin.Model()

    def body(parent, joint):
        j = pm.addJoint(parent, joint, pin.SE3.Random(), f"j{len(pm.joints)}")
        pm.appendBodyToJoint(j, pin.Inertia.Random(), pin.SE3.Identity())
        pm.addJointFrame(j, -1)
        pm.addBodyFrame(f"b{j}", j, pin.SE3.Identity(), pm.getFrameId(f"j{j}"))
        return j

    a = body(0, pin.JointModelFreeFlyer())
    body(a, pin.JointModelRY())
    c = body(0, pin.JointModelFreeFlyer())
    d = body(c, pin.JointModelRX())
    body(d, pin.JointModelSpherical())
    body(0, pin.JointModelRZ())
    return pm


@pytest.fixture(scope="module")
def models():
    pm = _pinocchio_model()
    return cgadyn.from_pinocchio(pm), pm


def test_the_model_knows_its_free_bodies(models):
    model, pm = models
    assert (model.nq, model.nv) == (pm.nq, pm.nv) == (21, 18)
    assert model.joint_kinds == ("free_flyer", "revolute", "free_flyer", "revolute",
                                 "spherical", "revolute")
    # nothing actuates a free body: the six coordinates of each are off
    assert model.actuated.tolist() == [False] * 6 + [True] + [False] * 6 + [True] * 5
    assert np.array_equal(cgadyn.neutral(model), pin.neutral(pm))


def test_dynamics_agree_with_pinocchio(models):
    """rnea, aba, crba, M⁻¹, both derivatives, the centroidal map, the centre of mass and
    the energies, at random states, to 1e-12 (solves scaled by cond(M))."""
    model, pm = models
    d = pm.createData()
    rng = np.random.default_rng(3)
    for _ in range(3):
        q = cgadyn.random_configuration(model, rng)
        v, tau = rng.normal(size=(2, model.nv))
        M = pin.crba(pm, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        cond = np.linalg.cond(M)
        assert np.allclose(cgadyn.rnea(model, q, v, tau), pin.rnea(pm, d, q, v, tau),
                           rtol=0, atol=1e-12)
        assert np.allclose(cgadyn.crba(model, q), M, rtol=0, atol=1e-12)
        assert np.allclose(cgadyn.aba(model, q, v, tau), pin.aba(pm, d, q, v, tau),
                           rtol=0, atol=1e-13 * cond)
        assert np.allclose(cgadyn.minverse(model, q), np.linalg.inv(M), rtol=0,
                           atol=1e-13 * cond)
        pin.computeRNEADerivatives(pm, d, q, v, tau)
        dq, dv = cgadyn.rnea_derivatives(model, q, v, tau)[:2]
        assert np.allclose(dq, d.dtau_dq, atol=1e-11) and np.allclose(dv, d.dtau_dv, atol=1e-11)
        pin.computeABADerivatives(pm, d, q, v, tau)
        dq, dv = cgadyn.aba_derivatives(model, q, v, tau)[:2]
        assert np.allclose(dq, d.ddq_dq, atol=1e-12 * cond)
        assert np.allclose(dv, d.ddq_dv, atol=1e-12 * cond)
        assert np.allclose(cgadyn.centroidal_momentum_matrix(model, q),
                           pin.computeCentroidalMap(pm, d, q), atol=1e-12)
        assert np.allclose(cgadyn.center_of_mass(model, q), pin.centerOfMass(pm, d, q),
                           atol=1e-13)
        assert np.isclose(cgadyn.potential_energy(model, q),
                          pin.computePotentialEnergy(pm, d, q), atol=1e-12)
        assert np.isclose(cgadyn.kinetic_energy(model, q, v),
                          pin.computeKineticEnergy(pm, d, q, v), atol=1e-12)
        q2 = cgadyn.random_configuration(model, rng)
        assert np.allclose(cgadyn.difference(model, q, q2), pin.difference(pm, q, q2),
                           atol=1e-12)
        assert np.allclose(cgadyn.integrate(model, q, v), pin.integrate(pm, q, v), atol=1e-13)


@pytest.mark.slow
def test_batches_are_the_single_calls(models):
    """Groups of eight and more (the lanes of M⁻¹ and of the derivatives) treat every free
    root as the single call does."""
    model, _ = models
    rng = np.random.default_rng(5)
    q = np.array([cgadyn.random_configuration(model, rng) for _ in range(11)])
    v, tau = rng.normal(size=(2, 11, model.nv))
    batch = cgadyn.minverse(model, q)
    assert np.allclose(batch, [cgadyn.minverse(model, x) for x in q], rtol=0, atol=1e-12)
    for fn in (cgadyn.rnea_derivatives, cgadyn.aba_derivatives):
        batch = fn(model, q, v, tau)
        for k in range(11):
            single = fn(model, q[k], v[k], tau[k])
            for b, s in zip(batch, single, strict=True):
                assert np.allclose(b[k], s, rtol=0, atol=1e-11), fn.__name__


def test_a_free_fall_conserves_energy(models):
    """Both free trees tumble under gravity (RK4, 1 s): the total energy drifts by less
    than 1e-5 relative, the drift shrinks with the step at least as its square (RK4 in the
    chart ``q ⊕ ·`` is below fourth order on rotations, ``sim/rollout.py``), and every
    quaternion stays unit."""
    model, _ = models
    rng = np.random.default_rng(9)
    q0, v0 = cgadyn.random_configuration(model, rng), rng.normal(size=model.nv)
    drift = []
    for dt in (1e-3, 5e-4):
        traj = cgadyn.simulate(model, q0, v0, dt, round(1.0 / dt), passive=False)
        energy = traj.energy
        drift.append(np.ptp(energy) / np.abs(energy).max())
        for at in (3, 11, 16):  # the two free bodies' quaternions and the ball's
            assert np.allclose(np.linalg.norm(traj.q[:, at:at + 4], axis=1), 1.0, atol=1e-12)
    assert drift[0] < 1e-5 and drift[1] < drift[0] / 3.5, drift


ARM_AND_BOXES = """
<mujoco model="arm_and_boxes">
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <body name="box1" pos="0.5 0 0.1">
      <freejoint name="box1_free"/>
      <geom type="box" size="0.05 0.1 0.05" mass="0.7"/>
    </body>
    <body name="shoulder" pos="0 0 0.4">
      <joint name="yaw" type="hinge" axis="0 0 1" armature="0.1" damping="0.3"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
      <body name="forearm" pos="0.3 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0" range="-2 2"/>
        <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.03"/>
      </body>
    </body>
    <body name="ball" pos="-0.4 0.2 0.3" quat="0.9 0.1 0.2 0.3">
      <freejoint name="ball_free"/>
      <geom type="sphere" size="0.06" pos="0.01 0 0"/>
      <body name="pendulum" pos="0 0 -0.1">
        <joint name="swing" type="hinge" axis="1 0 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_mjcf_with_free_objects_agrees_with_mujoco():
    """An arm between a free box and a free ball carrying a pendulum, compiled by MuJoCo:
    the joints in MuJoCo's order, each free joint a free flyer, and placements, M, inverse
    and forward dynamics and the passive torques against MuJoCo at random states."""
    mujoco = pytest.importorskip("mujoco")
    mj = mujoco.MjModel.from_xml_string(ARM_AND_BOXES)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = cgadyn.from_mujoco(mj)
    assert model.joint_names == ("box1_free", "yaw", "elbow", "ball_free", "swing")
    assert (model.nq, model.nv) == (mj.nq, mj.nv) == (17, 15)
    assert model.actuated.tolist() == [False] * 6 + [True] * 2 + [False] * 6 + [True]
    states = oracle.sample(model, 4, 2)
    refs = mujoco_oracle.references(model, mj, states)
    mine = mujoco_oracle.mine(model, mj, states)
    cond = np.linalg.cond(mine["mj_mass_matrix"])
    for key, ref in refs.items():
        scale = cond if key in mujoco_oracle.SCALED else 1.0
        assert np.all(oracle.relative_error(mine[key], ref) <= 1e-9 * scale), key
    q, v = cgadyn.from_mujoco_state(model, mj.qpos0, np.zeros(mj.nv))
    assert np.allclose(q[:3], [0.5, 0, 0.1]) and np.allclose(q[9:12], [-0.4, 0.2, 0.3])
