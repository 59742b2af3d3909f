"""Python's cyclic garbage collector held off while numba compiles.

A compilation makes and drops hundreds of thousands of small objects (IR nodes, types,
typing constraints) while a large recursion's IR stays alive, so the collector runs often
and each run of its oldest generation walks every live object: about a tenth of a first
run's compilation went there (``validation/startup.py``). numba brackets every
compilation with ``numba:compile`` events (raised only when no cached code was found); at
the outermost one the collector is paused, and when it ends the collector is put back as it
was. Nothing compiled changes; the objects a compilation leaves in cycles are collected by
the next ordinary collection.
"""

from __future__ import annotations

import gc
import threading

from numba.core import event


class Paused(event.Listener):
    """Disables the collector from the start of the outermost compilation to its end (the
    compilations nested inside it, of the functions it calls, keep it off)."""

    def __init__(self) -> None:
        self._depth = 0
        self._was_enabled = False
        self._lock = threading.Lock()

    def on_start(self, ev) -> None:
        with self._lock:
            if self._depth == 0:
                self._was_enabled = gc.isenabled()
                gc.disable()
            self._depth += 1

    def on_end(self, ev) -> None:
        with self._lock:
            self._depth -= 1
            if self._depth == 0 and self._was_enabled:
                gc.enable()


PAUSED = Paused()
event.register("numba:compile", PAUSED)
