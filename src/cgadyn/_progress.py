"""What a first run spends compiling, said while it happens.

numba compiles a function on its first call for given argument types and keeps the machine
code in its disk cache (``_jit``), so a first run spends seconds to minutes compiling where
later runs load in milliseconds. So that a user is never left waiting in silence, this
module listens to numba's ``numba:compile`` events (numba raises them only when it found no
cached code) and writes one line to stderr per cgadyn function compiled at the outermost
level for longer than half a second (the functions it calls compile inside it and are
counted, not listed):

    cgadyn: compiling aba (first run only, cached afterwards)... 11.2 s

``compiled()`` gives the count and the seconds so far, for a total at the end of a command.
``CGADYN_PROGRESS=0`` keeps quiet; nothing on stdout changes either way.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from contextlib import contextmanager

from numba.core import event

ENABLED = os.environ.get("CGADYN_PROGRESS", "1") != "0"
"""Whether the lines are written (``CGADYN_PROGRESS=0`` turns them off)."""

_ROLES = {"single": "", "native": "", "batch": " (batches)"}
"""The generated entries (``algorithms/entries``) are named after their algorithm."""


def label(fn) -> str | None:
    """How a compiled function is named to a user: its algorithm for an entry point
    (``aba``, ``rnea (batches)``), its module and name for the others
    (``sim.rollout.rollouts``), None outside cgadyn."""
    module = getattr(fn, "__module__", "") or ""
    if not module.startswith("cgadyn."):
        return None
    name = fn.__name__
    if module.startswith("cgadyn.algorithms.entries."):
        base, _, role = name.rpartition("_")
        return base + _ROLES.get(role, "_" + role)
    return f"{module.removeprefix('cgadyn.')}.{name}"


class Progress(event.Listener):
    """Counts and times compilations, and names on stderr the outermost ones that take
    longer than ``QUIET_SECONDS`` (a line appears when that time has passed, so that the
    many small helpers compiled on a first run do not each take a line)."""

    QUIET_SECONDS = 0.5

    def __init__(self) -> None:
        self.depth = 0
        self.count = 0
        self.seconds = 0.0
        self._start = 0.0
        self._name: str | None = None
        self._compiled = False
        self._timer: threading.Timer | None = None
        self._said = False
        self._lock = threading.Lock()

    def _say(self) -> None:
        with self._lock:
            if self._timer is not None and not self._said:
                sys.stderr.write(f"cgadyn: compiling {self._name} (first run only, cached "
                                 f"afterwards)... ")
                sys.stderr.flush()
                self._said = True

    def enter(self, name: str | None, compiles: bool) -> None:
        """A compilation of ``name`` begins (``compiles``), or a frame that may compile
        inside (a C entry point, which numba loads from its cache or compiles without an
        event of its own): the outermost one names the line."""
        if self.depth == 0:
            self._start, self._name, self._compiled, self._said = (
                time.perf_counter(), name, False, False)
        if compiles and not self._compiled:
            self._compiled = True
            if ENABLED and self._name is not None:
                self._timer = threading.Timer(self.QUIET_SECONDS, self._say)
                self._timer.daemon = True
                self._timer.start()
        self.depth += 1

    def exit(self) -> None:
        self.depth -= 1
        if self.depth > 0:
            return
        if self._compiled:
            took = time.perf_counter() - self._start
            self.seconds += took
            with self._lock:
                if self._timer is not None:
                    self._timer.cancel()
                    self._timer = None
                if self._said:
                    sys.stderr.write(f"{took:.1f} s\n")
                    sys.stderr.flush()

    def on_start(self, ev) -> None:
        name = label(ev.data["dispatcher"].py_func)
        self.count += name is not None
        self.enter(name, compiles=True)

    def on_end(self, ev) -> None:
        self.exit()


PROGRESS = Progress()
event.register("numba:compile", PROGRESS)


@contextmanager
def frame(fn):
    """Around the making of a C entry point ``fn`` (``_jit.Native``): what compiles inside
    is said under ``fn``'s name."""
    PROGRESS.enter(label(fn), compiles=False)
    try:
        yield
    finally:
        PROGRESS.exit()


def compiled() -> tuple[int, float]:
    """How many cgadyn functions this process compiled, and the seconds it spent."""
    return PROGRESS.count, PROGRESS.seconds
