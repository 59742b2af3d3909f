"""A fingerprint of the package's own code, for caches that must never outlive it.

numba's disk cache keys compiled code on the modification time of the function's own file,
not on the files of the kernels it inlines; the model cache keys models on the code that
built them. The model cache uses ``fingerprint()``: the version and the bytes of every
``.py`` file of the installed package (generated kernels included). numba's cache uses
``compiled_fingerprint()``, the same over the files that hold compiled code (those that
import ``_jit`` or use numba's decorators), so that editing the command line or the
documentation does not throw away minutes of compiled code. Each is read once per process.
"""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


_COMPILED = (b"_jit import", b"njit", b"cfunc")
"""What marks a file that holds compiled code."""


def _holds_compiled_code(path: Path) -> bool:
    return path.name == "_jit.py" or any(m in path.read_bytes() for m in _COMPILED)


@cache
def compiled_sources() -> tuple[Path, ...]:
    """The package's files that hold compiled code, in order."""
    return tuple(p for p in sorted(PACKAGE.rglob("*.py")) if _holds_compiled_code(p))


def _digest(only_compiled: bool) -> str:
    from . import __version__

    h = hashlib.sha256(__version__.encode())
    for path in compiled_sources() if only_compiled else sorted(PACKAGE.rglob("*.py")):
        h.update(str(path.relative_to(PACKAGE)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


@cache
def fingerprint() -> str:
    """A hex digest of the package's version and all its sources."""
    return _digest(only_compiled=False)


@cache
def compiled_fingerprint() -> str:
    """A hex digest of the package's version and the sources that hold compiled code."""
    return _digest(only_compiled=True)
