"""URDF loading checked against Pinocchio: joint order, parents, placements, axes,
inertias (fixed joints merged), limits and link frames; and every malformed input."""

from __future__ import annotations

import dataclasses
import functools
import glob
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cgadyn.cga.conventions import (
    inertia_from_parameters,
    inertia_to_pinocchio,
    inertia_transform,
    matrix_from_motor,
    motion_from_twist,
    motor_from_matrix,
    motor_product,
)
from cgadyn.multibody import (
    FREE_FLYER,
    PRISMATIC,
    REVOLUTE,
    REVOLUTE_UNBOUNDED,
    Model,
    load,
    load_urdf,
    robot_path,
    robots,
)
from cgadyn.multibody.joints import unit_axes
from cgadyn.multibody.registry import OWN_ROBOTS_DIR, refused

OWN = sorted(p.stem for p in OWN_ROBOTS_DIR.glob("*.urdf"))
# every registry robot that loads by default, fixed to the world: these tests check the URDF
# parser (the free-flyer root has tests of its own; MJCF robots have theirs)
ALL = [name for name in robots()
       if name not in refused() and robot_path(name).suffix != ".xml"]


@functools.cache
def pin_model(name: str) -> pin.Model:
    return pin.buildModelFromXML(robot_path(name).read_text())


def fixed(name: str) -> Model:
    return load(name, floating_base=False)


def close(a, b, tol=1e-12):
    a, b = np.asarray(a), np.asarray(b)
    return np.allclose(a, b, rtol=tol, atol=tol * max(1.0, float(np.abs(b).max(initial=0.0))))


# --- against Pinocchio, every registry robot ----------------------------------------------


@pytest.mark.parametrize("name", ALL)
def test_joint_order_and_parents(name):
    m, pm = fixed(name), pin_model(name)
    assert m.joint_names == tuple(pm.names[1:])
    assert m.nq == m.nv == m.njoints == pm.njoints - 1
    np.testing.assert_array_equal(m.parents, np.array(pm.parents[1:]) - 1)
    assert all(m.parents[j] < j for j in range(m.nq))


@pytest.mark.parametrize("name", ALL)
def test_placements(name):
    m, pm = fixed(name), pin_model(name)
    for j in range(m.nq):
        ref = pm.jointPlacements[j + 1].homogeneous
        assert close(m.placement_matrices[j], ref), m.joint_names[j]
        assert close(matrix_from_motor(m.placements[j]), ref), m.joint_names[j]


@pytest.mark.parametrize("name", ALL)
def test_axes(name):
    """The joint screw, in the joint frame, equals Pinocchio's motion subspace."""
    m, pm = fixed(name), pin_model(name)
    data, q = pm.createData(), pin.neutral(pm)
    for j in range(m.nq):
        S = pin.computeJointJacobian(pm, data, q, j + 1)[:, pm.idx_vs[j + 1]]
        assert close(motion_from_twist(m.axes[j]), S), m.joint_names[j]
        assert close(np.linalg.norm(m.axis_vectors[j]), 1.0)
        kind = m.joint_kinds[j]
        assert m.joint_types[j] == {"prismatic": PRISMATIC, "continuous": REVOLUTE_UNBOUNDED,
                                    "revolute": REVOLUTE}[kind]


@pytest.mark.parametrize("name", ALL)
def test_inertias(name):
    m, pm = fixed(name), pin_model(name)
    for j in range(m.nq):
        ref = pm.inertias[j + 1].matrix()
        assert close(inertia_to_pinocchio(m.inertias[j]), ref), m.joint_names[j]
        assert close(m.body_mass[j], pm.inertias[j + 1].mass)
        if m.body_mass[j] > 0:
            assert close(m.body_com[j], pm.inertias[j + 1].lever)
        assert close(m.body_rotational_inertia[j], pm.inertias[j + 1].inertia)


@pytest.mark.parametrize("name", ALL)
def test_limits(name):
    m, pm = fixed(name), pin_model(name)
    for j in range(m.nq):
        iq, iv = pm.idx_qs[j + 1], pm.idx_vs[j + 1]
        if m.joint_kinds[j] == "continuous":
            assert m.lower[j] == -np.inf and m.upper[j] == np.inf
            assert pm.nqs[j + 1] == 2
        else:
            assert m.lower[j] == pm.lowerPositionLimit[iq]
            assert m.upper[j] == pm.upperPositionLimit[iq]
        assert m.velocity_limit[j] == pm.velocityLimit[iv]
        assert m.effort_limit[j] == pm.effortLimit[iv]


