"""Generate ``src/cgadyn/algorithms/entries/``: the compiled entry points of every algorithm.

Each record of ``src/cgadyn/algorithms/table.py`` gets one module, ``entries/<name>.py``,
with three entry points around its core
``<module>.<name>_core(m, inputs..., [f,] outputs..., options..., work) -> status``:

- ``<name>_single(packed, inputs..., [f,] outputs..., options...)``: one sample, its
  workspace on the call's stack (on the heap above ``STACK_FLOATS``);
- ``<name>_native(pk, x, f, nf, o, options)``: the same from raw pointers, a C function
  (``numba.cfunc``, signature in ``_pointers.py``) that ``cgadyn._native`` calls with the
  arrays' data, sizes read from the packed model's header;
- ``<name>_batch(packed, inputs..., [f,] outputs..., options..., threads)``: (B, ...)
  samples in parallel chunks, one heap workspace per chunk; checks the shapes. A record
  with a ``group`` module hands each chunk to that module's ``<name>_group``.

They differ between algorithms only in names and arities, and numba caches compiled code
per function of a real file, so they are written out here rather than made by a closure
factory (whose functions would share one cache name). One module per algorithm, because
the package's disk cache is invalidated per file and per the files it imports
(``cgadyn._sources``): editing ``aba.py`` recompiles the entries of the algorithms that
use it, not those of rnea.

Usage::

    python tools/generate_entries.py            # rewrite the modules
    python tools/generate_entries.py --check    # exit 1 if a committed module is stale

The table is read by file path, so this script never imports the package it generates for.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TABLE = ROOT / "src" / "cgadyn" / "algorithms" / "table.py"
TARGET = ROOT / "src" / "cgadyn" / "algorithms" / "entries"
MAX_INPUTS, MAX_OUTPUTS, MAX_OPTIONS = 8, 8, 8
"""The bounds of ``cgadyn/_native.c`` (``MAX_IN``, ``MAX_OUT``, ``MAX_OPT``)."""


def load_table():
    spec = importlib.util.spec_from_file_location("cgadyn_algorithm_table", TABLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def size(dim, view: str = "m") -> str:
    """A dimension of the table as code: an int, or a size of the unpacked model."""
    return str(dim) if isinstance(dim, int) else f"{view}.{dim}"


def shape(dims, view: str = "m") -> str:
    return "(" + ", ".join(size(d, view) for d in dims) + ("," if len(dims) == 1 else "") + ")"


def entries(alg) -> str:
    """The three entry points of one algorithm."""
    inputs = [name for name, _ in alg.inputs]
    outputs = [f"o{i}" for i in range(len(alg.outputs))]
    forces = ["f"] if alg.forces else []
    options = list(alg.options)
    args = inputs + forces + outputs + options
    core = alg.core
    ws = "workspace_size(m.n, m.nq, m.nv, m.nl)"
    lines = [
        "", "",
        "@serial",
        f"def {alg.name}_single(packed, {', '.join(args)}):",
        f'    """One sample of ``{alg.core}``; its workspace on this call\'s stack."""',
        "    m = unpack(packed)",
        f"    size = {ws}",
        "    if size <= STACK_FLOATS:",
        f"        return {core}(m, {', '.join(args)}, stack_buffer(size))",
        f"    return {core}(m, {', '.join(args)}, np.empty(size))",
        "", "",
        "@native(SIGNATURE)",
        f"def {alg.name}_native(pk, x, f, nf, o, options):",
        f'    """``{alg.name}_single`` on raw pointers, for ``cgadyn._native``: its body written',
        f"    out, so that a first call compiles ``{alg.core}`` into this C function only, not",
        f'    into ``{alg.name}_single`` as well."""',
        "    m = unpack(packed_array(pk))",
    ]
    local = inputs + (["wrenches"] if alg.forces else []) + outputs + options
    value = [f"carray(x[{i}], {shape((dim,))})" for i, (_, dim) in enumerate(alg.inputs)]
    value += ["carray(f, (nf, 6))"] if alg.forces else []
    value += [f"carray(o[{i}], {shape(dims)})" for i, dims in enumerate(alg.outputs)]
    value += [f"options[{i}]" for i in range(len(options))]
    lines += [f"    {name} = {v}" for name, v in zip(local, value, strict=True)]
    lines += [
        f"    size = {ws}",
        "    if size <= STACK_FLOATS:",
        f"        return {core}(m, {', '.join(local)}, stack_buffer(size))",
        f"    return {core}(m, {', '.join(local)}, np.empty(size))",
    ]
    checks = [f"{x}.shape[1] != m.{dim}" for x, dim in alg.inputs]
    checks += [f"{x}.shape[0] != batch" for x in inputs[1:]]
    checks += [f"{o}.shape[0] != batch" for o in outputs]
    if alg.forces:
        checks += ["(f.shape[0] != 0 and f.shape[0] != batch)", "f.shape[1] != m.n"]
    per_sample = [f"{x}[b]" for x in inputs] + (["fb"] if alg.forces else [])
    per_sample += [f"{o}[b]" for o in outputs] + options
    lines += [
        "", "",
        "@parallel",
        f"def {alg.name}_batch(packed, {', '.join(args)}, threads):",
        f'    """(B, ...) samples of ``{alg.core}`` in parallel chunks; a status."""',
        "    m = unpack(packed)",
        f"    batch = {inputs[0]}.shape[0]",
        "    if (" + "\n            or ".join(checks) + "):",
        "        return WRONG_SHAPE",
        "    size = group_workspace_size(m.n, m.nq, m.nv, m.nl)" if alg.group else
        f"    size = {ws}",
        "    starts, stops = chunks(batch, threads)",
        "    status = np.zeros(starts.shape[0], dtype=np.int64)",
        "    for c in prange(starts.shape[0]):",
        "        mc = unpack(packed)",
        "        work = np.empty(size)",
    ]
    if alg.group:
        lines += [
            f"        s = {alg.name}_group(mc, {', '.join(args)}, starts[c], stops[c], work)",
            "        if s != OK:",
            "            status[c] = s",
        ]
        lines += _first_fault()
        return "\n".join(lines)
    if alg.forces:
        lines.append("        none = np.empty((0, 6))")
    lines.append("        for b in range(starts[c], stops[c]):")
    if alg.forces:
        lines.append("            fb = f[b] if f.shape[0] > 0 else none")
    lines += [
        f"            s = {core}(mc, {', '.join(per_sample)}, work)",
        "            if s != OK:",
        "                status[c] = at_sample(s, b)",
        "                break",
    ]
    return "\n".join(lines + _first_fault())


