"""The joint interface holds: only the joint module (and the converters) knows joint types.

``multibody/joints/`` states every fact that depends on a joint's type (``docs/joints.md``);
everything else asks it. The first test reads the source of the package and fails where a
module outside the joint module and the converters names a joint type's constant, branches
on a joint's type or kind, or compares nq with nv (a spherical joint, nq 4 and nv 3, would
pass such a test for a free flyer). The others check each type's record against itself and
MuJoCo's layout against MuJoCo.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import cgadyn
from cgadyn.multibody.joints import TYPES, table

PACKAGE = Path(cgadyn.__file__).parent
JOINT_MODULE = PACKAGE / "multibody" / "joints"
CONVERTERS = {PACKAGE / "multibody" / name for name in ("urdf.py", "mjcf.py",
                                                        "pinocchio_model.py",
                                                        "mujoco_model.py")} | {
    PACKAGE / "oracle.py"}
"""The files that translate other libraries' joints, and so may name types."""
AXIS_KINDS = {PACKAGE / "cga" / "conventions.py"}
"""``twist_from_axis`` takes an axis kind (a line or a direction) and accepts URDF's names
for them: it may compare strings that are joint kinds, but names no type constant."""

CONSTANTS = {r.name.upper() for r in TYPES}
"""The type constants (``REVOLUTE``, ``FREE_FLYER``, ...)."""
KIND_STRINGS = ({r.kind for r in TYPES} | {r.name for r in TYPES}) - {r.axis for r in TYPES}
"""Joint kinds and type names, but for the axis kinds (``"revolute"``: a line,
``"prismatic"``: a direction) that a record's ``axis`` holds and ``twist_from_axis`` takes."""
TYPE_FIELDS = {"joint_types", "joint_kinds", "types"}
"""Where a model (or its compiled view) holds each joint's type or kind."""


def _names(node: ast.AST) -> set[str]:
    """The names and attributes an expression reads."""
    out = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Name):
            out.add(n.id)
        elif isinstance(n, ast.Attribute):
            out.add(n.attr)
    return out


def _faults(path: Path, root: Path = PACKAGE) -> list[str]:
    """What ``path`` (a file under ``root``) knows of joint types that it should not."""
    tree = ast.parse(path.read_text(), str(path))
    faults = []
    for node in ast.walk(tree):
        where = f"{path.relative_to(root)}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.Name) and node.id in CONSTANTS or \
                isinstance(node, ast.Attribute) and node.attr in CONSTANTS:
            faults.append(f"{where} names a joint type constant")
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left, *node.comparators]
        names = [_names(s) for s in sides]
        if any("nq" in a and "nv" in b for a in names for b in names if a is not b):
            faults.append(f"{where} compares nq with nv")
        if any(a & TYPE_FIELDS for a in names):
            faults.append(f"{where} branches on a joint's type or kind")
        strings = {n.value for s in sides for n in ast.walk(s)
                   if isinstance(n, ast.Constant) and isinstance(n.value, str)}
        if strings & KIND_STRINGS and path not in AXIS_KINDS:
            faults.append(f"{where} compares with a joint kind {sorted(strings & KIND_STRINGS)}")
    return faults


def test_only_the_joint_module_and_the_converters_know_joint_types():
    outside = [p for p in sorted(PACKAGE.rglob("*.py"))
               if JOINT_MODULE not in p.parents and p not in CONVERTERS]
    assert len(outside) > 50  # the walk sees the package
    faults = [f for p in outside for f in _faults(p)]
    assert not faults, "joint-type knowledge outside multibody/joints/:\n" + "\n".join(faults)


def test_the_walk_catches_what_it_forbids(tmp_path):
    """Each rule fires on the code it was written against (as it stood before the joint
    interface): a test of the test."""
    bad = tmp_path / "bad.py"
    bad.write_text("def f(m, model, j, kind):\n"
                   "    a = m.nq != m.nv\n"
                   "    b = m.types[j] != FREE_FLYER\n"
                   "    c = model.joint_kinds[j] == 'free_flyer'\n"
                   "    d = kind == 'continuous'\n")
    faults = _faults(bad, tmp_path)
    assert len([f for f in faults if "nq with nv" in f]) == 1
    assert len([f for f in faults if "constant" in f]) == 1
    assert len([f for f in faults if "type or kind" in f]) == 2
    assert len([f for f in faults if "joint kind [" in f]) == 2