@pytest.mark.parametrize("name", ALL)
def test_link_frames(name):
    m, pm = fixed(name), pin_model(name)
    assert set(m.link_names) == {f.name for f in pm.frames if f.type == pin.BODY}
    assert m.link_joint[m.link_index(m.root_link)] == -1
    for i, link in enumerate(m.link_names):
        f = pm.frames[pm.getFrameId(link, pin.BODY)]
        assert m.link_joint[i] == f.parentJoint - 1, link
        assert close(m.link_placement_matrices[i], f.placement.homogeneous), link
        assert close(matrix_from_motor(m.link_placements[i]), f.placement.homogeneous), link


# --- merging fixed joints: the CGA formula of the brief ----------------------------------


def _link_inertias(urdf_path):
    """Per link: (mass, com, rotational inertia, inertial origin 4x4), parsed independently."""
    import xml.etree.ElementTree as ET

    def origin(el):
        o = el.find("origin")
        xyz = np.fromstring(o.get("xyz", "0 0 0"), sep=" ") if o is not None else np.zeros(3)
        rpy = np.fromstring(o.get("rpy", "0 0 0"), sep=" ") if o is not None else np.zeros(3)
        T = np.eye(4)
        T[:3, :3] = pin.rpy.rpyToMatrix(*rpy)
        T[:3, 3] = xyz
        return T

    out = {}
    for link in ET.parse(urdf_path).getroot().findall("link"):
        el = link.find("inertial")
        if el is None:
            continue
        i = el.find("inertia")
        g = {k: float(i.get(k, 0.0)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        I3 = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]],
                       [g["ixz"], g["iyz"], g["izz"]]])
        out[link.get("name")] = (float(el.find("mass").get("value")), I3, origin(el))
    return out


@pytest.mark.parametrize("name", [*OWN, "panda", "ur5", "baxter"])
def test_inertias_are_sums_of_moved_link_inertias(name):
    """inertias[j] = sum over links on body j of (link pose @ inertial origin) * I_link."""
    m = load(name)
    links = _link_inertias(robot_path(name))
    total = np.zeros((m.nq, 6, 6))
    for i, link in enumerate(m.link_names):
        j = m.link_joint[i]
        if j < 0 or link not in links:
            continue
        mass, I3, T_inertial = links[link]
        pose = motor_product(m.link_placements[i], motor_from_matrix(T_inertial))
        total[j] += inertia_transform(pose, inertia_from_parameters(mass, np.zeros(3), I3))
    for j in range(m.nq):
        assert close(total[j], m.inertias[j], 1e-11), m.joint_names[j]


# --- the model's contract -----------------------------------------------------------------


def test_model_is_immutable():
    m = load("skew_arm")
    for field in ("parents", "placements", "axes", "inertias", "body_mass", "lower",
                  "link_joint", "link_placements", "joint_types"):
        arr = getattr(m, field)
        assert not arr.flags.writeable, field
        with pytest.raises(ValueError):
            arr[...] = 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.name = "x"
    assert isinstance(m.joint_names, tuple) and isinstance(m.link_names, tuple)


@pytest.mark.parametrize("kind, stray", [("revolute", 4), ("prismatic", 1)])
def test_axes_must_pass_through_the_joint_frame_origin(kind, stray):
    """The recursions multiply by a rotor (revolute) or a translator (prismatic), so a
    model whose axis has a moment part, or a direction with a rotation part, is refused."""
    m = load("prismatic_tree")
    j = int(np.flatnonzero(m.joint_types == (REVOLUTE if kind == "revolute" else PRISMATIC))[0])
    axes = m.axes.copy()
    axes[j, stray] = 0.1
    with pytest.raises(ValueError, match=rf"axes\[{j}\] .*{kind}.*through the joint frame"):
        dataclasses.replace(m, axes=axes)


def test_inertias_must_be_rigid():
    """The recursions read a body's inertia from its ten parameters (``kernels.rigid``),
    so a 6x6 that is not a rigid body's is refused, naming the body."""
    m = load("prismatic_tree")
    inertias = m.inertias.copy()
    inertias[1, 3, 3] *= 1.5  # one of the three masses of the linear block
    with pytest.raises(ValueError, match=r"inertias\[1\] .* not a rigid body's inertia"):
        dataclasses.replace(m, inertias=inertias)


