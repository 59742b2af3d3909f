"""The robot registry: names, caching, paths and text, and that every robot is usable."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn.multibody import load, robot_path, robots
from cgadyn.multibody.registry import (
    DEFAULT_ROBOT,
    EXAMPLE_ROBOT_DATA,
    FREE,
    OWN_ROBOTS_DIR,
    example_robot_data_dir,
    natural_base,
    refused,
    resolve,
)

OWN = sorted(p.stem for p in OWN_ROBOTS_DIR.glob("*.urdf"))


def test_names():
    names = robots()
    assert names == sorted(names)
    for name in ("panda", "ur5", "double_pendulum", *OWN):
        assert name in names
    assert DEFAULT_ROBOT == "panda"
    assert {"skew_arm", "prismatic_tree", "gripper"} <= set(OWN)


def test_example_robot_data_found_and_complete():
    root = example_robot_data_dir()
    assert root is not None and (root / "panda_description").is_dir()
    missing = [n for n, (rel, _) in EXAMPLE_ROBOT_DATA.items() if not (root / rel).is_file()]
    assert missing == []
    assert set(EXAMPLE_ROBOT_DATA) <= set(robots())


def test_unknown_name_lists_the_known_ones():
    with pytest.raises(ValueError, match="unknown robot 'nonexistent_bot'") as err:
        load("nonexistent_bot")
    msg = str(err.value)
    assert "panda" in msg and "ur5" in msg and "skew_arm" in msg
    with pytest.raises(ValueError, match="panda"):
        robot_path("nonexistent_bot")


def test_cached_and_default():
    assert load("panda") is load("panda")
    assert load() is load("panda")
    m = load("panda")
    assert m.nq == 9 and m.name == "panda"
    assert m.joint_kinds[-2:] == ("prismatic", "prismatic")
    assert m.parents[-1] == m.parents[-2] == 6  # the two fingers branch off the hand


def test_path_and_text():
    path = robot_path("ur5")
    assert load(path).joint_names == load("ur5").joint_names
    assert load(str(path)).joint_names == load("ur5").joint_names
    assert load(path.read_text()).joint_names == load("ur5").joint_names
    with pytest.raises(FileNotFoundError):
        load("/no/such/robot.urdf")


def test_model_passes_through():
    m = load("cart_pole")
    assert load(m) is m


def test_natural_base_and_override():
    """Legged, humanoid and flying robots float (a free-flyer root first, called
    root_joint, in Pinocchio's layout); arms, hands, paths and text stand fixed."""
    for name in ("talos", "solo12", "anymal", "a1", "icub", "iris"):
        m = load(name)
        assert natural_base(name) == FREE and m.floating_base, name
        assert m.joint_names[0] == "root_joint" and m.joint_kinds[0] == "free_flyer"
        assert m.nq == m.nv + 1
    talos = load("talos")
    assert (talos.nq, talos.nv) == (39, 38) and load("talos_reduced") is talos
    assert not load("panda").floating_base and not load(robot_path("solo12")).floating_base
    assert load("panda", floating_base=True).nv == 15
    assert not load("solo12", floating_base=False).floating_base
    assert load(robot_path("ur5"), floating_base=True).nq == 13


def test_refused_robots_say_why():
    """romeo_laas_small has a non-physical inertia: refused by default, naming the link,
    and loaded as Pinocchio does with check_inertia=False; cassie is SDF with loops."""
    why = refused()
    assert "closed kinematic loops" in why["cassie"] and "cassie" not in robots()
    assert "romeo_laas_small" in why
    with pytest.raises(ValueError, match="link 'body'.*not positive semi-definite"):
        load("romeo_laas_small")
    assert load("romeo_laas_small", check_inertia=False).floating_base


def test_resolve_one_rule(tmp_path):
    """A name, an existing file of any extension, URDF text; a missing file says so."""
    assert resolve("panda")[0] == "name"
    other = tmp_path / "arm.xml"
    other.write_text(robot_path("ur5").read_text())
    assert resolve(str(other))[0] == "path" and load(str(other)).nv == 6
    assert resolve(other.read_text())[0] == "text"
    for missing in ("missing.urdf", "dir/missing", str(tmp_path / "x.xml")):
        with pytest.raises(FileNotFoundError, match="file not found"):
            resolve(missing)
    with pytest.raises(ValueError, match="a robot is a name"):
        resolve(3.0)


MASSLESS_HANDS = [f"{side}{finger}" for side in "LR" for finger in (
    "Finger21", "Finger22", "Finger23", "Finger31", "Finger32", "Finger33", "Hand", "Finger12",
    "Finger13", "Thumb1", "Thumb2", "Thumb3")]


def test_massless_subtree_is_explained():
    m = load("romeo")
    with pytest.raises(ValueError, match="joint 'RThumb3': the subtree it moves has no mass"):
        cgadyn.aba(m, cgadyn.neutral(m), np.zeros(m.nv), np.zeros(m.nv))
    assert np.isfinite(cgadyn.rnea(m, cgadyn.neutral(m), np.zeros(m.nv), np.zeros(m.nv))).all()


@pytest.mark.parametrize("name", [n for n in robots() if n not in refused()])
def test_every_robot_is_well_posed(name):
    """Each movable subtree has mass (so ABA is not singular) and each body's inertia is
    physical: positive semi-definite, principal moments obeying the triangle inequality."""
    m = load(name)
    assert m.nv > 0
    massless = [m.joint_names[j] for j in range(m.njoints)
                if sum(m.body_mass[i] for i in m.subtree(j)) <= 0]
    # romeo's hands are massless in example-robot-data: M(q) is singular there, for
    # Pinocchio as for us; rnea and crba work, forward dynamics says why it cannot
    assert massless == (MASSLESS_HANDS if name == "romeo" else [])
    for j in range(m.njoints):
        assert m.body_mass[j] >= 0
        ev = np.linalg.eigvalsh(m.body_rotational_inertia[j])
        assert ev.min() >= -1e-12, m.joint_names[j]


@pytest.mark.parametrize("name", OWN)
def test_own_robots_are_realistic(name):
    m = load(name)
    for j in range(m.nq):
        ev = np.linalg.eigvalsh(m.body_rotational_inertia[j])
        assert ev.min() > 0, m.joint_names[j]
        assert ev[0] + ev[1] >= ev[2] * (1 - 1e-9), m.joint_names[j]
        assert 0.01 <= m.body_mass[j] <= 20
    assert np.all(m.lower[m.joint_types == 1] < m.upper[m.joint_types == 1])
    assert np.all(np.isfinite(m.velocity_limit[[k != "continuous" for k in m.joint_kinds]]))


def test_own_robots_cover_the_cases():
    """Between them: prismatic, continuous, skew and unnormalised axes, +y and -y axes,
    fixed joints mid-chain with rotations, rotated inertial frames, massless links,
    branching trees."""
    import xml.etree.ElementTree as ET

    kinds, axes, fixed_rot, inertial_rot, massless = set(), [], 0, 0, 0
    for name in OWN:
        root = ET.parse(robot_path(name)).getroot()
        for j in root.findall("joint"):
            kinds.add(j.get("type"))
            if j.get("type") != "fixed":
                ax = j.find("axis")
                axes.append(np.fromstring(ax.get("xyz") if ax is not None else "1 0 0", sep=" "))
            elif np.any(np.fromstring(j.find("origin").get("rpy", "0 0 0"), sep=" ")):
                fixed_rot += 1
        for lk in root.findall("link"):
            el = lk.find("inertial")
            if el is None:
                massless += 1
            elif np.any(np.fromstring(el.find("origin").get("rpy", "0 0 0"), sep=" ")):
                inertial_rot += 1
    assert {"revolute", "continuous", "prismatic", "fixed"} <= kinds
    norms = [np.linalg.norm(a) for a in axes]
    assert any(abs(n - 1) > 0.1 for n in norms)  # unnormalised
    assert any(np.count_nonzero(a) > 1 for a in axes)  # skew
    assert any(a[1] > 0 and np.count_nonzero(a) == 1 for a in axes)  # +y
    assert any(a[1] < 0 and np.count_nonzero(a) == 1 for a in axes)  # -y
    assert fixed_rot >= 2 and inertial_rot >= 3 and massless >= 2
    branching = [n for n in OWN if len(set(load(n).parents)) < load(n).nq]
    assert len(branching) >= 2


def test_mujoco_suites_load_by_name():
    """Gymnasium's and dm_control's MJCF models (copies shipped in robots/mujoco/) load as
    ``<suite>:<model>``, through MuJoCo's compiler, named so, with their own base."""
    from cgadyn.multibody import registry

    names = robots()
    for name in ("gymnasium:ant", "gymnasium:humanoid", "dm_control:cheetah"):
        assert name in names and registry.source(name) == name.split(":")[0]
    ant = load("gymnasium:ant")
    assert (ant.name, ant.floating_base, ant.nv, len(ant.actuator_names)) == \
        ("gymnasium:ant", True, 14, 8)
    assert not load("dm_control:cheetah").floating_base
    with pytest.raises(ValueError, match="unknown robot 'gymnasium:nope'"):
        load("gymnasium:nope")
