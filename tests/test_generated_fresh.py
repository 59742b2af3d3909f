"""The committed generated kernels equal what tools/generate_kernels.py writes now."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _generator():
    spec = importlib.util.spec_from_file_location("generate_kernels", ROOT / "tools" /
                                                  "generate_kernels.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_generated_files_are_fresh():
    gen = _generator()
    assert gen.TARGET.read_text() == gen.generate(), "run python tools/generate_kernels.py"
    assert gen.BATCH_TARGET.read_text() == gen.generate_batch(), (
        "run python tools/generate_kernels.py"
    )
