"""Models from Pinocchio and MJCF: ``from_pinocchio`` of models built in code and parsed from
URDF, ``cgadyn.load`` of an MJCF file, all against Pinocchio on the same states; joints
that cgadyn does not support refused by name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

import cgadyn  # noqa: E402
from cgadyn.multibody import mjcf, registry  # noqa: E402
from cgadyn.multibody.joints.table import to_mujoco  # noqa: E402
from cgadyn.oracle import cgadyn_configuration, models, pin_configuration, symmetric  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "robots" / "slide_arm.xml"
TOL = 1e-12


@pytest.fixture(autouse=True)
def pinocchio_route(monkeypatch):
    """These tests read MJCF through Pinocchio's parser, the route without MuJoCo
    (``tests/test_mujoco_model.py`` tests MuJoCo's)."""
    from cgadyn.multibody import mujoco_model

    monkeypatch.setattr(mujoco_model, "available", lambda: False)


def _rel(mine, theirs) -> float:
    theirs = np.asarray(theirs)
    return float(np.abs(np.asarray(mine) - theirs).max() / max(np.abs(theirs).max(), 1e-300))


def _agree(model, pm, samples: int = 3, seed: int = 0) -> None:
    """rnea, aba, crba, every link's placement and world and local Jacobians agree with
    Pinocchio's to ``TOL`` relative, on random states."""
    rng = np.random.default_rng(seed)
    d = pm.createData()
    assert model.nv == pm.nv and model.joint_names == tuple(pm.names[1:])
    for _ in range(samples):
        q = cgadyn.random_configuration(model, rng)
        v, a = rng.standard_normal(model.nv), rng.standard_normal(model.nv)
        qp = pin_configuration(model, q)
        assert _rel(cgadyn.rnea(model, q, v, a), pin.rnea(pm, d, qp, v, a)) < TOL
        assert _rel(cgadyn.aba(model, q, v, a), pin.aba(pm, d, qp, v, a)) < 1e-10
        assert _rel(cgadyn.crba(model, q), symmetric(pin.crba(pm, d, qp))) < TOL
        pin.computeJointJacobians(pm, d, qp)
        pin.updateFramePlacements(pm, d)
        placements = cgadyn.link_placements(model, q)
        for k, link in enumerate(model.link_names):
            f = pm.getFrameId(link, pin.BODY)
            assert _rel(placements[k], d.oMf[f].homogeneous) < TOL
            for frame, ref in (("world", pin.WORLD), ("local", pin.LOCAL)):
                assert _rel(cgadyn.jacobian(model, q, link, frame),
                            pin.getFrameJacobian(pm, d, f, ref)) < TOL


def _inertia(rng):
    A = rng.standard_normal((3, 3))
    return pin.Inertia(rng.uniform(0.5, 2.0), 0.1 * rng.standard_normal(3),
                       A @ A.T + 0.1 * np.eye(3))


def _placement(rng):
    return pin.SE3(pin.exp3(rng.standard_normal(3)), 0.3 * rng.standard_normal(3))


def _unit(rng):
    x = rng.standard_normal(3)
    return x / np.linalg.norm(x)


def _continuous_unaligned(axis):
    """A ``JointModelRevoluteUnboundedUnaligned`` (its Python class takes no axis, URDF's
    continuous joint about an unaligned axis gives one)."""
    xml = (f'<robot name="r"><link name="a"/><link name="b"/><joint name="c" '
           f'type="continuous"><parent link="a"/><child link="b"/>'
           f'<axis xyz="{axis[0]} {axis[1]} {axis[2]}"/></joint></robot>')
    return pin.buildModelFromXML(xml).joints[1]


def coded_model(floating: bool = True, seed: int = 1):
    """A tree built in code with every supported joint type, unaligned axes included, two
    bodies appended per joint and a BODY frame per joint, off the joint's origin."""
    rng = np.random.default_rng(seed)
    pm = pin.Model()
    pm.name = "coded"
    root = 0
    if floating:
        root = pm.addJoint(0, pin.JointModelFreeFlyer(), _placement(rng), "base")
        pm.appendBodyToJoint(root, _inertia(rng), pin.SE3.Identity())
        pm.addBodyFrame("base_link", root, pin.SE3.Identity(), 0)
    joints = [pin.JointModelRX(), pin.JointModelRevoluteUnaligned(_unit(rng)),
              pin.JointModelRUBY(), _continuous_unaligned(_unit(rng)), pin.JointModelPZ(),
              pin.JointModelPrismaticUnaligned(_unit(rng)), pin.JointModelRZ(),
              pin.JointModelPY()]
    parents = [root, 1, 2, 1, 4, root, 6, 7]  # offsets from root: a branching tree
    for k, (joint, p) in enumerate(zip(joints, parents, strict=True)):
        parent = p if p == root else p + root
        j = pm.addJoint(parent, joint, _placement(rng), f"j{k}")
        pm.appendBodyToJoint(j, _inertia(rng), _placement(rng))
        pm.appendBodyToJoint(j, _inertia(rng), _placement(rng))
        pm.addBodyFrame(f"link{k}", j, _placement(rng), 0)
    return pm


@pytest.mark.parametrize("floating", [True, False])
def test_model_built_in_code_agrees_with_pinocchio(floating):
    pm = coded_model(floating)
    model = cgadyn.from_pinocchio(pm)
    assert model.floating_base == floating and model.name == "coded"
    assert model.joint_kinds.count("continuous") == 2
    assert model.nq == pm.nq - 2  # one angle per continuous joint, not (cos, sin)
    assert model.root_link == ("base_link" if floating else "universe")
    _agree(model, pm)


def test_configuration_conversion_round_trip():
    pm = coded_model()
    model = cgadyn.from_pinocchio(pm)
    q = cgadyn.random_configuration(model, np.random.default_rng(2))
    qp = pin_configuration(model, q)
    assert qp.shape == (pm.nq,)
    np.testing.assert_allclose(cgadyn_configuration(model, qp), q, atol=1e-15)
    with pytest.raises(ValueError, match=r"has 17 entries \(Pinocchio's nq\), got 16"):
        cgadyn_configuration(model, qp[:-1])


def test_model_without_body_frames_gets_a_link_per_joint():
    pm = pin.Model()
    j = pm.addJoint(0, pin.JointModelRY(), pin.SE3.Identity(), "hinge")
    pm.appendBodyToJoint(j, pin.Inertia.FromBox(1.0, 0.1, 0.2, 0.3), pin.SE3.Identity())
    model = cgadyn.from_pinocchio(pm, name="bare")
    assert model.link_names == ("universe", "hinge") and model.name == "bare"
    np.testing.assert_allclose(model.axis_vectors, [[0.0, 1.0, 0.0]])


@pytest.mark.parametrize("robot, floating", [("panda", False), ("double_pendulum_continuous",
                                                                 False), ("solo12", True)])
def test_example_robot_data_parsed_by_pinocchio(robot, floating):
    """The same URDF parsed by Pinocchio and converted agrees with Pinocchio and with
    ``cgadyn.load`` (link frames, limits, bodies and dynamics)."""
    if robot not in registry.robots():
        pytest.skip(f"{robot} not installed")
    path = str(registry.robot_path(robot))
    pm = (pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating
          else pin.buildModelFromUrdf(path))
    model = cgadyn.from_pinocchio(pm)
    loaded = cgadyn.load(robot)
    assert model.floating_base == loaded.floating_base == floating
    assert model.joint_names == loaded.joint_names and model.joint_kinds == loaded.joint_kinds
    assert set(model.link_names) == set(loaded.link_names)
    assert model.root_link == loaded.root_link
    for field in ("lower", "upper", "parents", "body_mass", "axis_vectors"):
        np.testing.assert_allclose(getattr(model, field), getattr(loaded, field), atol=1e-12)
    _agree(model, pm, samples=2)
    rng = np.random.default_rng(5)
    q = cgadyn.random_configuration(model, rng)
    v, a = rng.standard_normal(model.nv), rng.standard_normal(model.nv)
    assert _rel(cgadyn.rnea(model, q, v, a), cgadyn.rnea(loaded, q, v, a)) < TOL
    order = [loaded.link_index(name) for name in model.link_names]
    assert _rel(cgadyn.link_placements(model, q), cgadyn.link_placements(loaded, q)[order]) < TOL


def test_mjcf_file_loads_as_pinocchio_parses_it():
    model = cgadyn.load(str(ARM))
    pm = pin.buildModelFromMJCF(str(ARM))
    assert registry.resolve(str(ARM))[0] == "mjcf"
    assert model.name == "slide_arm" and not model.floating_base
    assert model.joint_kinds == ("revolute", "revolute", "prismatic", "revolute")
    assert model.link_names == ("stand", "turret", "upper_arm", "forearm", "wrist", "tool")
    np.testing.assert_allclose(model.lower[:3], [-2.5, -1.5, -0.1])
    assert model.total_mass == pytest.approx(2.0 + 1.5 + 0.8 + 0.3 + 0.2)  # the tool welded
    _agree(model, pm)
    text = ARM.read_text()
    assert registry.resolve(text)[0] == "mjcf"
    assert np.array_equal(cgadyn.load(text).inertias, model.inertias)
    _, oracle_pm = models(str(ARM))
    assert oracle_pm.nq == pm.nq and oracle_pm.name == "slide_arm"


@pytest.mark.parametrize("xml, mjcf", [
    (b'<mujoco model="a"/>', True),
    (b'\xef\xbb\xbf<?xml version="1.0"?>\n<!-- a <robot> -->\n<mujoco>', True),
    (b'<robot name="x"><mujoco/></robot>', False),
    (b"<mujocox/>", False),
    (b"not xml", False),
])
def test_mjcf_is_decided_by_the_root_element(xml, mjcf):
    from cgadyn.multibody.mjcf import is_mjcf

    assert is_mjcf(xml) is mjcf


def test_mjcf_floating_base(tmp_path):
    floating = cgadyn.load(ARM, floating_base=True)
    assert floating.floating_base and floating.joint_names[0] == "root_joint"
    assert floating.root_link == "stand" and floating.nv == 10
    _agree(floating, pin.buildModelFromMJCFAndRootJoint(str(ARM), pin.JointModelFreeFlyer()),
           samples=1)
    free = tmp_path / "free_arm.xml"
    free.write_text(ARM.read_text().replace('<body name="stand">', FREE_BODY))
    model = cgadyn.load(free)
    assert model.floating_base and model.nv == 10 and model.joint_names[0] == "float"
    pm = mjcf.pinocchio_model(free)  # the free joint's placement the identity, as in MuJoCo
    assert pm.jointPlacements[1].isIdentity()
    _agree(model, pm, samples=1)
    assert models(free)[1].jointPlacements[1].isIdentity()  # the oracle reads it alike
    with pytest.raises(ValueError, match="the root body has a free joint"):
        cgadyn.load(free, floating_base=False)


FREE_BODY = '<body name="stand" pos="0.3 0 1" euler="0.2 0.1 0"><freejoint name="float"/>'
"""slide_arm's stand made a free body, placed and turned in the world."""


@pytest.mark.parametrize("free", [False, True])
def test_mjcf_model_agrees_with_mujoco(tmp_path, free):
    """The file means to cgadyn what it means to MuJoCo itself: mass matrix, bias forces
    (C(q, v) v + g(q)) and every body's pose, on random states. A free joint's q and v are
    Pinocchio's (quaternion w last, linear velocity in the body frame); MuJoCo puts w first
    and the linear velocity in the world frame: v_cgadyn = T v_mujoco, M_mujoco = Tᵀ M T."""
    mujoco = pytest.importorskip("mujoco")
    path = ARM
    if free:
        path = tmp_path / "free_arm.xml"
        path.write_text(ARM.read_text().replace('<body name="stand">', FREE_BODY))
    mm = mujoco.MjModel.from_xml_path(str(path))
    md = mujoco.MjData(mm)
    model = cgadyn.load(path)
    assert model.floating_base == free
    rng = np.random.default_rng(7)
    M = np.zeros((mm.nv, mm.nv))
    for _ in range(3):
        q, v = cgadyn.random_configuration(model, rng), rng.standard_normal(model.nv)
        md.qpos[:] = to_mujoco(model, q)  # w first (multibody.joints)
        mujoco.mj_forward(mm, md)
        mujoco.mj_fullM(mm, md, M)
        T = np.eye(model.nv)
        if free:
            T[:3, :3] = md.xmat[1].reshape(3, 3).T
        assert _rel(T.T @ cgadyn.crba(model, q) @ T, M) < TOL
        if not free:
            md.qvel[:] = v
            mujoco.mj_forward(mm, md)
            assert _rel(cgadyn.nonlinear_effects(model, q, v), md.qfrc_bias) < TOL
        placements = cgadyn.link_placements(model, q)
        for k, link in enumerate(model.link_names):
            b = mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_BODY, link)
            np.testing.assert_allclose(placements[k, :3, 3], md.xpos[b], atol=1e-14)
            np.testing.assert_allclose(placements[k, :3, :3], md.xmat[b].reshape(3, 3),
                                       atol=1e-14)


