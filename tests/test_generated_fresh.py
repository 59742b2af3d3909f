"""The committed generated kernels equal what tools/generate_kernels.py writes now, and the
generator runs even when the files it generates are broken."""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
KERNELS = ROOT / "src" / "cgadyn" / "kernels"


def _generator():
    spec = importlib.util.spec_from_file_location("generate_kernels", ROOT / "tools" /
                                                  "generate_kernels.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_generated_files_are_fresh():
    gen = _generator()
    kernels = gen.derive()
    assert gen.TARGET.read_text() == gen.generate(kernels), "run python tools/generate_kernels.py"
    assert gen.BATCH_TARGET.read_text() == gen.generate_batch(kernels), (
        "run python tools/generate_kernels.py")


def test_the_generator_repairs_a_broken_generated_file(tmp_path):
    """It imports the reference algebra only, never the kernels it writes."""
    shutil.copytree(ROOT / "src", tmp_path / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    (tmp_path / "tools").mkdir()
    shutil.copy(ROOT / "tools" / "generate_kernels.py", tmp_path / "tools")
    broken = tmp_path / "src" / "cgadyn" / "kernels"
    (broken / "_generated.py").write_text("def motor_mul(:  # a broken file\n")
    (broken / "_generated_batch.py").unlink()
    run = subprocess.run([sys.executable, str(tmp_path / "tools" / "generate_kernels.py")],
                         capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    for name in ("_generated.py", "_generated_batch.py"):
        assert (broken / name).read_text() == (KERNELS / name).read_text()
