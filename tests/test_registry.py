"""The robot registry: names, caching, paths and text, and that every robot is usable."""

from __future__ import annotations

import numpy as np
import pytest

from cgadyn.multibody import load, robot_path, robots
from cgadyn.multibody.registry import (
    DEFAULT_ROBOT,
    EXAMPLE_ROBOT_DATA,
    OWN_ROBOTS_DIR,
    example_robot_data_dir,
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
    missing = [n for n, rel in EXAMPLE_ROBOT_DATA.items() if not (root / rel).is_file()]
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


@pytest.mark.parametrize("name", robots())
def test_every_robot_is_well_posed(name):
    """Each movable subtree has mass (so ABA is not singular) and each body's inertia is
    physical: positive semi-definite, principal moments obeying the triangle inequality."""
    m = load(name)
    assert m.nq > 0
    for j in range(m.nq):
        assert m.body_mass[j] >= 0
        assert sum(m.body_mass[i] for i in m.subtree(j)) > 0, m.joint_names[j]
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
