"""Run a Python script with its numba code named for ``perf``: a sampled profile by function.

    perf record -F 4000 -o perf.data python tools/perf_map.py SCRIPT [ARGS ...]
    perf report -i perf.data --no-children --sort sym

numba's machine code lives in anonymous memory, so ``perf`` shows its samples as bare
addresses. This wrapper records the object code of every library numba loads from its
cache while ``SCRIPT`` runs (run the script once before, so that what it compiles is
cached: a warm run is what to profile), and at exit writes ``/tmp/perf-PID.map``,
the file through which ``perf report`` names code that no file on disk holds: each function
symbol of each object (``nm``) at the address where the engine loaded it, placed by one
exported function whose address the engine gives. Functions LLVM inlined are counted in
their callers; each ``core`` of cgadyn is a function of its own (``_jit.core``).
"""

from __future__ import annotations

import atexit
import os
import runpy
import subprocess
import sys
import tempfile

from numba.core import codegen

_LOADED: dict[int, tuple[object, bytes]] = {}


def _keep(original):
    def wrapper(library, value, *args):
        _LOADED[id(library)] = (library, bytes(value))
        return original(library, value, *args)
    return wrapper


def _symbols(obj: bytes) -> list[tuple[int, int, str, str]]:
    """``(offset, size, kind, name)`` of the defined code symbols of an object file."""
    with tempfile.NamedTemporaryFile(suffix=".o") as f:
        f.write(obj)
        f.flush()
        out = subprocess.run(["nm", "-S", "--defined-only", f.name], capture_output=True,
                             text=True, check=False).stdout
    symbols = []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tTW":
            symbols.append((int(parts[0], 16), int(parts[1], 16), parts[2], parts[3]))
    return symbols


def write_map(path: str | None = None) -> str:
    """Write the perf map of the code loaded so far; returns its path."""
    lines = []
    for library, obj in _LOADED.values():
        symbols = _symbols(obj)
        base = None
        for offset, _, kind, name in symbols:
            if kind == "T":
                address = library._codegen._engine.get_function_address(name)
                if address:
                    base = address - offset
                    break
        if base is not None:
            lines += [f"{base + o:x} {size:x} {name}\n" for o, size, _, name in symbols]
    path = path or f"/tmp/perf-{os.getpid()}.map"
    with open(path, "w") as f:
        f.writelines(lines)
    return path


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    codegen.CPUCodeLibrary._set_compiled_object = _keep(
        codegen.CPUCodeLibrary._set_compiled_object)
    atexit.register(write_map)
    sys.argv = sys.argv[1:]
    runpy.run_path(sys.argv[0], run_name="__main__")


if __name__ == "__main__":
    main()
