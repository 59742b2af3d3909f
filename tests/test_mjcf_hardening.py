"""MJCF read whole or refused, and ``from_pinocchio`` exact (issue 31, items 3, 9, 10).

Pinocchio's MJCF parser (4.1) reads only the first body under ``<worldbody>``, ignores a
root joint asked for a body that has a joint, drops sites, ignores ``<include>`` and reads
NaN through: each is refused by name or read as MuJoCo reads it, checked against MuJoCo's
own compiler. A ``PrismaticUnaligned`` joint with a non-unit axis converts exactly; a
revolute one, which Pinocchio cannot turn rigidly, is refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

import cgadyn  # noqa: E402
from cgadyn.multibody.joints.table import to_mujoco  # noqa: E402
from cgadyn.oracle import models, symmetric  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "robots" / "slide_arm.xml"
TOL = 1e-12

BODY = ('<body name="{name}" pos="{pos}">{joint}'
        '<inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.03"/></body>')
HINGE = '<joint name="{name}_joint" type="hinge" axis="0 1 0"/>'


@pytest.fixture(autouse=True)
def pinocchio_route(monkeypatch):
    """These tests read MJCF through Pinocchio's parser, the route without MuJoCo
    (``tests/test_mujoco_model.py`` tests MuJoCo's)."""
    from cgadyn.multibody import mujoco_model

    monkeypatch.setattr(mujoco_model, "available", lambda: False)


def _scene(*bodies: str, extra: str = "") -> str:
    return (f'<mujoco model="scene"><worldbody><geom type="plane" size="1 1 0.1"/>'
            f'{"".join(bodies)}{extra}</worldbody></mujoco>')


def _body(name: str, pos: str = "0 0 0", joint: str | None = None) -> str:
    joint = {"hinge": HINGE.format(name=name), "free": f'<freejoint name="{name}_free"/>',
             None: ""}[joint]
    return BODY.format(name=name, pos=pos, joint=joint)


def _rel(mine, theirs) -> float:
    theirs = np.asarray(theirs)
    return float(np.abs(np.asarray(mine) - theirs).max() / max(np.abs(theirs).max(), 1e-300))


@pytest.mark.parametrize("bodies, dropped", [
    ((_body("table"), _body("arm", "0 0 0.5", "hinge")), "'arm'"),
    ((_body("left", "0 0.3 0", "hinge"), _body("right", "0 -0.3 0", "hinge")), "'right'"),
    ((_body("ball", "0 0 1", "free"), _body("box", "1 0 1", "free")), "'box'"),
])
def test_bodies_after_the_first_top_level_body_are_refused_by_name(bodies, dropped):
    """A table then an arm loaded as a robot with no joints; two arms as one; two free
    bodies as one. Now refused, naming what would be dropped."""
    with pytest.raises(ValueError, match=rf"cgadyn reads one top-level body per MJCF file "
                                         rf"for now.*the bodies {dropped} would be dropped"):
        cgadyn.load(_scene(*bodies))


def test_a_body_nested_in_a_frame_or_a_world_without_body_is_refused():
    nested = _body("arm", joint="hinge").replace(
        "</body>", f'<frame pos="0 0 1">{_body("lost", joint="hinge")}</frame></body>')
    with pytest.raises(ValueError, match=r"the bodies 'lost' would be dropped"):
        cgadyn.load(_scene(nested))
    with pytest.raises(ValueError, match=r"no <body> under <worldbody>"):
        cgadyn.load(_scene())


def test_floating_base_on_a_body_with_a_joint_is_refused_naming_the_joint():
    """Pinocchio ignored the request: a fixed model with nq 2 came back for
    floating_base=True, and validate --floating-base passed it."""
    two_joints = _body("arm", joint="hinge").replace(
        "</body>", _body("hand", "0.3 0 0").replace(
            "<inertial", '<joint name="lift" type="slide" axis="0 0 1"/><inertial') + "</body>")
    with pytest.raises(ValueError, match=r"floating_base=True, but the top-level body 'arm' "
                                         r"has the joint 'arm_joint', so no free flyer"):
        cgadyn.load(_scene(two_joints), floating_base=True)
    with pytest.raises(ValueError, match="has the joint 'arm_joint'"):
        models(_scene(two_joints), floating_base=True)
    assert cgadyn.load(_scene(two_joints)).nq == 2  # its own base: fixed
    free = cgadyn.load(_scene(_body("ball", "0 0 1", "free")), floating_base=True)
    assert free.floating_base and free.joint_names == ("ball_free",)


def _mujoco_free_arm(tmp_path) -> Path:
    path = tmp_path / "free_arm.xml"
    path.write_text(ARM.read_text().replace('<body name="stand">',
                                            '<body name="stand"><freejoint name="root_joint"/>'))
    return path


def test_floating_base_added_to_a_jointless_body_agrees_with_mujoco(tmp_path):
    """floating_base=True on slide_arm (its stand has no joint) means what a <freejoint/>
    on the stand means to MuJoCo: mass matrix and body poses (M_mujoco = Tᵀ M T)."""
    mujoco = pytest.importorskip("mujoco")
    model = cgadyn.load(ARM, floating_base=True)
    assert model.floating_base and model.joint_names[0] == "root_joint"
    mm = mujoco.MjModel.from_xml_path(str(_mujoco_free_arm(tmp_path)))
    md = mujoco.MjData(mm)
    M = np.zeros((mm.nv, mm.nv))
    rng = np.random.default_rng(11)
    for _ in range(3):
        q = cgadyn.random_configuration(model, rng)
        md.qpos[:] = to_mujoco(model, q)  # w first (multibody.joints)
        mujoco.mj_forward(mm, md)
        mujoco.mj_fullM(mm, md, M)
        T = np.eye(model.nv)
        T[:3, :3] = md.xmat[1].reshape(3, 3).T
        assert _rel(T.T @ cgadyn.crba(model, q) @ T, M) < TOL
        placements = cgadyn.link_placements(model, q)
        for k, link in enumerate(model.link_names):
            b = mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_BODY, link)
            np.testing.assert_allclose(placements[k, :3, 3], md.xpos[b], atol=1e-14)
            np.testing.assert_allclose(placements[k, :3, :3], md.xmat[b].reshape(3, 3),
                                       atol=1e-14)


