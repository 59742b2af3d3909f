"""Call a compiled function without numba's per-call type dispatch.

A numba dispatcher spends about half a microsecond resolving argument types on every
call; for single-sample dynamics that is a large share of the whole call. A wrapper that
has checked its arguments have exactly the canonical types (C-contiguous float64 arrays of
the right shapes, the model's own arrays) may call the compiled entry point of that
signature directly: ``Entry(dispatcher).call(*args)``. The first call goes through the
dispatcher (compiling or loading the cache) and then swaps in the entry point. Under
``NUMBA_DISABLE_JIT=1`` the plain Python function is called every time.
"""

from __future__ import annotations

import numba


class Entry:
    """A compiled function's fastest calling path for one fixed signature."""

    __slots__ = ("call", "dispatcher")

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self.call = self._first_call

    def _first_call(self, *args):
        result = self.dispatcher(*args)
        overloads = getattr(self.dispatcher, "overloads", None)
        if overloads is not None:
            cres = overloads.get(tuple(numba.typeof(a) for a in args))
            if cres is not None:
                self.call = cres.entry_point
        return result
