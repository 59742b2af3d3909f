"""The path of a call from a public function to compiled code, and back.

Each algorithm of ``table.py`` has three compiled entries (``entries/<name>.py``). A public
function first offers its arguments to ``cgadyn._native.call`` (``fast``): arrays that are
already one C-contiguous float64 sample of the right length go straight to the algorithm's
C entry point, which allocates nothing but the result. Anything else, and any fault, takes
``run``, the checked path, which

1. converts and checks the inputs (``_inputs``): lists, other dtypes, strided views;
   wrong shapes, None, complex numbers get a ``ValueError`` naming the argument;
2. runs one sample through the C entry point (or, where ``cgadyn._native`` is not built,
   through numba's dispatcher; under ``NUMBA_DISABLE_JIT=1`` in pure Python), or a batch
   ``(B, ...)`` through the parallel batch entry, one call for all samples;
3. turns a status other than 0 into the ``ValueError`` of ``errors.explain``.

The C entry points are compiled (or loaded from numba's disk cache) and registered with
``cgadyn._native`` on their first use. Batches run under ``_threads.PARALLEL_LOCK``. Arrays
of another library go whole to the module that serves them (``_arrays``), above this
layer, which calls ``run`` again on numpy chunks.
"""

from __future__ import annotations

import importlib
import math
import os
import threading
import warnings

import numba
import numpy as np

from .. import _arrays
from .._threads import PARALLEL_LOCK
from ..multibody.packed import DEFAULT_GRAVITY
from . import _blocks, _inputs
from .errors import explain
from .table import ALGORITHMS, SIZES

NATIVE_ENABLED = os.environ.get("CGADYN_NATIVE", "1") != "0" and not numba.config.DISABLE_JIT
"""``CGADYN_NATIVE=0`` runs one-sample calls through numba's dispatcher instead."""

NATIVE_ABI = 2
"""The calling convention of ``cgadyn._native`` this module speaks (``ABI`` in _native.c)."""

try:
    from .. import _native
except ImportError as exc:  # not built: see setup.py
    _native = None
    NATIVE_STATUS = f"missing ({exc})"
else:
    NATIVE_STATUS = "loaded"
    if getattr(_native, "ABI", 1) != NATIVE_ABI:  # built from older sources
        _native = None
        NATIVE_STATUS = "missing (built from older sources of cgadyn: it must be rebuilt)"
if not NATIVE_ENABLED:
    _native = None
    NATIVE_STATUS = ("disabled (NUMBA_DISABLE_JIT=1)" if numba.config.DISABLE_JIT
                     else "disabled (CGADYN_NATIVE=0)")
"""``cgadyn._native``: ``"loaded"``, ``"missing (why)"`` or ``"disabled (by what)"``."""

NATIVE_MISSING_ADVICE = (
    "single calls (rnea, aba, crba, ...) go through numba's dispatcher instead, several "
    "times slower, since it types, unboxes and boxes every argument (batches are "
    "unaffected). To build it, install a C compiler (gcc or clang, e.g. `apt install gcc`, "
    "or Xcode's command line tools) and reinstall cgadyn the way it was installed (`pip "
    "install --force-reinstall --no-deps .` or `pip install -e .` in a checkout)")
"""What a missing C extension costs and how to get it (the warning, ``cgadyn info``)."""

if NATIVE_STATUS.startswith("missing"):
    from .. import NativeExtensionMissing

    warnings.warn(f"cgadyn's C extension cgadyn._native is {NATIVE_STATUS}: "
                  f"{NATIVE_MISSING_ADVICE}", NativeExtensionMissing, stacklevel=2)

_REGISTER = threading.Lock()


def _code(size) -> int:
    return size if isinstance(size, int) else -1 - SIZES.index(size)