SITES = """<mujoco model="sites">
  <worldbody>
    <site name="world_site" pos="0.1 0.2 0.3" euler="10 20 30"/>
    <body name="base">
      <inertial pos="0 0 0" mass="3" diaginertia="0.1 0.1 0.1"/>
      <site name="base_site" pos="0 0.1 0.05" axisangle="1 1 0 45"/>
      <body name="link1" pos="0 0 0.2" euler="0 15 0">
        <joint name="j1" type="hinge" axis="0 1 1"/>
        <inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.03"/>
        <site name="mid" pos="0.2 0 0" quat="0.9 0.1 0.2 0.3"/>
        <site type="capsule" name="bar" fromto="0 0 0 0.3 0.1 -0.2" size="0.01"/>
        <body name="link2" pos="0.4 0 0">
          <joint name="j2" type="slide" axis="1 0 0"/>
          <inertial pos="0.05 0 0" mass="0.5" diaginertia="0.01 0.01 0.01"/>
          <site name="tip" pos="0.1 0.02 0" xyaxes="0 1 0 -1 0 0.3"/>
          <site name="tip_z" pos="0.1 0 0.01" zaxis="1 1 1"/>
          <site pos="0 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>"""
"""Named sites placed every way MJCF allows (angles in degrees, MJCF's default), on the
world, a welded body and two moving ones, and one unnamed site (left out)."""


def test_sites_are_links_placed_as_mujoco_places_them():
    mujoco = pytest.importorskip("mujoco")
    model = cgadyn.load(SITES)
    names = ("world_site", "base_site", "mid", "bar", "tip", "tip_z")
    assert model.link_names == ("base", "link1", "link2", *names)
    assert model.total_mass == pytest.approx(1.5)  # sites add no mass
    mm = mujoco.MjModel.from_xml_string(SITES)
    md = mujoco.MjData(mm)
    _, pm = models(SITES)  # the oracle's model has the sites as frames too
    d = pm.createData()
    rng = np.random.default_rng(4)
    for _ in range(3):
        q = rng.standard_normal(model.nq)
        md.qpos[:] = q
        mujoco.mj_forward(mm, md)
        placements = cgadyn.link_placements(model, q)
        pin.computeJointJacobians(pm, d, q)
        pin.updateFramePlacements(pm, d)
        for name in names:
            k, s = model.link_index(name), mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_SITE, name)
            np.testing.assert_allclose(placements[k, :3, 3], md.site_xpos[s], atol=1e-14)
            np.testing.assert_allclose(placements[k, :3, :3], md.site_xmat[s].reshape(3, 3),
                                       atol=1e-14)
            f = pm.getFrameId(name, pin.BODY)
            assert _rel(cgadyn.jacobian(model, q, name, "world"),
                        pin.getFrameJacobian(pm, d, f, pin.WORLD)) < TOL
        jac = np.zeros((3, mm.nv))
        mujoco.mj_jacSite(mm, md, jac, None, mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_SITE,
                                                               "tip"))
        J = cgadyn.jacobian(model, q, "tip", "local_world_aligned")
        np.testing.assert_allclose(J[:3], jac, atol=1e-14)


