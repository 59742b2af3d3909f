"""Fingerprints of the package's own code, for caches that must never outlive it.

numba's disk cache keys compiled code on the modification time of the function's own file,
not on the files of the kernels it inlines or calls; the model cache keys models on the code
that built them. The model cache uses ``fingerprint()``: the version and the bytes of every
``.py`` file of the installed package (generated kernels included). numba's cache uses
``closure_fingerprints()``: for each file that holds compiled code, a digest of the version
and of every package file it imports, directly or through others (its dependency closure;
imports inside functions count). Editing ``algorithms/aba.py`` therefore changes the
fingerprint of ``aba.py`` and of the files that import it, never that of ``rnea.py``: the
machine code of rnea stays cached. Each is computed once per process.
"""

from __future__ import annotations

import hashlib
import re
from functools import cache
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


_COMPILED = (b"_jit import", b"njit", b"cfunc")
"""What marks a file that holds compiled code."""

_IMPORT = re.compile(
    rb"^[ \t]*(?:from[ \t]+(\.*[\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)"
    rb"|import[ \t]+([^\n]*))", re.M)
"""``from X import names`` (names possibly in parentheses over several lines) and
``import X``, at any indentation: a line of a docstring that reads like an import only makes
the closure larger, never smaller."""


OUTSIDE_MACHINE_CODE = ("_sources.py", "_progress.py")
"""Files that compiled code imports but that put nothing into machine code: how caches are
keyed, and what is said while compiling."""


def _holds_compiled_code(path: Path) -> bool:
    return path.name == "_jit.py" or any(m in path.read_bytes() for m in _COMPILED)


@cache
def _files() -> tuple[Path, ...]:
    return tuple(sorted(PACKAGE.rglob("*.py")))


@cache
def compiled_sources() -> tuple[Path, ...]:
    """The package's files that hold compiled code, in order."""
    return tuple(p for p in _files() if _holds_compiled_code(p))


@cache
def _modules() -> dict[tuple[str, ...], Path]:
    """Each package module's dotted name (relative to the package, as parts) and file."""
    found = {}
    for path in _files():
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        found[parts[:-1] if parts[-1] == "__init__" else parts] = path
    return found


def _module_file(dotted: list[str]) -> Path | None:
    """The file of the package module ``dotted`` (relative to the package), if any."""
    return _modules().get(tuple(dotted))


def _names(text: bytes) -> list[str]:
    text = text.strip(b"()").replace(b"\\\n", b" ")
    return [n.split()[0].decode() for n in re.split(rb"[,\n]", text)
            if n.split() and not n.strip().startswith(b"#")]


def _imports(path: Path) -> set[Path]:
    """The package files that ``path`` imports (one step)."""
    here = list(path.relative_to(PACKAGE).parent.parts)
    found: set[Path] = set()
    for frm, names, plain in _IMPORT.findall(path.read_bytes()):
        if plain:
            for name in _names(plain):
                parts = name.split(".")
                if parts[0] == PACKAGE.name and (f := _module_file(parts[1:])):
                    found.add(f)
            continue
        module = frm.decode()
        level = len(module) - len(module.lstrip("."))
        rest = [p for p in module.lstrip(".").split(".") if p]
        if level:
            base = here[:len(here) - level + 1] + rest
        elif rest and rest[0] == PACKAGE.name:
            base = rest[1:]
        else:
            continue
        for name in _names(names):
            target = _module_file(base + [name]) or _module_file(base)
            if target:
                found.add(target)
    found.discard(PACKAGE / "__init__.py")  # re-exports and the version, hashed anyway
    return found - {PACKAGE / name for name in OUTSIDE_MACHINE_CODE}


@cache
def _graph() -> dict[Path, set[Path]]:
    return {path: _imports(path) for path in _files()}


def closure(path: Path) -> tuple[Path, ...]:
    """``path`` and every package file it imports, directly or through others, in order."""
    graph, seen, todo = _graph(), set(), [path]
    while todo:
        p = todo.pop()
        if p not in seen:
            seen.add(p)
            todo.extend(graph.get(p, ()))
    return tuple(sorted(seen))


@cache
def _file_digest(path: Path) -> bytes:
    return hashlib.sha256(path.read_bytes()).digest()


def _digest(paths) -> str:
    from . import __version__

    h = hashlib.sha256(__version__.encode())
    for path in paths:
        h.update(str(path.relative_to(PACKAGE)).encode())
        h.update(_file_digest(path))
    return h.hexdigest()


@cache
def fingerprint() -> str:
    """A hex digest of the package's version and all its sources."""
    return _digest(_files())


@cache
def closure_fingerprints() -> dict[Path, str]:
    """For each file that holds compiled code, a hex digest of the version and of its
    dependency closure (``closure``)."""
    return {path: _digest(closure(path)) for path in compiled_sources()}
