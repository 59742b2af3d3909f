"""Cached machine code never outlives the sources it was compiled from, in any of numba's
cache directories.

numba keys a cached function on its own file only; an edit to a kernel it inlines from
another file leaves the cached function as it was. ``cgadyn._jit`` heals this at import. The
scenario: a copy of the package computes under one ``NUMBA_CACHE_DIR``, then under another;
an inlined kernel (the joint scalars, in ``multibody/joints/dispatch.py``, not the file of the
algorithm) is edited; each directory, used again, must give the edited code's numbers.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import cgadyn

pytestmark = pytest.mark.slow


SCRIPT = """
import numpy as np
import cgadyn
model = cgadyn.load("double_pendulum")
print(repr(cgadyn.rnea(model, np.array([0.3, -0.2]), np.zeros(2), np.zeros(2)).tolist()))
"""
EDIT = ("        x = q[k]\n", "        x = q[k] + 0.5\n")
"""The joint scalars of ``q + 0.5``: the torques of another configuration."""


def _env(tmp_path: Path, cache: Path) -> dict[str, str]:
    """The environment of a process that imports the copy of the package in ``tmp_path``
    and caches its machine code in ``cache``."""
    return {**os.environ, "PYTHONPATH": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1",
            "NUMBA_CACHE_DIR": str(cache), "CGADYN_CACHE_DIR": str(tmp_path / "models")}


def _run(tmp_path: Path, cache: Path) -> list[float]:
    run = subprocess.run([sys.executable, "-c", SCRIPT], env=_env(tmp_path, cache),
                         capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    return eval(run.stdout.strip().splitlines()[-1])


def _copy(tmp_path: Path) -> tuple[Path, np.ndarray, np.ndarray]:
    """A copy of the package in ``tmp_path``, and ``SCRIPT``'s torques before and after
    ``EDIT`` (computed here, by the package itself)."""
    package = Path(cgadyn.__file__).parent
    copy = tmp_path / "cgadyn"
    shutil.copytree(package, copy, ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    model = cgadyn.load("double_pendulum")
    before = cgadyn.rnea(model, [0.3, -0.2], [0.0, 0.0], [0.0, 0.0])
    after = cgadyn.rnea(model, [0.8, 0.3], [0.0, 0.0], [0.0, 0.0])
    assert not np.allclose(before, after)  # the edit shows in the numbers
    return copy, before, after


def test_an_edited_kernel_heals_every_cache_directory(tmp_path: Path):
    copy, before, after = _copy(tmp_path)
    first, second = tmp_path / "numba_a", tmp_path / "numba_b"
    assert np.allclose(_run(tmp_path, first), before, rtol=0, atol=1e-12)
    assert np.allclose(_run(tmp_path, second), before, rtol=0, atol=1e-12)
    joints = copy / "multibody" / "joints" / "dispatch.py"
    text = joints.read_text()
    assert text.count(EDIT[0]) == 1
    joints.write_text(text.replace(*EDIT))
    assert np.allclose(_run(tmp_path, first), after, rtol=0, atol=1e-12)
    assert np.allclose(_run(tmp_path, second), after, rtol=0, atol=1e-12)


def test_an_edit_throws_away_only_the_machine_code_that_depends_on_it(tmp_path, monkeypatch):
    """After an edit of ``algorithms/aba.py``, ``_jit._heal`` deletes the cached functions of
    every file whose imports reach ``aba.py`` (aba's core, its entries, the rollouts) and
    keeps the others (rnea's core and entries): a new process loads rnea from the cache."""
    from numba.core import config
    from numba.core.caching import UserProvidedCacheLocator

    from cgadyn import _jit, _sources

    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path))
    edited = _sources.PACKAGE / "algorithms" / "aba.py"
    prints = _sources.closure_fingerprints()
    depends = {p for p in prints if edited in _sources.closure(p)}
    rel = {str(p.relative_to(_sources.PACKAGE)) for p in depends}
    assert {"algorithms/aba.py", "algorithms/entries/aba.py", "sim/rollout.py"} <= rel
    assert not {"algorithms/rnea.py", "algorithms/entries/rnea.py"} & rel
    made = {}
    for src in {p.parent for p in prints}:
        sub = UserProvidedCacheLocator.get_suitable_cache_subpath(str(src / "__init__.py"))
        d = tmp_path / sub
        d.mkdir(parents=True)
        stamp = {p.name: ("before the edit" if p in depends else fp)
                 for p, fp in prints.items() if p.parent == src}
        (d / _jit.STAMP).write_text(json.dumps(stamp))
        for p in prints:
            if p.parent == src:
                f = d / f"{p.stem}.some_function-12.py311.nbi"
                f.write_text("")
                made[f] = p
    _jit._heal()
    for f, p in made.items():
        assert f.exists() == (p not in depends), (f, p)
    for src in {p.parent for p in prints}:
        sub = UserProvidedCacheLocator.get_suitable_cache_subpath(str(src / "__init__.py"))
        assert json.loads((tmp_path / sub / _jit.STAMP).read_text()) == {
            p.name: fp for p, fp in prints.items() if p.parent == src}


LATE = """
import sys, time
from pathlib import Path
import numpy as np
import cgadyn
model = cgadyn.load("double_pendulum")
Path(sys.argv[1]).write_text("imported")
while not Path(sys.argv[2]).exists():
    time.sleep(0.05)
print(repr(cgadyn.rnea(model, np.array([0.3, -0.2]), np.zeros(2), np.zeros(2)).tolist()))
"""
"""A process that imports the package, waits, and only then compiles rnea and caches it."""


def test_a_process_that_imported_before_an_edit_does_not_cache_as_current(tmp_path: Path):
    """The race ``_heal`` alone does not cover: a process imports the sources, an inlined
    kernel is edited, a new process heals the cache (and stamps it as the edited code's),
    then the first process compiles rnea from the code it imported and caches it under
    numba's stamp of rnea's own file, which the edit did not touch. The first process
    computes with the code it imported; a third must compute with the edited code (numba's
    index names the fingerprint of the sources it was compiled from,
    ``_jit._install_source_stamps``)."""
    copy, before, after = _copy(tmp_path)
    cache = tmp_path / "numba"
    env = _env(tmp_path, cache)
    ready, go = tmp_path / "ready", tmp_path / "go"
    late = subprocess.Popen([sys.executable, "-c", LATE, str(ready), str(go)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tmp_path)
    try:
        for _ in range(6000):
            if ready.exists() or late.poll() is not None:
                break
            time.sleep(0.05)
        assert ready.exists(), late.communicate()[1]
        joints = copy / "multibody" / "joints" / "dispatch.py"
        joints.write_text(joints.read_text().replace(*EDIT))
        heal = subprocess.run([sys.executable, "-c", "import cgadyn._jit"], env=env,
                              capture_output=True, text=True, timeout=600, cwd=tmp_path)
        assert heal.returncode == 0, heal.stderr  # a new process heals the cache, caches nothing
        go.write_text("go")
        out, err = late.communicate(timeout=600)
    finally:
        if late.poll() is None:
            late.kill()
    assert late.returncode == 0, err
    assert np.allclose(eval(out.strip().splitlines()[-1]), before, rtol=0, atol=1e-12)
    assert np.allclose(_run(tmp_path, cache), after, rtol=0, atol=1e-12)