def test_unit_axes():
    """A column ±e_i gives i where every column of its joint is one (a free flyer's: its
    unit twists), -1 for every coordinate of a joint with any other column."""
    S = np.array([[0, 0, -1.0, 0, 0, 0], [0, 0, 0, 0, 1.0, 0], [0, 0.6, 0.8, 0, 0, 0],
                  [0, 0, 2.0, 0, 0, 0]] + [list(r) for r in np.eye(6)])
    types = np.array([REVOLUTE, PRISMATIC, REVOLUTE, REVOLUTE, FREE_FLYER])
    assert unit_axes(S, types).tolist() == [2, 4, -1, -1] + list(range(6))
    S[5, 1] = 0.5  # one column of the free flyer no longer a unit twist
    assert unit_axes(S, types).tolist() == [2, 4, -1, -1] + [-1] * 6
    m = load("prismatic_tree")
    k = np.arange(m.nv)
    axes = m.unit_axes
    assert np.all(np.abs(m.motion_subspace[k[axes >= 0], axes[axes >= 0]]) == 1.0)


def test_dtypes_and_shapes():
    m = load("prismatic_tree")
    n, nl = m.nq, len(m.link_names)
    assert m.joint_types.dtype == np.int64 and m.parents.dtype == np.int64
    assert m.link_joint.dtype == np.int64
    assert m.placements.shape == (n, 8) and m.axes.shape == (n, 6)
    assert m.inertias.shape == (n, 6, 6) and m.link_placements.shape == (nl, 8)
    assert m.placements.dtype == np.float64


def test_source_forms_agree(tmp_path):
    path = robot_path("gripper")
    text = path.read_text()
    a, b, c = load_urdf(path), load_urdf(str(path)), load_urdf(text)
    assert a.joint_names == b.joint_names == c.joint_names
    np.testing.assert_array_equal(a.inertias, c.inertias)
    np.testing.assert_array_equal(a.placements, c.placements)
    assert a.name == "gripper" and load_urdf(text, name="other").name == "other"
    assert load(str(path)).joint_names == a.joint_names
    assert load(text).joint_names == a.joint_names


def test_own_robot_features():
    """Our robots cover what they are for."""
    arm, tree, grip = load("skew_arm"), load("prismatic_tree"), load("gripper")
    # joints listed in the file in another order than Pinocchio's
    assert tree.joint_names == ("lift", "left_shoulder", "left_slide", "head_pan",
                                "right_shoulder", "right_slide", "right_wrist")
    assert list(tree.parents) == [-1, 0, 1, 0, 0, 4, 5]
    assert grip.joint_names.index("finger_left") < grip.joint_names.index("finger_right")
    assert "continuous" in arm.joint_kinds and "prismatic" in tree.joint_kinds
    assert grip.mimic[grip.joint_index("finger_left")] == ("finger_right", 1.0, 0.0)
    assert grip.mimic[grip.joint_index("finger_right")] is None
    # a massless link sits between a revolute joint and a massive tip
    assert grip.body_mass[grip.joint_index("thumb_base")] == pytest.approx(0.03)


def test_mimic_joints_are_independent():
    m = load("panda")
    assert m.nq == 9 and m.joint_names[-2:] == ("panda_finger_joint1", "panda_finger_joint2")
    assert m.mimic[-1] is not None and m.mimic[-1][0] == "panda_finger_joint1"


def test_model_helpers():
    m = load("prismatic_tree")
    assert m.children(-1) == (0,)
    assert m.children(0) == (1, 3, 4)
    assert m.subtree(4) == (4, 5, 6)
    assert m.joint_index("head_pan") == 3
    with pytest.raises(ValueError, match="head_pan"):
        m.joint_index("nope")
    with pytest.raises(ValueError, match="torso"):
        m.link_index("nope")
    assert "prismatic_tree" in repr(m)


# --- errors -------------------------------------------------------------------------------

INERTIAL = ('<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" '
            'ixz="0" iyz="0"/></inertial>')


def urdf(joints, links=("a", "b", "c")):
    body = "".join(f'<link name="{lk}">{INERTIAL}</link>' for lk in links)
    return f'<robot name="t">{body}{joints}</robot>'


def joint(name, parent, child, kind="revolute", axis="0 0 1", limit=True):
    lim = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if limit else ""
    ax = f'<axis xyz="{axis}"/>' if axis is not None else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/>{ax}{lim}</joint>')


