"""Generate ``src/cgadyn/algorithms/_entries.py``: the compiled entry points of every algorithm.

Each record of ``src/cgadyn/algorithms/table.py`` gets three entry points around its core
``<module>.<name>_core(m, inputs..., [f,] outputs..., option, work) -> status``:

- ``<name>_single(packed, inputs..., [f,] outputs..., option)``: one sample, its workspace
  on the call's stack (on the heap above ``STACK_FLOATS``);
- ``<name>_native(pk, x0, x1, x2, f, nf, o0, o1, o2, option)``: the same from raw pointers,
  a C function (``numba.cfunc``) that ``cgadyn._native`` calls with the arrays' data, sizes
  read from the packed model's header;
- ``<name>_batch(packed, inputs..., [f,] outputs..., option, threads)``: (B, ...) samples in
  parallel chunks, one heap workspace per chunk; checks the shapes. A record with a
  ``group`` module hands each chunk to that module's ``<name>_group``.

They differ between algorithms only in names and arities, and numba caches compiled code
per function of a real file, so they are written out here rather than made by a closure
factory (whose functions would share one cache name).

Usage::

    python tools/generate_entries.py            # rewrite the file
    python tools/generate_entries.py --check    # exit 1 if the committed file is stale

The table is read by file path, so this script never imports the package it generates for.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TABLE = ROOT / "src" / "cgadyn" / "algorithms" / "table.py"
TARGET = ROOT / "src" / "cgadyn" / "algorithms" / "_entries.py"
MAX_INPUTS, MAX_OUTPUTS = 3, 3


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
    args = inputs + forces + outputs
    core = alg.core
    ws = f"{alg.name}_workspace(m.n, m.nq, m.nv, m.nl)"
    lines = [
        "", "",
        "@serial",
        f"def {alg.name}_single(packed, {', '.join(args)}, option):",
        f'    """One sample of ``{alg.core}``; its workspace on this call\'s stack."""',
        "    m = unpack(packed)",
        f"    size = {ws}",
        "    if size <= STACK_FLOATS:",
        f"        return {core}(m, {', '.join(args)}, option, stack_buffer(size))",
        f"    return {core}(m, {', '.join(args)}, option, np.empty(size))",
        "", "",
        "@native(SIGNATURE)",
        f"def {alg.name}_native(pk, x0, x1, x2, f, nf, o0, o1, o2, option):",
        f'    """``{alg.name}_single`` on raw pointers, for ``cgadyn._native``."""',
        "    packed = packed_array(pk)",
        "    m = unpack(packed)",
    ]
    call = [f"carray(x{i}, {shape((dim,))})" for i, (_, dim) in enumerate(alg.inputs)]
    call += ["carray(f, (nf, 6))"] if alg.forces else []
    call += [f"carray(o{i}, {shape(dims)})" for i, dims in enumerate(alg.outputs)]
    lines.append(f"    return {alg.name}_single(")
    lines.append("        packed,")
    lines += [f"        {c}," for c in call]
    lines.append("        option)")
    checks = [f"{x}.shape[1] != m.{dim}" for x, dim in alg.inputs]
    checks += [f"{x}.shape[0] != batch" for x in inputs[1:]]
    checks += [f"{o}.shape[0] != batch" for o in outputs]
    if alg.forces:
        checks += ["(f.shape[0] != 0 and f.shape[0] != batch)", "f.shape[1] != m.n"]
    per_sample = [f"{x}[b]" for x in inputs] + (["fb"] if alg.forces else [])
    per_sample += [f"{o}[b]" for o in outputs]
    lines += [
        "", "",
        "@parallel",
        f"def {alg.name}_batch(packed, {', '.join(args)}, option, threads):",
        f'    """(B, ...) samples of ``{alg.core}`` in parallel chunks; a status."""',
        "    m = unpack(packed)",
        f"    batch = {inputs[0]}.shape[0]",
        "    if (" + "\n            or ".join(checks) + "):",
        "        return WRONG_SHAPE",
        f"    size = {alg.name}_group_workspace(m.n, m.nq, m.nv, m.nl)" if alg.group else
        f"    size = {ws}",
        "    starts, stops = chunks(batch, threads)",
        "    status = np.zeros(starts.shape[0], dtype=np.int64)",
        "    for c in prange(starts.shape[0]):",
        "        mc = unpack(packed)",
        "        work = np.empty(size)",
    ]
    if alg.group:
        lines += [
            f"        s = {alg.name}_group(mc, {', '.join(args)}, starts[c], stops[c], option,"
            " work)",
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
        f"            s = {core}(mc, {', '.join(per_sample)}, option, work)",
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


HEADER = '''"""Compiled entry points of the algorithms of ``table.py``: one sample, C, batch.

GENERATED by tools/generate_entries.py from ``table.py``: do not edit by hand.
"""

import numpy as np
from numba import carray, prange, types

from .._jit import native, parallel, serial
from .._views import as_int64
from ..multibody.packed import HEADER, unpack
{imports}
from ._workspace import STACK_FLOATS, chunks, stack_buffer
from .status import OK, WRONG_SHAPE, at_sample

_P = types.CPointer(types.float64)
SIGNATURE = types.int64(_P, _P, _P, _P, _P, types.int64, _P, _P, _P, types.int64)
"""``(packed, x0, x1, x2, f, nf, o0, o1, o2, option) -> status``: unused inputs and
outputs are ignored; ``f`` holds ``nf`` (0 or n) wrenches."""


@serial
def packed_array(pk):
    """The packed model at ``pk`` as an array, its length read from its header."""
    return carray(pk, (carray(as_int64(pk), (HEADER,))[HEADER - 1],))
'''


def generate() -> str:
    table = load_table()
    for alg in table.ALGORITHMS:
        assert len(alg.inputs) <= MAX_INPUTS and len(alg.outputs) <= MAX_OUTPUTS, alg.name
    imports = "\n".join(
        f"from .{alg.module} import {alg.core}\nfrom .{alg.module} import workspace_size as "
        f"{alg.name}_workspace" for alg in sorted(table.ALGORITHMS, key=lambda a: a.module))
    imports += "".join(
        f"\nfrom .{alg.group} import {alg.name}_group\nfrom .{alg.group} import workspace_size "
        f"as {alg.name}_group_workspace" for alg in table.ALGORITHMS if alg.group)
    return HEADER.format(imports=imports) + "".join(
        entries(alg) + "\n" for alg in table.ALGORITHMS)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if the file is stale")
    args = parser.parse_args()
    text = generate()
    if args.check:
        if (TARGET.read_text() if TARGET.exists() else "") != text:
            print(f"{TARGET} is stale: run python tools/generate_entries.py", file=sys.stderr)
            return 1
        print(f"{TARGET} is up to date")
        return 0
    TARGET.write_text(text)
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
