"""Call a compiled single-sample algorithm on the fastest path numba offers from Python.

A numba dispatcher checks its arguments' types in C (dtype, dimensions, layout,
writability) in a few tens of nanoseconds per argument; checking the same in Python costs
ten times more. So the Python-facing functions hand their arguments straight to the
dispatcher (``Compiled.fast``) with compilation *disabled*: arguments of exactly the
canonical types (C-contiguous writable float64 arrays, ``None`` for absent options) run at
once, anything else raises ``TypeError`` instead of compiling a new specialisation (as
does everything before the first compile), and the caller then normalises its inputs and
takes ``Compiled.call``, which compiles (or loads from the disk cache) the canonical
signature the first time it is needed. Compilation is only ever switched on under a lock,
for one signature. Under ``NUMBA_DISABLE_JIT=1`` both paths call the plain Python function.

A refusal would cost numba about 80 µs (it types every argument in Python to look for
conversions and to word its error message), so the dispatcher's two miss callbacks are
replaced by ones that refuse at once (about 1 µs): an int or float32 array then costs a
few microseconds on the checked path, not a hundred. Should numba stop calling them, the
refusal is only slower, never wrong.
"""

from __future__ import annotations

import threading

import numba

_COMPILING = threading.Lock()


class Compiled:
    """A numba-compiled function called only with its canonical argument types.

    ``fast(*args)``: canonical types only, anything else raises ``TypeError``;
    ``call(*args)``: normalised arguments, compiled on first use.
    """

    __slots__ = ("call", "dispatcher", "fast")

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        if hasattr(dispatcher, "disable_compile"):
            self.fast = _not_compiled_yet
            self.call = self._compile_and_call
        else:  # NUMBA_DISABLE_JIT=1: a plain Python function
            self.fast = self.call = dispatcher

    def _compile_and_call(self, *args):
        """Call with normalised arguments, compiling their signature first if needed."""
        try:
            return self.fast(*args)
        except TypeError:
            pass
        d = self.dispatcher
        with _COMPILING:
            d.disable_compile(False)
            try:
                d.compile(tuple(numba.typeof(a) for a in args))
            finally:
                if d.signatures:  # numba refuses to disable compiling with none
                    d.disable_compile()
            d._search_new_conversions = _no_conversions  # the C dispatcher's miss callbacks
            d._explain_matching_error = _not_compiled_yet
            self.fast = d
        return d(*args)


def _not_compiled_yet(*args, **kws):
    raise TypeError("not the compiled signature: take the checked path")


def _no_conversions(*args, **kws) -> bool:
    return False
