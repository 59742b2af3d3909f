"""The one place where cgadyn asks numba to compile, and how.

Every compiled function of the package is declared with one of these decorators, named by
its role:

- ``inline``: a small kernel (a motor product, a sandwich) inlined into every compiled
  caller, so that a recursion is one function without calls: by numba, or (asked for with
  ``CGADYN_INLINE=llvm``) compiled once and inlined by LLVM (``_inlining``);
- ``core``: the body of an algorithm, one sample; the only liberty taken with IEEE
  arithmetic is fusing a multiply and an add into one FMA instruction (``contract``);
  it allocates nothing and counts no references;
- ``serial``: any other compiled function;
- ``parallel``: a batch entry, its samples split over numba's threads with ``prange``;
- ``native(signature)``: a C-callable entry point (``numba.cfunc``) that ``cgadyn._native``
  calls with raw pointers (see ``docs/architecture.md``);
- (``kernels.straight.kernel``: a generated straight-line kernel, an intrinsic that emits
  its operations into each compiled caller from its own source, or with
  ``CGADYN_KERNELS=numba`` an ``inline``;)
- ``intrinsic``: an operation written in LLVM IR (``numba.extending.intrinsic``), for the
  vector instructions of ``kernels/lanes.py``, which numba's optimiser does not form by
  itself (its superword vectoriser is off by default).

Every one uses numpy's error model: a float division by zero gives inf or NaN (which the
algorithms report as a status) instead of raising, since compiled code must not raise.

Machine code is cached on disk (``__pycache__`` beside the sources, or ``NUMBA_CACHE_DIR``,
or numba's user cache directory) so that a second process loads it instead of compiling. numba
keys a cached function on its own file only, not on the kernels it inlines from other
files, so this module first compares, for each file of compiled code, the fingerprint of
the files it depends on (``_sources.closure_fingerprints``) with the one its cache was built
from and, where they differ, deletes that file's cached machine code: a cache never outlives
the code it was compiled from, and an edit recompiles only what depends on it. Where numba
finds no writable cache location at all, decorating with ``cache=True`` raises
``RuntimeError`` at import; here the package then compiles in memory instead, with one
warning, and works the same (only slower to start). What compiles is said on stderr while
it compiles (``_progress``).
"""

from __future__ import annotations

import json
import os
import threading
import warnings
from collections.abc import Callable
from pathlib import Path

import numba
from numba.extending import intrinsic

from . import _collector, _inlining, _progress  # noqa: F401 (_collector: its listener)
from ._sources import closure_fingerprints, compiled_sources

__all__ = ["caching", "core", "inline", "intrinsic", "native", "parallel", "serial"]

_CACHE = [True]
"""Whether numba can cache on disk: True until a decoration finds no cache location."""


STAMP = "cgadyn-sources.json"
"""The file, in each directory of cached machine code, naming the fingerprint of each source
file (``_sources.closure_fingerprints``) its machine code was built from."""


def _cache_dirs() -> list[tuple[Path, list[Path]]]:
    """Where numba may keep the machine code of the package's compiled functions: for every
    directory of compiled sources (``_sources.compiled_sources``), that directory and the
    directories numba's locators derive from it, in the order numba tries them: under
    ``NUMBA_CACHE_DIR`` where that is set, ``__pycache__``, under the user-wide cache. Under
    the two caches, numba names the directory by the source directory's name and a SHA-1 of
    its whole path (``get_suitable_cache_subpath``)."""
    from numba.core import config
    from numba.core.caching import UserProvidedCacheLocator
    from numba.misc.appdirs import AppDirs

    user = Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)
    found = []
    for src in sorted({path.parent for path in compiled_sources()}):
        sub = UserProvidedCacheLocator.get_suitable_cache_subpath(str(src / "__init__.py"))
        given = [Path(config.CACHE_DIR) / sub] if config.CACHE_DIR else []
        found.append((src, [*given, src / "__pycache__", user / sub]))
    return found


def _read_stamp(d: Path) -> dict[str, str]:
    try:
        stamp = json.loads((d / STAMP).read_text())
    except (OSError, ValueError):
        return {}
    return stamp if isinstance(stamp, dict) else {}


