"""A fingerprint of the package's own code, for caches that must never outlive it.

numba's disk cache keys compiled code on the modification time of the function's own file,
not on the files of the kernels it inlines; the model cache keys models on the code that
built them. Both use ``fingerprint()``: the version and the bytes of every ``.py`` file of
the installed package (generated kernels included), read once per process.
"""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


@cache
def fingerprint() -> str:
    """A hex digest of the package's version and sources."""
    from . import __version__

    h = hashlib.sha256(__version__.encode())
    for path in sorted(PACKAGE.rglob("*.py")):
        h.update(str(path.relative_to(PACKAGE)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()