class Entry:
    """The compiled entries of one algorithm and its slot in ``cgadyn._native``."""

    def __init__(self, slot: int, algorithm):
        self.slot, self.algorithm = slot, algorithm
        name = algorithm.name
        module = importlib.import_module(f".entries.{name}", __package__)
        self.single = getattr(module, f"{name}_single")
        self.native = getattr(module, f"{name}_native")
        self.batch = getattr(module, f"{name}_batch")
        self.registered = False

    def register(self) -> None:
        """Compile (or load) the C entry point and hand it to ``cgadyn._native``."""
        with _REGISTER:
            if not self.registered:
                alg = self.algorithm
                _native.register(self.slot, self.native.address,
                                 [_code(size) for _, size in alg.inputs],
                                 [[_code(d) for d in dims] for dims in alg.outputs],
                                 alg.forces, len(alg.options))
                self.registered = True

    def outputs(self, model, batch: tuple[int, ...]) -> list[np.ndarray]:
        """Output arrays with undefined contents. Several outputs are views of one block,
        each starting on a 64-byte boundary: freed together, separate arrays of a few MiB
        would go back to the kernel and cost a page fault per 4 KiB on the next batch,
        where one block of
        4 MiB or more is mapped in huge pages (numpy asks for them). A batch's block is one
        that an earlier batch returned and its caller dropped, where there is one
        (``_blocks``)."""
        sizes = {"n": model.njoints, "nq": model.nq, "nv": model.nv, "nl": model.nlinks}
        shapes = [batch + tuple(sizes.get(d, d) for d in dims)
                  for dims in self.algorithm.outputs]
        if not batch and len(shapes) == 1:
            return [np.empty(shapes[0])]
        counts = [math.prod(shape) for shape in shapes]
        starts = np.cumsum([0] + [-(-c // 8) * 8 for c in counts])  # 8 floats: 64 bytes
        raw = _blocks.block(int(starts[-1]) + 8)
        skip = (-raw.ctypes.data % 64) // 8
        return [raw[skip + o:skip + o + c].reshape(shape)
                for o, c, shape in zip(starts[:-1], counts, shapes, strict=True)]

    def one(self, model, packed, x: tuple, f, options: tuple[int, ...]):
        """One sample: ``(status, outputs)``."""
        forces = (f,) if self.algorithm.forces else ()
        if _native is not None:
            if not self.registered:
                self.register()
            r = _native.call(self.slot, packed, *x, *forces, *options)
            if isinstance(r, int):
                return r, None
            if r is not None:
                return 0, r if isinstance(r, tuple) else (r,)
        out = self.outputs(model, ())
        if self.algorithm.forces and f is None:
            forces = (np.empty((0, 6)),)
        return int(self.single(packed, *x, *forces, *out, *options)), tuple(out)

    def many(self, model, packed, x: tuple, f, options: tuple[int, ...]):
        """A (B, ...) batch in one parallel call: ``(status, outputs)``."""
        out = self.outputs(model, x[0].shape[:1])
        forces = ()
        if self.algorithm.forces:
            forces = (f if f is not None else np.empty((0, model.njoints, 6)),)
        with PARALLEL_LOCK:
            status = self.batch(packed, *x, *forces, *out, *options,
                                numba.get_num_threads())
        return int(status), tuple(out)


ENTRIES = {a.name: Entry(slot, a) for slot, a in enumerate(ALGORITHMS)}
SLOTS = {name: e.slot for name, e in ENTRIES.items()}


def _no_fast_path(*args):
    return None


fast = _native.call if _native is not None else _no_fast_path
"""``fast(slot, packed, x..., [f,] option...)`` (``f`` where the algorithm takes wrenches,
one int per option of its record): the result of a canonical one-sample call,
else (an odd input, a fault, an entry not yet registered) something that is not an
ndarray or tuple; the caller then calls ``run``."""


def run(name: str, model, arrays: tuple, gravity=DEFAULT_GRAVITY, f_ext=None,
        options: tuple[int, ...] = ()):
    """The checked path of algorithm ``name`` on ``arrays`` (its inputs, in table order) and
    ``options`` (its integer arguments, in table order): its output, or a tuple of its
    outputs, for one sample or a batch."""
    server = _arrays.server(arrays)
    if server is not None:  # another library's arrays, served above
        return server.run(name, model, arrays, gravity, f_ext, options)
    entry = ENTRIES[name]
    alg = entry.algorithm
    x = _inputs.states(model, arrays, alg.inputs)
    batch = x[0].shape[:-1]
    packed = _inputs.packed(model, gravity)
    f = _inputs.external(model, f_ext, batch) if alg.forces else None
    if batch == (0,):
        out = tuple(entry.outputs(model, batch))
    elif batch == (1,):  # a one-sample batch: the one-sample entry, without threads
        status, out = entry.one(model, packed, tuple(a[0] for a in x),
                                None if f is None else f[0], options)
        out = None if out is None else tuple(o[None] for o in out)
    elif batch:
        status, out = entry.many(model, packed, x, f, options)
    else:
        status, out = entry.one(model, packed, x, f, options)
    if batch != (0,) and status != 0:
        names = dict(zip((n for n, _ in alg.inputs), x, strict=True))
        if f_ext is not None:
            names["f_ext"] = np.asarray(f_ext, dtype=float)
        raise explain(status, model, alg, names)
    return out[0] if len(out) == 1 else out
