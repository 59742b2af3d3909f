"""The one place where cgadyn asks numba to compile, and how.

Every compiled function of the package is declared with one of these decorators, named by
its role:

- ``inline``: a small kernel (a motor product, a sandwich) that numba inlines into every
  compiled caller (``inline="always"``: the recursions run about 30 % faster than with calls);
- ``core``: the body of an algorithm, one sample; the only liberty taken with IEEE
  arithmetic is fusing a multiply and an add into one FMA instruction (``contract``);
- ``serial``: any other compiled function;
- ``parallel``: a batch entry, its samples split over numba's threads with ``prange``;
- ``native(signature)``: a C-callable entry point (``numba.cfunc``) that ``cgadyn._native``
  calls with raw pointers (see ``docs/architecture.md``).

Every one uses numpy's error model: a float division by zero gives inf or NaN (which the
algorithms report as a status) instead of raising, since compiled code must not raise.

Machine code is cached on disk (``__pycache__`` beside the sources, or ``NUMBA_CACHE_DIR``,
or numba's user cache directory) so that a second process starts in about a second. numba
keys a cached function on its own file only, not on the kernels it inlines from other
files, so this module first compares the fingerprint of the package's compiled code
(``_sources.compiled_fingerprint``) with the one its cache was built from and, when that
code has changed, deletes the package's cached machine code: a cache never outlives the
code it was compiled from. Where numba finds no writable cache location at all, decorating
with ``cache=True`` raises ``RuntimeError`` at import; here the package then compiles in
memory instead, with one warning, and works the same (only slower to start).
"""

from __future__ import annotations

import os
import threading
import warnings
from collections.abc import Callable
from pathlib import Path

import numba

from ._sources import PACKAGE, compiled_fingerprint

__all__ = ["caching", "core", "inline", "native", "parallel", "serial"]

_CACHE = [True]
"""Whether numba can cache on disk: True until a decoration finds no cache location."""


def _cache_dirs() -> list[Path]:
    """Where numba may keep the package's compiled code: ``__pycache__`` beside the
    sources, and its mirror of the package's path under ``NUMBA_CACHE_DIR``."""
    dirs = [d for d in PACKAGE.rglob("__pycache__") if d.is_dir()]
    root = os.environ.get("NUMBA_CACHE_DIR")
    if root:
        mirror = Path(root) / str(PACKAGE).lstrip(os.sep)
        if mirror.is_dir():
            dirs += [mirror, *(d for d in mirror.rglob("*") if d.is_dir())]
    return dirs


def _heal() -> None:
    """Delete the package's cached machine code if it was compiled from other sources."""
    stamp = PACKAGE / "__pycache__" / "numba-sources.txt"
    try:
        if stamp.read_text() == compiled_fingerprint():
            return
    except OSError:
        pass
    for d in _cache_dirs():
        for f in [*d.glob("*.nbi"), *d.glob("*.nbc")]:
            try:
                f.unlink()
            except OSError:
                pass
    try:
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(compiled_fingerprint())
    except OSError:
        pass  # read-only: numba will not cache here either


_heal()


def caching() -> bool:
    """True while compiled code is cached on disk (False after no location was writable)."""
    return _CACHE[0]


def _compile(decorator: Callable, fn: Callable, **options):
    if _CACHE[0]:
        try:
            return decorator(cache=True, **options)(fn)
        except RuntimeError as exc:  # "cannot cache function ...: no locator available"
            _CACHE[0] = False
            warnings.warn(
                f"cgadyn: numba cannot cache compiled code on disk ({exc}); compiling in "
                f"memory instead, so every new process compiles again. Set NUMBA_CACHE_DIR "
                f"to a writable directory to cache it.", RuntimeWarning, stacklevel=3)
    return decorator(**options)(fn)


def inline(fn: Callable):
    """A kernel inlined into its compiled callers."""
    return _compile(numba.njit, fn, nogil=True, inline="always", error_model="numpy")


def core(fn: Callable):
    """One sample of an algorithm, with multiply-adds fused (``fastmath={"contract"}``)."""
    return _compile(numba.njit, fn, nogil=True, fastmath={"contract"}, error_model="numpy")


def serial(fn: Callable):
    """A compiled function that runs on the calling thread."""
    return _compile(numba.njit, fn, nogil=True, error_model="numpy")


def parallel(fn: Callable):
    """A batch entry whose ``prange`` loops run on numba's threads."""
    return _compile(numba.njit, fn, nogil=True, parallel=True, error_model="numpy")


def native(signature) -> Callable:
    """A C-callable entry point of the given numba signature (``numba.cfunc``), compiled (or
    loaded from the disk cache) on first use of its ``address``, not at import."""
    return lambda fn: Native(fn, signature)


class Native:
    """A ``numba.cfunc`` made on demand: ``address`` is the C function's address."""

    _lock = threading.Lock()

    def __init__(self, fn: Callable, signature):
        self.py_func, self.signature, self._cfunc = fn, signature, None

    @property
    def address(self) -> int:
        if self._cfunc is None:
            with self._lock:
                if self._cfunc is None:
                    self._cfunc = _compile(numba.cfunc, self.py_func, sig=self.signature,
                                           error_model="numpy")
        return self._cfunc.address