def test_a_site_named_as_a_body_or_placed_by_a_default_is_refused():
    with pytest.raises(ValueError, match="site 'link2' has the name of a body"):
        cgadyn.load(SITES.replace('name="tip"', 'name="link2"'))
    defaults = SITES.replace("<worldbody>",
                             '<default><site pos="0 0 1"/></default><worldbody>')
    with pytest.raises(ValueError, match="a <default> class sets the site attribute 'pos'"):
        cgadyn.load(defaults)


@pytest.mark.parametrize("old, new, message", [
    ('<inertial pos="0.1 0 0" mass="1"', '<inertial pos="nan 0 0" mass="1"',
     r"body 'link1': <inertial pos=\"nan 0 0\"> is not 3 finite numbers"),
    ('<body name="link2" pos="0.4 0 0">', '<body name="link2" pos="0.4 inf 0">',
     r"body 'link2': <body pos=\"0.4 inf 0\"> is not 3 finite numbers"),
    ('axis="0 1 1"', 'axis="0 1"', r"body 'link1': <joint axis=\"0 1\"> is not 3 finite"),
    ('mass="0.5"', 'mass="heavy"', r"body 'link2': <inertial mass=\"heavy\"> is not 1 finite "
                                   r"number"),
])
def test_numbers_that_are_not_finite_are_named(old, new, message):
    """NaN in <inertial pos> said "Eigenvalues did not converge", naming nothing."""
    assert old in SITES
    with pytest.raises(ValueError, match=message):
        cgadyn.load(SITES.replace(old, new))


def test_a_code_built_body_that_is_not_finite_is_named():
    pm = pin.Model()
    j = pm.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "elbow")
    pm.appendBodyToJoint(j, pin.Inertia(1.0, np.array([np.nan, 0.0, 0.0]), np.eye(3)),
                         pin.SE3.Identity())
    with pytest.raises(ValueError, match=r"the body of joint 'elbow' has a centre of mass "
                                         r"\(lever\) that is not finite"):
        cgadyn.from_pinocchio(pm)


def _part(body: str) -> str:
    return f"<mujoco>{body}</mujoco>"


def test_includes_are_read_as_mujoco_reads_them(tmp_path):
    """Pinocchio 4.1 ignores <include> ("no body found", with its C++ source location):
    expanded here, relative to the main file's directory, nested includes too."""
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "arm.xml").write_text(_part(
        '<worldbody><include file="parts/body.xml"/></worldbody>'))
    (tmp_path / "parts" / "body.xml").write_text(_part(_body("arm", joint="hinge")))
    main = tmp_path / "main.xml"
    main.write_text('<mujoco model="inc"><compiler angle="radian"/>'
                    '<include file="parts/arm.xml"/></mujoco>')
    model = cgadyn.load(main)
    inline = cgadyn.load(_scene(_body("arm", joint="hinge")))
    assert model.joint_names == ("arm_joint",) and model.link_names == ("arm",)
    assert np.array_equal(model.inertias, inline.inertias)
    mujoco = pytest.importorskip("mujoco")
    assert mujoco.MjModel.from_xml_path(str(main)).nq == model.nq


@pytest.mark.parametrize("include, part, message", [
    ('<include file="missing.xml"/>', None,
     r"<include file='missing.xml'> names a file that does not exist: '.*missing.xml'"),
    ("<include/>", None, r"an <include> has no 'file' attribute"),
    ('<include file="part.xml"/>', "<mujoco><worldbody><body></worldbody></mujoco>",
     r"malformed XML in '.*part.xml' \(included by '.*main.xml'\)"),
    ('<include file="part.xml"/>', '<robot name="r"/>',
     r"the included file '.*part.xml' has the root element <robot>; expected <mujoco>"),
])
def test_include_errors_name_the_file_without_cpp_locations(tmp_path, include, part, message):
    if part is not None:
        (tmp_path / "part.xml").write_text(part)
    main = tmp_path / "main.xml"
    main.write_text(f'<mujoco model="inc"><worldbody>{include}</worldbody></mujoco>')
    with pytest.raises(ValueError, match=message) as info:
        cgadyn.load(main)
    assert ".cpp" not in str(info.value) and "From file" not in str(info.value)


def test_pinocchio_errors_come_without_cpp_locations():
    mesh = _scene(_body("arm", joint="hinge")).replace(
        "<worldbody>", '<asset><mesh name="m"/></asset><worldbody>')
    with pytest.raises(ValueError, match=r"Pinocchio cannot parse the MJCF in the MJCF text: "
                                         r"\S") as info:
        cgadyn.load(mesh)
    assert ".cpp" not in str(info.value) and "From file" not in str(info.value)