@pytest.mark.parametrize("attrs", ['pos="0 0 0.1"', 'euler="0.4 0 0"', 'quat="0 1 0 0"'])
def test_mjcf_world_body_away_from_the_origin_refused(tmp_path, attrs):
    """Pinocchio's MJCF parser puts a jointless child of <worldbody> at the origin; such a
    file is refused rather than loaded as another robot, and wrapping it loads."""
    moved = tmp_path / "moved.xml"
    moved.write_text(ARM.read_text().replace('<body name="stand">',
                                             f'<body name="stand" {attrs}>'))
    with pytest.raises(ValueError, match=r"body 'stand' is welded to the world with "
                                         r"\w+=.*which Pinocchio's MJCF parser ignores"):
        cgadyn.load(moved)
    wrapped = tmp_path / "wrapped.xml"
    wrapped.write_text(moved.read_text().replace('<body name="stand"', '<body name="base">'
                                                 '<body name="stand"').replace(
        "</worldbody>", "</body></worldbody>"))
    assert cgadyn.load(wrapped).link_names[:2] == ("base", "stand")
    assert cgadyn.load(ARM.read_text().replace('<body name="stand">',  # identity: accepted
                                               '<body name="stand" quat="-1 0 0 0">')).nv == 4


def test_cli_validates_an_mjcf_file(capsys):
    from cgadyn.cli import main

    assert main(["validate", str(ARM), "--samples", "2"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("cgadyn validate: slide_arm, fixed base, nq 4, nv 4")
    assert "PASS: 13/13" in out


@pytest.mark.parametrize("make, shortname", [
    (lambda pm: pin.JointModelComposite(pin.JointModelRX()), "JointModelComposite"),
    (lambda pm: pin.JointModelMimic(pm.joints[1], 2.0, 0.1), "JointModelMimic"),
])
def test_unsupported_joint_refused_by_name(make, shortname):
    pm = pin.Model()
    pm.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "elbow")
    pm.addJoint(1, make(pm), pin.SE3.Identity(), "wrist")
    with pytest.raises(ValueError, match=rf"joint 'wrist' is a {shortname}, which cgadyn does "
                                         rf"not support; supported joints: revolute"):
        cgadyn.from_pinocchio(pm)


def test_mjcf_ball_joint_is_spherical(tmp_path):
    ball = tmp_path / "ball.xml"
    ball.write_text(ARM.read_text().replace('type="hinge" axis="1 0 0"', 'type="ball"'))
    model = cgadyn.load(ball)
    assert model.joint_kinds[model.joint_names.index("roll")] == "spherical"


def test_free_flyer_below_the_root_refused():
    pm = pin.Model()
    pm.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "yaw")
    pm.addJoint(1, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "floater")
    with pytest.raises(ValueError, match="'floater' is a JointModelFreeFlyer whose parent is "
                                         "not the universe"):
        cgadyn.from_pinocchio(pm)