CHAIN = joint("j1", "a", "b") + joint("j2", "b", "c")


def test_valid_minimal_urdf():
    m = load_urdf(urdf(CHAIN))
    assert m.joint_names == ("j1", "j2") and m.root_link == "a"


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothere.urdf"):
        load_urdf(tmp_path / "nothere.urdf")
    with pytest.raises(FileNotFoundError):
        load_urdf(str(tmp_path / "nothere.urdf"))


def test_malformed_xml():
    with pytest.raises(ValueError, match="malformed XML"):
        load_urdf('<robot name="t"><link name="a"></robot>')


def test_not_a_robot():
    with pytest.raises(ValueError, match="<robot>"):
        load_urdf('<sdf version="1.6"><model name="x"/></sdf>')


@pytest.mark.parametrize("kind", ["floating", "planar"])
def test_unsupported_joint_type(kind):
    text = urdf(joint("base_free", "a", "b", kind=kind, limit=False) + joint("j2", "b", "c"))
    with pytest.raises(ValueError, match="base_free") as err:
        load_urdf(text)
    msg = str(err.value)
    assert kind in msg and "fixed to the world" in msg and "prismatic" in msg


def test_unknown_joint_type():
    with pytest.raises(ValueError, match="spherical"):
        load_urdf(urdf(joint("j1", "a", "b", kind="spherical") + joint("j2", "b", "c")))


def test_closed_loop():
    text = urdf(CHAIN + joint("j3", "a", "c"))
    with pytest.raises(ValueError, match="closed loop") as err:
        load_urdf(text)
    assert "'c'" in str(err.value)


def test_detached_cycle():
    text = urdf(joint("j1", "a", "b") + joint("j2", "c", "d") + joint("j3", "d", "c"),
                links=("a", "b", "c", "d"))
    with pytest.raises(ValueError, match="closed loop") as err:
        load_urdf(text)
    assert "'c'" in str(err.value) and "'d'" in str(err.value)


def test_multiple_roots():
    text = urdf(joint("j1", "a", "b"), links=("a", "b", "c"))
    with pytest.raises(ValueError, match="several root links") as err:
        load_urdf(text)
    assert "'a'" in str(err.value) and "'c'" in str(err.value)


def test_zero_axis():
    with pytest.raises(ValueError, match="j2.*axis"):
        load_urdf(urdf(joint("j1", "a", "b") + joint("j2", "b", "c", axis="0 0 0")))


def test_missing_limit():
    with pytest.raises(ValueError, match="j1.*<limit>"):
        load_urdf(urdf(joint("j1", "a", "b", limit=False) + joint("j2", "b", "c")))


def test_undefined_link():
    with pytest.raises(ValueError, match="'zz'.*not defined"):
        load_urdf(urdf(joint("j1", "a", "b") + joint("j2", "b", "zz")))


def test_duplicate_link():
    with pytest.raises(ValueError, match="'b' is defined twice"):
        load_urdf(urdf(CHAIN, links=("a", "b", "b", "c")))


def test_non_physical_inertia():
    bad = ('<link name="c"><inertial><mass value="1"/><inertia ixx="1" iyy="0.1" izz="0.11" '
           'ixy="0" ixz="0" iyz="0"/></inertial></link>')
    text = urdf(CHAIN, links=("a", "b")).replace("</robot>", bad + "</robot>")
    # ixx > iyy + izz violates the triangle inequality but is still PSD: Pinocchio loads it
    assert load_urdf(text).nq == 2
    text = text.replace('izz="0.11" ixy="0"', 'izz="0.11" ixy="5"')
    with pytest.raises(ValueError, match="'c'.*positive semi-definite"):
        load_urdf(text)


def test_continuous_and_defaults():
    text = urdf(joint("j1", "a", "b", kind="continuous", limit=False, axis=None)
                + joint("j2", "b", "c", kind="prismatic", axis="0 -2 0"))
    m = load_urdf(text)
    assert m.joint_kinds == ("continuous", "prismatic")
    np.testing.assert_array_equal(m.axis_vectors, [[1, 0, 0], [0, -1, 0]])
    assert m.lower[0] == -np.inf and m.upper[0] == np.inf
    assert m.velocity_limit[0] == np.inf and m.effort_limit[0] == np.inf


def test_robot_without_joints():
    m = load_urdf(f'<robot name="solo"><link name="a">{INERTIAL}</link></robot>')
    assert m.nq == 0 and m.link_names == ("a",) and isinstance(m, Model)