def test_slide_arm_loads_by_name():
    from cgadyn.multibody import registry

    assert "slide_arm" in cgadyn.robots() and registry.source("slide_arm") == "cgadyn"
    model = cgadyn.load("slide_arm")
    assert model.name == "slide_arm" and model.nq == 4 and not model.floating_base
    assert np.array_equal(model.inertias, cgadyn.load(ARM).inertias)
    assert cgadyn.load("slide_arm", floating_base=True).floating_base
    assert models("slide_arm")[1].nq == 4  # the oracle reads it as MJCF too


@pytest.mark.parametrize("value", ["False", "True", 0, 1, 0.0, "yes"])
def test_floating_base_other_than_a_bool_or_none_is_refused(value):
    """load("panda", floating_base="False") returned a floating model."""
    with pytest.raises(ValueError, match=r"floating_base must be True, False or None"):
        cgadyn.load("panda", floating_base=value)


def test_numpy_bools_are_accepted_as_floating_base():
    assert cgadyn.load("slide_arm", floating_base=np.True_).floating_base
    assert not cgadyn.load("slide_arm", floating_base=np.bool_(False)).floating_base


def _unaligned_prismatic_model():
    """Two PrismaticUnaligned joints with non-unit axes around a hinge, BODY frames off
    the joints' origins: Pinocchio moves each body by q times its axis."""
    rng = np.random.default_rng(8)
    pm = pin.Model()
    parent = 0
    for k, joint in enumerate((pin.JointModelPrismaticUnaligned(np.array([1.0, 1.0, 0.0])),
                               pin.JointModelRY(),
                               pin.JointModelPrismaticUnaligned(np.array([0.2, -0.3, 0.1])))):
        placement = pin.SE3(pin.exp3(rng.standard_normal(3)), rng.standard_normal(3))
        parent = pm.addJoint(parent, joint, placement, f"j{k}")
        pm.appendBodyToJoint(parent, pin.Inertia(1.0 + k, 0.1 * rng.standard_normal(3),
                                                 np.diag([0.1, 0.2, 0.25])),
                             pin.SE3.Identity())
        pm.addFrame(pin.Frame(f"link{k}", parent, 0, pin.SE3(
            pin.exp3(rng.standard_normal(3)), rng.standard_normal(3)), pin.FrameType.BODY,
            pin.Inertia.Zero()), False)
    return pm


def test_prismatic_unaligned_with_a_non_unit_axis_converts_exactly():
    """Its axis was normalised: rnea 0.50 relative off, link placements 0.58."""
    pm = _unaligned_prismatic_model()
    model = cgadyn.from_pinocchio(pm)
    np.testing.assert_array_equal(model.axis_vectors[[0, 2]], [[1.0, 1.0, 0.0],
                                                              [0.2, -0.3, 0.1]])
    d = pm.createData()
    rng = np.random.default_rng(9)
    for _ in range(3):
        q, v, a = (rng.standard_normal(3) for _ in range(3))
        assert _rel(cgadyn.rnea(model, q, v, a), pin.rnea(pm, d, q, v, a)) < TOL
        assert _rel(cgadyn.crba(model, q), symmetric(pin.crba(pm, d, q))) < TOL
        assert _rel(cgadyn.aba(model, q, v, a), pin.aba(pm, d, q, v, a)) < TOL
        pin.computeRNEADerivatives(pm, d, q, v, a)
        dq, dv, _ = cgadyn.rnea_derivatives(model, q, v, a)
        assert _rel(dq, d.dtau_dq) < TOL and _rel(dv, d.dtau_dv) < TOL
        pin.forwardKinematics(pm, d, q)
        pin.updateFramePlacements(pm, d)
        pin.computeJointJacobians(pm, d, q)
        placements = cgadyn.link_placements(model, q)
        for k, link in enumerate(model.link_names):
            f = pm.getFrameId(link, pin.BODY)
            assert _rel(placements[k], d.oMf[f].homogeneous) < TOL
            assert _rel(cgadyn.jacobian(model, q, link, "world"),
                        pin.getFrameJacobian(pm, d, f, pin.WORLD)) < TOL
    batch = rng.standard_normal((5, 3))
    assert _rel(cgadyn.rnea(model, batch, batch, batch),
                [pin.rnea(pm, d, x, x, x) for x in batch]) < TOL


def test_revolute_unaligned_with_a_non_unit_axis_is_refused_by_name():
    """Pinocchio turns such a joint by a matrix that is not a rotation (RᵀR - 1 is 0.47
    for the axis (1, 1, 0)): no rigid model to convert."""
    pm = pin.Model()
    pm.addJoint(0, pin.JointModelRevoluteUnaligned(np.array([1.0, 1.0, 0.0])),
                pin.SE3.Identity(), "tilted")
    with pytest.raises(ValueError, match=r"joint 'tilted' is a JointModelRevoluteUnaligned "
                                         r"about the axis \[1.0, 1.0, 0.0\] of norm 1.41"):
        cgadyn.from_pinocchio(pm)
