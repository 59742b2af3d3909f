"""The named workspaces: each declared once (``WORKSPACE``), carved, sized and twinned for
lanes by the generated ``work/`` modules, and never read by position."""

from __future__ import annotations

import ast
import importlib
import importlib.util
import sys
from collections import namedtuple
from pathlib import Path

import numba
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "cgadyn"
Sizes = namedtuple("Sizes", "n nq nv nl")


def _generator():
    spec = importlib.util.spec_from_file_location("generate_workspaces",
                                                  ROOT / "tools" / "generate_workspaces.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


GENERATOR = _generator()
DECLARED = GENERATOR.declarations()


def _module_name(path: Path) -> str:
    return ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)


def _work_module(source: Path):
    return importlib.import_module(_module_name(source.parent / "work" / source.name))


def test_generated_workspaces_are_fresh():
    for path, text in GENERATOR.generate().items():
        assert path.read_text() == text, f"{path} stale: run python tools/generate_workspaces.py"


def test_every_core_module_declares_its_workspace():
    """The modules that carve a workspace for a core all declare it: the algorithms with a
    core, the rollouts and the task stacks."""
    names = {p.relative_to(PACKAGE).as_posix() for p in DECLARED}
    for expected in ("algorithms/rnea.py", "algorithms/aba.py", "algorithms/crba.py",
                     "algorithms/minverse.py", "algorithms/minverse_lanes.py",
                     "algorithms/rnea_derivatives.py", "algorithms/rnea_derivatives_lanes.py",
                     "algorithms/aba_derivatives.py", "algorithms/aba_derivatives_lanes.py",
                     "algorithms/kinematics.py", "algorithms/jacobian.py",
                     "algorithms/centroidal.py", "algorithms/energy.py",
                     "algorithms/manifold.py", "sim/rollout.py", "tasks/_stack.py",
                     "tasks/_solve.py"):
        assert expected in names


def _extra(module) -> tuple[int, ...]:
    """Values for a workspace's own size arguments (after the model's four)."""
    count = module.workspace_size.py_func.__code__.co_argcount - 4
    return tuple(range(3, 3 + count))


@pytest.mark.parametrize("source", sorted(DECLARED), ids=lambda p: p.stem)
def test_carving_matches_the_declaration_and_the_size(source):
    """In pure Python (``carve`` slices a numpy buffer there): the arrays lie one after
    another in the declared order with the declared shapes, and end at ``workspace_size``."""
    module = _work_module(source)
    for sizes in (Sizes(3, 3, 3, 5), Sizes(5, 11, 10, 7)):
        extra = _extra(module)
        size = module.workspace_size.py_func(*sizes, *extra)
        buf = np.zeros(size)
        work = module.workspace.py_func(buf, sizes, *extra)
        assert list(work._fields) == list(DECLARED[source])
        o = 0
        for name, array in zip(work._fields, work, strict=True):
            if array.size:
                assert array.__array_interface__["data"][0] == buf[o:].ctypes.data, name
            assert array.ndim == len(DECLARED[source][name]), name
            o += array.size
        assert o == size


@pytest.mark.parametrize("source", sorted(DECLARED), ids=lambda p: p.stem)
def test_the_lane_twin_has_the_scalar_offsets(source):
    """``lane_workspace`` views each array at the offset the scalar carving gives it, so a
    scalar pass indexes the group's workspace exactly as its own."""
    module = _work_module(source)
    fields = list(DECLARED[source])
    extra = _extra(module)
    args = ", ".join(f"a{i}" for i in range(len(extra)))
    code = (f"def offsets(buf, m{', ' if extra else ''}{args}):\n"
            f"    k = lane_workspace(buf, m{', ' if extra else ''}{args})\n"
            f"    return ({', '.join(f'k.{x}.offset' for x in fields)},)\n")
    scope = {"lane_workspace": module.lane_workspace}
    exec(code, scope)  # noqa: S102 (a test's own compiled probe)
    offsets = numba.njit(scope["offsets"])
    sizes = Sizes(5, 11, 10, 7)
    size = module.workspace_size.py_func(*sizes, *extra)
    got = offsets(np.zeros(8 * size), sizes, *extra)
    work = module.workspace.py_func(np.zeros(size), sizes, *extra)
    expected, o = [], 0
    for array in work:
        expected.append(o)
        o += array.size
    assert list(got) == expected


_POSITIONAL = {"k_", "k0", "kl", "sc", "sw", "cw", "wk", "work"}


def test_no_workspace_is_read_by_position():
    """No module unpacks a workspace from a call by position or indexes one with a
    number: every array is read by its declared name."""
    bad = []
    for path in PACKAGE.rglob("*.py"):
        if "work" in path.relative_to(PACKAGE).parts[:-1]:
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if (isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name)
                    and node.value.id in _POSITIONAL
                    and isinstance(node.slice, (ast.Constant, ast.UnaryOp))):
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno} {ast.unparse(node)}")
            if (isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Tuple)
                    and isinstance(node.value, ast.Name) and node.value.id in _POSITIONAL):
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno} {ast.unparse(node)}")
            if isinstance(node, ast.FunctionDef) and node.name == "_workspace":
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno} a hand-carved workspace")
    assert not bad, "\n".join(bad)


_ALLOCATIONS = {"empty", "zeros", "ones", "full", "empty_like", "zeros_like", "copy"}


def _root(node: ast.expr) -> ast.expr:
    while isinstance(node, (ast.Attribute, ast.Subscript)):
        node = node.value
    return node


def test_bare_views_are_carved_from_arguments():
    """A bare view (``data_pointer``, ``_views.carve``) owns no reference, and compiled code
    frees a local array after its last use, not at the end of its scope: a workspace
    allocated in a function and carved there is freed before its views are used. So every
    ``data_pointer`` reads an argument of its function (or a view carved from one), never
    an array the same function allocates."""
    bad = []
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for fn in ast.walk(tree):
            if not isinstance(fn, ast.FunctionDef):
                continue
            allocated = {
                target.id for node in ast.walk(fn) if isinstance(node, ast.Assign)
                and isinstance(node.value, ast.Call)
                and isinstance(node.value.func, ast.Attribute)
                and node.value.func.attr in _ALLOCATIONS
                for target in node.targets if isinstance(target, ast.Name)}
            for node in ast.walk(fn):
                if (isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute))
                        and (getattr(node.func, "id", None) or node.func.attr) == "data_pointer"
                        and node.args):
                    root = _root(node.args[0])
                    if isinstance(root, ast.Call) or (isinstance(root, ast.Name)
                                                      and root.id in allocated):
                        bad.append(f"{path.relative_to(ROOT)}:{node.lineno} {ast.unparse(node)}")
    assert not bad, "\n".join(bad)


def test_a_bad_declaration_is_refused(tmp_path, monkeypatch):
    with pytest.raises(ValueError, match="size argument"):
        GENERATOR.module(PACKAGE / "algorithms" / "rnea.py", {"X": ("N", 6)})
    with pytest.raises(ValueError, match="non-empty tuple"):
        GENERATOR.module(PACKAGE / "algorithms" / "rnea.py", {"X": ()})
    with pytest.raises(ValueError, match="only size"):
        GENERATOR.module(PACKAGE / "algorithms" / "rnea.py", {"X": ("max(n, 2)",)})


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))
