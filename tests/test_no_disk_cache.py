"""cgadyn works where numba can cache nothing on disk: it compiles in memory, with a warning.

Every cache location is made unwritable for a copy of the package: each ``__pycache__`` is a
file (so no directory can be made there, even by root), and ``NUMBA_CACHE_DIR``, ``HOME`` and
``XDG_CACHE_HOME`` point below ``/dev/null``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cgadyn

pytestmark = pytest.mark.slow


SCRIPT = """
import warnings
import numpy as np
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    import cgadyn
    model = cgadyn.load("double_pendulum")
    tau = cgadyn.rnea(model, np.array([0.3, -0.2]), np.zeros(2), np.zeros(2))
print(repr(tau.tolist()))
print(sum("cannot cache" in str(w.message) for w in caught))
"""


def test_import_and_compute_without_any_writable_cache(tmp_path: Path):
    package = Path(cgadyn.__file__).parent
    copy = tmp_path / "cgadyn"
    shutil.copytree(package, copy, ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    for d in [copy, *(p for p in copy.rglob("*") if p.is_dir())]:
        (d / "__pycache__").write_text("a file where numba would make a directory")
    env = {**os.environ, "PYTHONPATH": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1",
           "NUMBA_CACHE_DIR": "/dev/null/numba", "HOME": "/dev/null",
           "XDG_CACHE_HOME": "/dev/null", "CGADYN_CACHE_DIR": "/dev/null/cgadyn"}
    run = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True,
                         text=True, timeout=600, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr
    tau_line, warnings_line = run.stdout.strip().splitlines()[-2:]
    tau = eval(tau_line)
    expected = cgadyn.rnea(cgadyn.load("double_pendulum"), [0.3, -0.2], [0.0, 0.0], [0.0, 0.0])
    assert tau == expected.tolist()
    assert int(warnings_line) == 1  # one warning, not one per function
