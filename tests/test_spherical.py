"""The spherical joint (Pinocchio's ``JointModelSpherical``, MuJoCo's ``ball``) in every
algorithm: models built in Pinocchio with spherical joints anywhere in the tree (a chain, a
tree with a spherical root, a free-flyer root above them), converted by
``cgadyn.from_pinocchio`` and compared with Pinocchio on every check of ``oracle.CHECKS``;
batches against single calls; the manifold's identities; MuJoCo's ball joint against
MuJoCo; a rollout that keeps the quaternions unit."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from joint_cases import ik_reaches_poses, random_model

import cgadyn
from cgadyn import oracle
from cgadyn.multibody.joints import SPHERICAL, TYPES
from cgadyn.validate import leaf_links

TOL = 1e-10


def _unaligned() -> pin.JointModel:
    return pin.JointModelRevoluteUnaligned(np.array([0.6, 0.0, 0.8]))


MODELS = {
    "chain": lambda: random_model("chain", [(0, pin.JointModelRX()), (1, pin.JointModelSpherical()),
                                            (2, _unaligned()), (3, pin.JointModelSpherical())], 1),
    "tree": lambda: random_model("tree", [(0, pin.JointModelSpherical()),
                                          (1, pin.JointModelSpherical()), (2, pin.JointModelRY()),
                                          (1, pin.JointModelPZ()), (4, pin.JointModelSpherical()),
                                          (5, pin.JointModelRUBZ())], 2),
    "floating": lambda: random_model("floating", [(0, pin.JointModelFreeFlyer()),
                                                  (1, pin.JointModelSpherical()),
                                                  (2, pin.JointModelRZ()),
                                                  (3, pin.JointModelSpherical())], 3),
}


@pytest.fixture(scope="module", params=sorted(MODELS))
def models(request):
    pm = MODELS[request.param]()
    return cgadyn.from_pinocchio(pm), pm


def test_the_record_and_the_conversion(models):
    model, pm = models
    record = TYPES[SPHERICAL]
    assert (record.nq, record.nv, record.quaternion, record.additive) == (4, 3, 0, False)
    assert model.nv == pm.nv and model.joint_names == tuple(pm.names[1:])
    spherical = [j for j in range(model.njoints) if model.joint_types[j] == SPHERICAL]
    assert [pm.joints[j + 1].shortname() for j in spherical] == \
        ["JointModelSpherical"] * len(spherical)
    assert np.array_equal(oracle.pin_configuration(model, cgadyn.neutral(model)),
                          pin.neutral(pm))


def test_every_check_matches_pinocchio(models):
    """rnea, aba, crba, g(q), the Jacobians, the placements, the derivatives, M⁻¹, ccrba,
    the centre of mass and the manifold, at random states: to 1e-10 relative (× cond(M)
    for the solves, ``oracle.SCALED``)."""
    model, pm = models
    states = oracle.sample(model, 5, 7)
    leaves = leaf_links(model)
    frames = oracle._frames(pm, leaves)
    data = pm.createData()
    qp = oracle.pin_configuration(model, states.q)
    cond = oracle.conditioning(model, states.q)
    worst = {}
    for check in oracle.CHECKS:
        if check.theirs is None:
            ref = np.stack([oracle.fk_reference(pm, data, qp[i], model.link_names)
                            for i in range(5)])
        else:
            ref = np.stack([check.theirs(pm, data, qp[i], states, i, frames)
                            for i in range(5)])
        rel = oracle.relative_error(check.mine(model, states, leaves), ref)
        scale = cond if check.scaled else 1.0
        worst[check.key] = float((rel / scale).max())
    assert all(w <= TOL for w in worst.values()), worst


def test_energy_matches_pinocchio(models):
    model, pm = models
    data = pm.createData()
    s = oracle.sample(model, 3, 8)
    for q, v in zip(s.q, s.v, strict=True):
        qp = oracle.pin_configuration(model, q)
        kinetic, potential = cgadyn.energy(model, q, v)
        assert kinetic == pytest.approx(pin.computeKineticEnergy(pm, data, qp, v), rel=TOL)
        assert potential == pytest.approx(pin.computePotentialEnergy(pm, data, qp), rel=TOL,
                                          abs=1e-12)


def test_batches_equal_single_calls(models):
    """Eleven samples: a group of eight in lanes where a pass has them, and the rest."""
    model, _ = models
    s = oracle.sample(model, 11, 9)
    batch = {
        "rnea": cgadyn.rnea(model, s.q, s.v, s.a),
        "aba": cgadyn.aba(model, s.q, s.v, s.tau),
        "crba": cgadyn.crba(model, s.q),
        "minverse": cgadyn.minverse(model, s.q),
        "rnea_derivatives": np.stack(cgadyn.rnea_derivatives(model, s.q, s.v, s.a), 1),
        "aba_derivatives": np.stack(cgadyn.aba_derivatives(model, s.q, s.v, s.tau), 1),
    }
    for i in range(11):
        single = {
            "rnea": cgadyn.rnea(model, s.q[i], s.v[i], s.a[i]),
            "aba": cgadyn.aba(model, s.q[i], s.v[i], s.tau[i]),
            "crba": cgadyn.crba(model, s.q[i]),
            "minverse": cgadyn.minverse(model, s.q[i]),
            "rnea_derivatives": np.stack(cgadyn.rnea_derivatives(model, s.q[i], s.v[i],
                                                                 s.a[i])),
            "aba_derivatives": np.stack(cgadyn.aba_derivatives(model, s.q[i], s.v[i],
                                                               s.tau[i])),
        }
        for key, value in single.items():
            assert np.allclose(batch[key][i], value, rtol=1e-12, atol=1e-12), (key, i)


def test_aba_inverts_rnea_and_minverse_inverts_crba(models):
    model, _ = models
    s = oracle.sample(model, 4, 10)
    tau = cgadyn.rnea(model, s.q, s.v, s.a)
    assert np.all(oracle.relative_error(cgadyn.aba(model, s.q, s.v, tau), s.a) <= 1e-9)
    eye = np.einsum("bij,bjk->bik", cgadyn.crba(model, s.q), cgadyn.minverse(model, s.q))
    assert np.abs(eye - np.eye(model.nv)).max() <= 1e-9


def test_manifold_identities(models):
    """``q0 ⊕ (q1 ⊖ q0) = q1`` (the quaternions up to sign), ``d/dt (q ⊕ t v) = v``, and
    every quaternion of a random configuration unit."""
    model, _ = models
    s = oracle.sample(model, 4, 11)
    q0, q1 = s.q, np.roll(s.q, 1, axis=0)
    back = cgadyn.integrate(model, q0, cgadyn.difference(model, q0, q1))
    T0 = cgadyn.link_placements(model, back)
    assert np.abs(T0 - cgadyn.link_placements(model, q1)).max() <= 1e-12
    for j in range(model.njoints):
        if model.joint_types[j] == SPHERICAL:
            quat = s.q[:, model.idx_q[j]:model.idx_q[j] + 4]
            assert np.allclose(np.linalg.norm(quat, axis=1), 1.0, atol=1e-14)
    h = 1e-6
    slope = (cgadyn.difference(model, q0, cgadyn.integrate(model, q0, h * s.v)) -
             cgadyn.difference(model, q0, cgadyn.integrate(model, q0, -h * s.v))) / (2 * h)
    assert np.abs(slope - s.v).max() <= 1e-8


def test_a_quaternion_off_the_unit_sphere_is_refused_by_name(models):
    model, _ = models
    j = next(j for j in range(model.njoints) if model.joint_types[j] == SPHERICAL)
    q = oracle.sample(model, 1, 12).q[0]
    q[model.idx_q[j]:model.idx_q[j] + 4] *= 1.1
    with pytest.raises(ValueError, match=model.joint_names[j]):
        cgadyn.rnea(model, q, np.zeros(model.nv), np.zeros(model.nv))


def test_rollout_keeps_quaternions_unit(models):
    """RK4 on the manifold: every spherical joint's quaternion stays unit, and without
    damping the energy drifts little."""
    model, _ = models
    s = oracle.sample(model, 2, 13)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = cgadyn.simulate(model, s.q, 0.5 * s.v, 1e-3, 300, passive=False)
    assert not np.any(traj.diverged)
    for j in range(model.njoints):
        if model.joint_types[j] == SPHERICAL:
            quat = traj.q[..., model.idx_q[j]:model.idx_q[j] + 4]
            assert np.abs(np.linalg.norm(quat, axis=-1) - 1.0).max() <= 1e-12
    drift = np.abs(traj.energy[:, -1] - traj.energy[:, 0]) / np.abs(traj.energy[:, 0])
    assert drift.max() <= 1e-6


BALLS = """
<mujoco model="balls">
  <compiler angle="radian"/>
  <worldbody>
    <body name="a" pos="0.1 0.2 0.3" quat="0.9 0.1 -0.3 0.2">
      <joint name="j1" type="hinge" axis="0.3 1 0.2" pos="0.05 -0.1 0.02" ref="0.4"
             armature="0.3" damping="0.7"/>
      <joint name="j2" type="ball" pos="-0.1 0.3 0.1" damping="0.2" armature="0.1"/>
      <geom type="box" size="0.1 0.2 0.05" pos="0.1 0 0" euler="0.2 0.1 0.3"/>
      <body name="b" pos="0 0 -0.5" euler="0.3 0.2 0.1">
        <joint name="j3" type="ball" pos="0 0.1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0.1 -0.4" size="0.04"/>
        <body name="c" pos="0.3 0.1 -0.4">
          <joint name="j4" type="hinge" axis="1 0 0"/>
          <geom type="sphere" size="0.1" pos="0.05 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_mujoco_ball_joints_agree_with_mujoco():
    mujoco = pytest.importorskip("mujoco")
    from cgadyn import mujoco_oracle
    from cgadyn.multibody.mujoco_model import from_mujoco

    mj = mujoco.MjModel.from_xml_string(BALLS)
    model = from_mujoco(mj)
    assert model.joint_names == ("j1", "j2", "j3", "j4")
    assert [model.joint_kinds[j] for j in range(4)] == ["continuous", "spherical", "spherical",
                                                        "continuous"]
    assert (model.nq, model.nv) == (mj.nq, mj.nv) == (10, 8)
    assert np.array_equal(model.armature, mj.dof_armature)
    assert np.array_equal(model.damping, mj.dof_damping)
    s = oracle.sample(model, 5, 14)
    s = oracle.States(s.q, 3.0 * s.v, s.a, s.tau)
    refs = mujoco_oracle.references(model, mj, s)
    mine = mujoco_oracle.mine(model, mj, s)
    cond = np.linalg.cond(mine["mj_mass_matrix"])
    for key, ref in refs.items():
        scale = cond if key in mujoco_oracle.SCALED else 1.0
        rel = oracle.relative_error(mine[key], ref)
        assert np.all(rel <= 1e-9 * scale), (key, float((rel / scale).max()))
    qpos, qvel = cgadyn.to_mujoco_state(model, s.q, s.v)
    assert np.array_equal(qpos[:, 1:5], np.concatenate([s.q[:, 4:5], s.q[:, 1:4]], 1))
    q, v = cgadyn.from_mujoco_state(model, qpos, qvel)
    assert np.array_equal(q, s.q) and np.array_equal(v, s.v)


