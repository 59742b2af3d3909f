"""Imports point down the layers of ``docs/architecture.md``, and never in a cycle.

Every module of ``src/cgadyn`` is parsed with ``ast``; every import counts, the ones inside
functions (taken on first use) as much as those at the top of a file: an import inside a
function is still a dependency, only a later one. ``LAYERS`` is the one statement of the
order; the diagram of ``docs/architecture.md`` is checked against it.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path

import cgadyn

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "cgadyn"

LAYERS: tuple[tuple[str, ...], ...] = (
    ("_sources", "_json", "_views", "_native", "_progress", "_collector", "_inlining", "_jit",
     "_threads", "_arrays", "_paths"),
    ("algebra",),
    ("kernels",),
    ("cga",),
    ("pga",),
    ("multibody",),
    ("algorithms",),
    ("tasks",),
    ("constraints",),
    ("contact",),
    ("sim",),
    ("distributed",),
    ("oracle", "mujoco_oracle"),
    ("validate", "bench"),
    ("commands",),
    ("cli",),
)
"""The layers from the bottom up, each named by its first component under ``cgadyn`` (a
subpackage or a top-level module). A module may import from its own layer and the layers
below; modules of one layer import each other without a cycle."""

RANK = {group: rank for rank, layer in enumerate(LAYERS) for group in layer}


@dataclass(frozen=True)
class Import:
    source: str  # the importing module, "cgadyn.sim.plot"
    target: str  # the imported module, "cgadyn.commands.common"
    line: int

    def __str__(self) -> str:
        return f"{self.source} imports {self.target} (line {self.line})"


def _modules() -> dict[str, Path]:
    """Dotted name -> file of every Python module of the package (a package by its
    ``__init__.py``)."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _root_definitions() -> set[str]:
    """Names that ``cgadyn/__init__.py`` defines itself (``__version__``, the warning
    class): importing them reaches nothing else."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text(encoding="utf-8"))
    names = set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef | ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


MODULES = _modules()
ROOT_OWN = _root_definitions()
FACADE = max(cgadyn._LAZY.values(), key=lambda module: RANK[module.split(".")[1]])
"""What ``import cgadyn`` stands for: the module of its highest lazy name (the package
reaches every layer its public names come from)."""


def _targets(module: str, node: ast.Import | ast.ImportFrom) -> list[str]:
    """The package modules an import statement of ``module`` reaches (``cgadyn`` alone for
    the names the root defines itself)."""
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
        return [FACADE if n == "cgadyn" else n for n in names if n.split(".")[0] == "cgadyn"]
    if node.level:
        base = module.split(".")
        if MODULES[module].name != "__init__.py":
            base = base[:-1]
        base = base[:len(base) - (node.level - 1)]
        origin = ".".join(base + ([node.module] if node.module else []))
    else:
        origin = node.module or ""
    if origin.split(".")[0] != "cgadyn":
        return []
    out = []
    for alias in node.names:
        full = f"{origin}.{alias.name}"
        if full in MODULES:
            out.append(full)
        elif origin == "cgadyn":
            out.append(cgadyn._LAZY.get(alias.name, "cgadyn" if alias.name in ROOT_OWN
                                        else full))  # full: an extension, cgadyn._native
        else:
            out.append(origin)
    return out


def _imports() -> list[Import]:
    out = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if isinstance(node, ast.Import | ast.ImportFrom):
                out += [Import(module, t, node.lineno) for t in _targets(module, node)
                        if t != module]
    return out


def _group(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "cgadyn"


def upward(imports: list[Import]) -> list[str]:
    """Each import of a module from a layer above its own, or from a module no layer
    names (package ``__init__.py`` files, which re-export their modules, are exempt)."""
    bad = []
    for imp in imports:
        if MODULES[imp.source].name == "__init__.py" or imp.target == "cgadyn":
            continue
        src, dst = _group(imp.source), _group(imp.target)
        if src not in RANK or dst not in RANK:
            bad.append(f"{imp}: {(src if src not in RANK else dst)!r} is in no layer of "
                       f"tests/test_layers.py LAYERS")
        elif RANK[dst] > RANK[src]:
            bad.append(f"{imp}: {dst} is a layer above {src}")
    return bad


def cycles(imports: list[Import]) -> list[str]:
    """Each set of modules that import each other, directly or through others, with the
    imports that close it (Tarjan's strongly connected components)."""
    graph: dict[str, list[Import]] = {m: [] for m in MODULES}
    for imp in imports:
        if imp.target in MODULES and imp.target != "cgadyn":
            graph[imp.source].append(imp)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for imp in graph[v]:
            w = imp.target
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                inner = sorted({str(i) for m in component for i in graph[m]
                                if i.target in component})
                found.append("a cycle: " + "; ".join(inner))

    for v in graph:
        if v not in index:
            visit(v)
    return found


def test_every_import_points_down():
    bad = upward(_imports())
    assert not bad, "imports from a layer above:\n" + "\n".join(bad)


def test_no_import_cycle():
    bad = cycles(_imports())
    assert not bad, "\n".join(bad)


def test_the_checks_catch_an_upward_import_and_a_cycle():
    """The two checks above can fail: an import of the command line from ``sim`` and a pair
    of modules importing each other are both reported, naming modules and lines."""
    fake = [Import("cgadyn.sim.plot", "cgadyn.commands.common", 7),
            Import("cgadyn.algorithms.calls", "cgadyn.distributed", 3),
            Import("cgadyn.distributed", "cgadyn.algorithms.calls", 9)]
    assert upward(fake) == [
        "cgadyn.sim.plot imports cgadyn.commands.common (line 7): commands is a layer "
        "above sim",
        "cgadyn.algorithms.calls imports cgadyn.distributed (line 3): distributed is a "
        "layer above algorithms"]
    assert cycles(fake) == ["a cycle: cgadyn.algorithms.calls imports cgadyn.distributed "
                            "(line 3); cgadyn.distributed imports cgadyn.algorithms.calls "
                            "(line 9)"]


def test_imports_inside_functions_count():
    imports = _imports()
    inside = [i for i in imports if i.source == "cgadyn.distributed"
              and i.target.startswith("cgadyn.sim")]
    assert inside, "distributed imports sim inside its functions; the walk must see it"


def test_the_architecture_diagram_lists_these_layers():
    """The diagram under "## Layers" in docs/architecture.md names the layers top down, one
    line each (its first words, ``name/``, ``name.py`` or ``name.c``), as ``LAYERS`` does
    bottom up."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    diagram = re.search(r"## Layers\n.*?```\n(.*?)```", text, re.S).group(1)
    drawn = []
    for line in diagram.splitlines():
        if line and not line[0].isspace():
            head = re.split(r"\s{2,}", line.strip())[0]
            drawn.append({re.sub(r"(/|\.py|\.c)$", "", w) for w in head.split()})
    assert drawn == [set(layer) for layer in reversed(LAYERS)]