def test_what_the_model_cannot_hold_is_refused():
    with pytest.raises(ValueError, match="expects a pinocchio.Model, got str"):
        cgadyn.from_pinocchio("panda")
    pm = coded_model(floating=False)
    pm.armature[2] = -0.1
    with pytest.raises(ValueError, match=r"Model.armature\[2\] .* is -0.1; expected a finite "
                                         r"number >= 0"):
        cgadyn.from_pinocchio(pm)
    pm = coded_model(floating=False)
    pm.gravity.linear = np.array([0.0, 0.0, -1.62])
    with pytest.raises(ValueError, match=r"gravity is \[0.0, 0.0, -1.62\]"):
        cgadyn.from_pinocchio(pm)
    pm = coded_model(floating=False)
    pm.inertias[3] = pin.Inertia.FromDynamicParameters(  # Pinocchio does not check these
        np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, -1.0]))
    with pytest.raises(ValueError, match="the body of joint 'j2'.*check_inertia=False"):
        cgadyn.from_pinocchio(pm)
    assert cgadyn.from_pinocchio(pm, check_inertia=False).body_mass[2] == 1.0


def test_mjcf_models_are_cached_on_disk(tmp_path, monkeypatch):
    from cgadyn.multibody.mjcf import load_mjcf

    monkeypatch.setenv("CGADYN_CACHE_DIR", str(tmp_path))
    built = load_mjcf(ARM)
    assert len(list(tmp_path.rglob("*.npz"))) == 1
    read = load_mjcf(ARM)
    assert read is not built and read.link_names == built.link_names
    assert np.array_equal(read.inertias, built.inertias) and read.root_link == "stand"
    assert load_mjcf(ARM, floating_base=True).floating_base  # its own entry
    assert len(list(tmp_path.rglob("*.npz"))) == 2
