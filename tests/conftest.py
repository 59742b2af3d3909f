"""Test-suite settings: hypothesis runs derandomized, so CI sees the same examples every run.

Set ``HYPOTHESIS_PROFILE=explore`` to draw fresh random examples locally.
"""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, deadline=None)
settings.register_profile("explore", deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


# --- where the suite's time goes -------------------------------------------------------
# A cold run (fresh clone, empty cache) spends most of its time in numba compiling. The
# summary at the end names the test files and the compiled functions that cost the most,
# so that CI's log says where to cut.

import time  # noqa: E402
from collections import defaultdict  # noqa: E402

import pytest  # noqa: E402
from numba.core import event as _numba_event  # noqa: E402


class _CompileClock(_numba_event.Listener):
    """Outermost numba compilations: seconds per compiled function and per test file."""

    def __init__(self) -> None:
        self.depth = 0
        self.started = 0.0
        self.name = ""
        self.per_function: dict[str, float] = defaultdict(float)
        self.per_file: dict[str, float] = defaultdict(float)
        self.current_file = "(collection)"

    def on_start(self, event: _numba_event.Event) -> None:
        if self.depth == 0:
            self.started = time.perf_counter()
            dispatcher = (event.data or {}).get("dispatcher")
            self.name = getattr(getattr(dispatcher, "py_func", None), "__qualname__", "?")
        self.depth += 1

    def on_end(self, event: _numba_event.Event) -> None:
        self.depth -= 1
        if self.depth == 0:
            seconds = time.perf_counter() - self.started
            self.per_function[self.name] += seconds
            self.per_file[self.current_file] += seconds


_clock = _CompileClock()
_file_seconds: dict[str, float] = defaultdict(float)
_numba_event.register("numba:compile", _clock)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):  # type: ignore[no-untyped-def]
    _clock.current_file = item.location[0]
    started = time.perf_counter()
    yield
    _file_seconds[item.location[0]] += time.perf_counter() - started


def pytest_terminal_summary(terminalreporter, exitstatus, config):  # type: ignore[no-untyped-def]
    total = sum(_file_seconds.values())
    if total < 60:
        return
    write = terminalreporter.write_line
    terminalreporter.section("where the time went (files over 1 % of the run)")
    for name, seconds in sorted(_file_seconds.items(), key=lambda kv: -kv[1]):
        if seconds >= 0.01 * total:
            write(f"{seconds:8.1f} s  (compiling {_clock.per_file.get(name, 0.0):7.1f} s)  {name}")
    write(f"numba compiled for {sum(_clock.per_function.values()):.0f} s of {total:.0f} s; "
          "the costliest:")
    for name, seconds in sorted(_clock.per_function.items(), key=lambda kv: -kv[1])[:20]:
        write(f"{seconds:8.1f} s  {name}")
