"""A first run says what it compiles (``cgadyn._progress``): one line on stderr per
outermost compilation of a cgadyn function that takes longer than the quiet time, nothing on
stdout, nothing for code loaded from the cache, and nothing under ``CGADYN_PROGRESS=0``."""

from __future__ import annotations

import time

import numba
import pytest

from cgadyn import _progress


def _probe(name: str):
    """A fresh compiled function that counts as cgadyn's (its module is ``cgadyn.probe``)."""
    def f(x):
        return x + 1.0

    f.__module__, f.__name__, f.__qualname__ = "cgadyn.probe", name, name
    return numba.njit(f)


def test_a_compilation_is_named_on_stderr_with_its_time(capsys, monkeypatch):
    monkeypatch.setattr(_progress.Progress, "QUIET_SECONDS", 0.0)
    count, seconds = _progress.compiled()
    f = _probe("first")
    time.sleep(0.01)
    assert f(1.0) == 2.0
    out, err = capsys.readouterr()
    assert out == ""
    assert "cgadyn: compiling probe.first (first run only, cached afterwards)... " in err
    assert err.rstrip().endswith(" s")
    assert _progress.compiled()[0] == count + 1 and _progress.compiled()[1] > seconds
    f(2.0)  # compiled: nothing more to say
    assert capsys.readouterr().err == ""


def test_quick_compilations_and_other_code_are_not_listed(capsys, monkeypatch):
    monkeypatch.setattr(_progress.Progress, "QUIET_SECONDS", 60.0)
    assert _probe("quick")(1.0) == 2.0
    numba.njit(lambda x: x * 2.0)(3.0)  # not cgadyn's
    assert capsys.readouterr().err == ""


def test_cgadyn_progress_0_keeps_quiet(capsys, monkeypatch):
    monkeypatch.setattr(_progress.Progress, "QUIET_SECONDS", 0.0)
    monkeypatch.setattr(_progress, "ENABLED", False)
    assert _probe("silent")(1.0) == 2.0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(("module", "name", "said"), [
    ("cgadyn.algorithms.entries.aba", "aba_single", "aba"),
    ("cgadyn.algorithms.entries.aba", "aba_native", "aba"),
    ("cgadyn.algorithms.entries.rnea_derivatives", "rnea_derivatives_batch",
     "rnea_derivatives (batches)"),
    ("cgadyn.sim.rollout", "rollouts", "sim.rollout.rollouts"),
    ("numpy", "sum", None),
])
def test_labels(module, name, said):
    def f():
        pass

    f.__module__, f.__name__ = module, name
    assert _progress.label(f) == said