def _first_fault() -> list[str]:
    """The end of a batch entry: the first chunk's fault, or OK."""
    return [
        "    for c in range(starts.shape[0]):",
        "        if status[c] != OK:",
        "            return status[c]",
        "    return OK",
    ]


GENERATED = "GENERATED by tools/generate_entries.py from ``table.py``: do not edit by hand."


def module(alg) -> str:
    """The module of one algorithm's entry points."""
    imports = [
        "import numpy as np",
        "from numba import carray, prange",
        "",
        "from ..._jit import native, parallel, serial",
        "from ...multibody.packed import unpack",
        "from .._pointers import SIGNATURE, packed_array",
        "from .._workspace import STACK_FLOATS, chunks, stack_buffer",
        f"from ..{alg.module} import {alg.core}",
    ]
    if alg.group:
        imports.append(f"from ..{alg.group} import {alg.name}_group")
    imports.append("from ..status import OK, WRONG_SHAPE" + ("" if alg.group else ", at_sample"))
    imports.append(f"from ..work.{alg.module} import workspace_size")
    if alg.group:
        imports.append(f"from ..work.{alg.group} import workspace_size as group_workspace_size")
    doc = (f'"""Compiled entry points of ``{alg.name}``: one sample, C, batch.\n\n'
           f'{GENERATED}\n"""\n\n')
    return doc + "\n".join(imports) + "\n" + entries(alg) + "\n"


def package(table) -> str:
    names = textwrap.fill(", ".join(f"``{alg.name}``" for alg in table.ALGORITHMS) + ".", 92)
    return (f'"""The compiled entry points of each algorithm of ``table.py``, one module '
            f'per algorithm:\n{names}\n\nImported by '
            f'``calls.Entry``.\n\n{GENERATED}\n"""\n')


def generate() -> dict[str, str]:
    """File name → text of every module of ``entries/``."""
    table = load_table()
    for alg in table.ALGORITHMS:
        assert len(alg.inputs) <= MAX_INPUTS, alg.name
        assert len(alg.outputs) <= MAX_OUTPUTS, alg.name
        assert len(alg.options) <= MAX_OPTIONS, alg.name
    files = {"__init__.py": package(table)}
    files.update({f"{alg.name}.py": module(alg) for alg in table.ALGORITHMS})
    return files


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if the files are stale")
    args = parser.parse_args()
    files = generate()
    present = {p.name for p in TARGET.glob("*.py")} if TARGET.is_dir() else set()
    if args.check:
        stale = sorted(name for name, text in files.items()
                       if not (TARGET / name).is_file() or (TARGET / name).read_text() != text)
        stale += sorted(present - set(files))
        if stale:
            print(f"{TARGET}: {', '.join(stale)} stale: run python tools/generate_entries.py",
                  file=sys.stderr)
            return 1
        print(f"{TARGET} is up to date")
        return 0
    TARGET.mkdir(exist_ok=True)
    for name in present - set(files):
        (TARGET / name).unlink()
    for name, text in files.items():
        (TARGET / name).write_text(text)
    print(f"wrote {len(files)} files in {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