@pytest.mark.parametrize("record", TYPES, ids=lambda r: r.name)
def test_each_record_is_consistent(record):
    rng = np.random.default_rng(0)
    assert TYPES[record.code] is record
    B = np.zeros(6) if record.axis is None else np.array([0.0, 0.0, 0.0, 0.0, 0.0, -1.0])
    assert record.subspace(B).shape == (record.nv, 6)
    assert len(record.neutral) == record.nq and len(record.speeds) == record.nv
    lower, upper = record.limits(np.full(record.nq, -2.0), np.full(record.nq, 2.0))
    assert lower.shape == upper.shape == (record.nq,) and np.all(lower <= upper)
    q = rng.uniform(np.maximum(lower, -np.pi), np.minimum(upper, np.pi))
    if record.random is not None:
        record.random(rng, q, 1.0)
    if record.quaternion >= 0:
        unit = q[record.quaternion:record.quaternion + record.unit_length]
        assert np.linalg.norm(unit) == \
            pytest.approx(1.0, abs=1e-15)
    qp = record.to_pinocchio(q)
    assert qp.shape == (record.pinocchio_nq,)
    np.testing.assert_allclose(record.from_pinocchio(qp), q, atol=1e-15)
    np.testing.assert_array_equal(record.from_mujoco(record.to_mujoco(q)), q)
    v = rng.standard_normal(record.nv)
    np.testing.assert_allclose(
        record.from_mujoco_velocity(q, record.mujoco_velocity(q, v)), v, atol=1e-14)


@pytest.mark.parametrize("robot, flat", [("panda", True), ("solo12", False)])
def test_the_packed_model_says_whether_the_configuration_is_a_vector(robot, flat):
    from cgadyn.multibody.packed import unpack

    model = cgadyn.load(robot)
    assert bool(unpack(model.packed).flat) is flat
    assert table.flat(model.joint_types) is flat
    assert model.floating_base is not flat


def test_mujoco_layout_of_a_free_joint_is_mujocos():
    """``table.to_mujoco`` and ``table.mujoco_velocity`` put a free flyer's state where
    MuJoCo reads it: the body lands where cgadyn places it, and MuJoCo's body velocity
    (in the body's frame) is cgadyn's body twist."""
    mujoco = pytest.importorskip("mujoco")
    text = (PACKAGE.parents[1] / "robots" / "slide_arm.xml").read_text().replace(
        '<body name="stand">', '<body name="stand"><freejoint name="float"/>')
    model = cgadyn.load(text)
    mm = mujoco.MjModel.from_xml_string(text)
    md = mujoco.MjData(mm)
    rng = np.random.default_rng(5)
    q, v = cgadyn.random_configuration(model, rng), rng.standard_normal(model.nv)
    md.qpos[:] = table.to_mujoco(model, q)
    md.qvel[:] = table.mujoco_velocity(model, q, v)
    mujoco.mj_forward(mm, md)
    body = mujoco.mj_name2id(mm, mujoco.mjtObj.mjOBJ_BODY, "stand")
    placement = cgadyn.link_placements(model, q)[model.link_index("stand")]
    np.testing.assert_allclose(md.xpos[body], placement[:3, 3], atol=1e-14)
    np.testing.assert_allclose(md.xmat[body].reshape(3, 3), placement[:3, :3], atol=1e-14)
    twist = np.zeros(6)
    mujoco.mj_objectVelocity(mm, md, mujoco.mjtObj.mjOBJ_BODY, body, twist, 1)
    np.testing.assert_allclose(twist[3:], v[:3], atol=1e-12)  # [ω, v] local, against [v, ω]
    np.testing.assert_allclose(twist[:3], v[3:6], atol=1e-12)
    np.testing.assert_array_equal(table.from_mujoco(model, md.qpos), q)