def test_a_ball_joints_range_is_its_cone_limit():
    """A limited ball joint loads without a warning, its ``range`` kept as its cone limit
    (``Model.cone_limit``; the contact step enforces it, ``tests/test_cone_limits.py``)."""
    mujoco = pytest.importorskip("mujoco")
    from cgadyn.multibody.mujoco_model import from_mujoco

    xml = BALLS.replace('<joint name="j3" type="ball" pos="0 0.1 0"/>',
                        '<joint name="j3" type="ball" pos="0 0.1 0" range="0 0.7"/>')
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = from_mujoco(mujoco.MjModel.from_xml_string(xml))
    assert model.joint_kinds[2] == "spherical"
    assert model.cone_limit[2] == 0.7 and np.isinf(np.delete(model.cone_limit, 2)).all()


def test_pinocchio_mjcf_ball_joints_convert(tmp_path):
    """Pinocchio's own MJCF parser makes ball joints ``JointModelSpherical``; converted,
    they agree with Pinocchio."""
    path = tmp_path / "balls.xml"
    one = BALLS.replace('<body name="a" pos="0.1 0.2 0.3" quat="0.9 0.1 -0.3 0.2">',
                        '<body name="a">')  # Pinocchio: one joint a body (else a composite)
    start = one.index('<joint name="j1"')
    path.write_text(one[:start] + one[one.index("/>", start) + 2:])
    pm = pin.buildModelFromMJCF(str(path))
    model = cgadyn.from_pinocchio(pm)
    assert sum(model.joint_types[j] == SPHERICAL for j in range(model.njoints)) == 2
    data = pm.createData()
    s = oracle.sample(model, 3, 15)
    for q, v, a in zip(s.q, s.v, s.a, strict=True):
        qp = oracle.pin_configuration(model, q)
        ref = pin.rnea(pm, data, qp, v, a)
        assert oracle.relative_error(cgadyn.rnea(model, q, v, a)[None], ref[None])[0] <= TOL


def test_inverse_kinematics_reaches_poses_through_spherical_joints():
    """Levenberg-Marquardt on the manifold (``joint_integrate``): reachable poses of the
    chain's last link, the quaternions unit, judged by Pinocchio's log6."""
    model, res = ik_reaches_poses(MODELS["chain"]())
    for b in range(3):
        for j in (1, 3):
            i = model.idx_q[j]
            assert abs(np.linalg.norm(res.q[b, i:i + 4]) - 1.0) <= 1e-12