def test_every_example_robot_data_urdf_loads_like_pinocchio():
    """Not only the registry: every URDF that ships (legged, humanoid ...) orders like
    Pinocchio, or is refused with a ValueError for a reason Pinocchio lets pass."""
    from cgadyn.multibody.registry import example_robot_data_dir

    root = example_robot_data_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    refused = []
    for path in sorted(glob.glob(str(root / "**" / "*.urdf"), recursive=True)):
        try:
            pm = pin.buildModelFromXML(Path(path).read_text())
        except Exception:
            continue
        try:
            m = load_urdf(path)
        except ValueError as exc:
            refused.append((Path(path).name, str(exc)))
            continue
        assert m.joint_names == tuple(pm.names[1:]), path
        np.testing.assert_array_equal(m.parents, np.array(pm.parents[1:]) - 1)
    # romeo_laas_small has links with indefinite rotational inertias
    assert all("positive semi-definite" in msg for _, msg in refused), refused


# --- random trees: the joint-order rule ---------------------------------------------------


@st.composite
def random_tree(draw):
    n = draw(st.integers(1, 9))
    names = draw(st.lists(st.text("abcAB_0", min_size=1, max_size=4), min_size=n,
                          max_size=n, unique=True))
    parts = []
    for i in range(n):
        parent = draw(st.integers(0, i))  # link index (link 0 is the root)
        kind = draw(st.sampled_from(["revolute", "continuous", "prismatic", "fixed"]))
        axis = draw(st.lists(st.integers(-2, 2), min_size=3, max_size=3).filter(any))
        xyz = draw(st.lists(st.floats(-1, 1), min_size=3, max_size=3))
        rpy = draw(st.lists(st.floats(-3, 3), min_size=3, max_size=3))
        parts.append(
            f'<joint name="J{names[i]}" type="{kind}"><parent link="L{parent}"/>'
            f'<child link="L{i + 1}"/><origin xyz="{" ".join(map(str, xyz))}" '
            f'rpy="{" ".join(map(str, rpy))}"/><axis xyz="{" ".join(map(str, axis))}"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')
    order = draw(st.permutations(parts))
    links = "".join(f'<link name="L{i}">{INERTIAL}</link>' for i in range(n + 1))
    return f'<robot name="r">{links}{"".join(order)}</robot>'


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_tree())
def test_random_trees_match_pinocchio(text):
    m, pm = load_urdf(text), pin.buildModelFromXML(text)
    assert m.joint_names == tuple(pm.names[1:])
    np.testing.assert_array_equal(m.parents, np.array(pm.parents[1:]) - 1)
    for j in range(m.nq):
        assert close(m.placement_matrices[j], pm.jointPlacements[j + 1].homogeneous)
        assert close(inertia_to_pinocchio(m.inertias[j]), pm.inertias[j + 1].matrix())


@pytest.mark.parametrize("element, expected", [
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
     '<origin xyz="0 nan 0"/><axis xyz="0 0 1"/>'
     '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>',
     r"joint 'j1': <origin xyz='0 nan 0'> is not 3 finite numbers"),
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
     '<axis xyz="1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>',
     r"joint 'j1': <axis xyz='1 0'> is not 3 finite numbers, not all zero"),
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
     '<axis xyz="a b c"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>',
     r"joint 'j1': <axis xyz='a b c'>"),
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
     '<axis xyz="0 0 1"/><limit lower="x" upper="1" effort="1" velocity="1"/></joint>',
     r"joint 'j1': <limit lower='x'> is not a finite number"),
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="c"/>'
     '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
     '<link name="c"><inertial><origin rpy="0 inf 0"/><mass value="1"/></inertial></link>',
     r"link 'c': <inertial/origin rpy='0 inf 0'> is not 3 finite numbers"),
    ('<joint name="j1" type="revolute"><parent link="a"/><child link="c"/>'
     '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
     '<link name="c"><inertial><mass value="-2"/></inertial></link>',
     r"link 'c': <inertial/mass value='-2'> is not a finite number >= 0"),
])
def test_bad_numbers_name_their_element(element, expected):
    links = '<link name="a"/>' + ('' if 'link name="c"' in element else '<link name="b"/>')
    with pytest.raises(ValueError, match=expected):
        load_urdf(f'<robot name="r">{links}{element}</robot>')