def _heal() -> None:
    """Delete the package's cached machine code wherever it was compiled from other sources.

    Each source file's fingerprint covers the files it imports, directly or not
    (``_sources.closure_fingerprints``); a file's cached functions (numba names them
    ``<file stem>.<function>-<line>.py*.nbi`` and ``.nbc``) are deleted where the stamp
    of their directory (``STAMP``: file name → fingerprint) names another fingerprint, so an
    edit throws away the machine code of the files that depend on it and no other. Every
    cache directory carries its own stamp, so that one last used by other sources (under
    another ``NUMBA_CACHE_DIR``, say) is healed when it is used again. The first directory
    numba will try is made now and stamped, so that the code numba caches there later is
    known to be this code's."""
    prints = _PRINTS
    for src, dirs in _cache_dirs():
        now = {p.name: fp for p, fp in prints.items() if p.parent == src}
        try:
            dirs[0].mkdir(parents=True, exist_ok=True)
        except OSError:
            pass  # not writable: numba tries the next one
        for d in dirs:
            if not d.is_dir():
                continue
            stamp = _read_stamp(d)
            if stamp == now:
                continue
            fresh = {Path(name).stem for name, fp in now.items() if stamp.get(name) == fp}
            for f in [*d.glob("*.nbi"), *d.glob("*.nbc")]:
                if f.name.split(".", 1)[0] not in fresh:  # stale, or of a file now gone
                    try:
                        f.unlink()
                    except OSError:
                        pass
            try:
                (d / STAMP).write_text(json.dumps(now, indent=0, sort_keys=True))
            except OSError:
                pass  # read-only: numba will not cache here either


_PRINTS = closure_fingerprints()
"""Each compiled source file's fingerprint of the files it imports, as this process read
them at import."""

_heal()


def _install_source_stamps() -> None:
    """Make numba's cache index of each function of a compiled source file name the file's
    fingerprint (``_PRINTS``) as this process imported it, beside numba's own stamp of the
    file alone.

    ``_heal`` throws away what was compiled from other sources when a process starts, but
    a process that imported the sources before an edit of a file they import, and compiles
    later, writes the machine code of the code it imported into the cache, under the stamp
    of the function's own (unedited) file: later processes would load it as current. With
    the fingerprint in the stamp, numba reads an index written by such a process as stale
    and compiles again. Where numba's locators have no ``get_source_stamp`` (another numba),
    nothing is changed: the healing at import still applies."""
    from numba.core import caching

    mixin = getattr(caching, "_SourceFileBackedLocatorMixin", None)
    original = getattr(mixin, "get_source_stamp", None)
    if original is None or getattr(original, "_cgadyn", False):
        return

    def get_source_stamp(self):
        stamp = original(self)
        fingerprint = _PRINTS.get(Path(getattr(self, "_py_file", "")).resolve())
        return stamp if fingerprint is None else (stamp, fingerprint)

    get_source_stamp._cgadyn = True
    mixin.get_source_stamp = get_source_stamp


_install_source_stamps()


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


INLINE_BY = "llvm" if os.environ.get("CGADYN_INLINE") == "llvm" and _inlining.available() \
    else "numba"
"""How kernels are inlined: ``"numba"`` (numba's ``inline="always"``: the default) or, with
``CGADYN_INLINE=llvm``, ``"llvm"`` (compiled once and inlined by LLVM, ``_inlining``: a first
compilation several times shorter, the same results to rounding, but some calls slower than
the 5 % the project allows; ``validation/results/startup.md``)."""
if INLINE_BY == "llvm":
    _inlining.install()


def inline(fn: Callable):
    """A kernel inlined into its compiled callers, its multiply-adds fused as in a ``core``
    (it runs inside the cores)."""
    if INLINE_BY == "numba":
        return _compile(numba.njit, fn, nogil=True, inline="always", error_model="numpy")
    _inlining.always_inline(fn)
    return _compile(numba.njit, fn, nogil=True, fastmath={"contract"}, error_model="numpy")


def core(fn: Callable):
    """One sample of an algorithm, with multiply-adds fused (``fastmath={"contract"}``),
    compiled without reference counting (``_nrt=False``).

    A core allocates nothing: it reads and writes arrays its caller holds (arguments, and
    views carved from a workspace the caller passes), so its reference counts could never
    reach zero and counting them only costs. numba pairs and removes most counts, but
    not all once LLVM has reshaped a large function (a decrement sunk from two branches
    into one, on a phi of pointers), and each count left is a call in the recursion's
    loop that LLVM cannot move loads across. Without reference counting, numba refuses at
    compile time what would need it (an allocation, an array returned), so a core that
    breaks the promise does not compile. ``tests/test_no_leaks.py`` checks that every
    call frees what it allocates."""
    return _compile(numba.njit, fn, nogil=True, fastmath={"contract"}, error_model="numpy",
                    _nrt=False)


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
                    with _progress.frame(self.py_func):
                        self._cfunc = _compile(numba.cfunc, self.py_func, sig=self.signature,
                                               error_model="numpy")
        return self._cfunc.address
