"""examples/mppi_solo12.py: MPPI over batched contact rollouts moves solo12's base to a
target over its feet, which the same joint PD alone, holding one posture, cannot; both keep
it standing."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "mppi_solo12.py"


@pytest.fixture(scope="module")
def result():
    spec = importlib.util.spec_from_file_location("mppi_solo12", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    # a shorter run than the example's: no push, the target from 0.2 s, fewer samples
    return module.run(seconds=0.8, samples=32, push=(0.0, 0.0, (0.0, 0.0, 0.0)),
                      shift_at=0.2, seed=0)


@pytest.mark.slow
def test_mppi_moves_the_base_to_the_target_and_the_pd_alone_does_not(result):
    target = np.linalg.norm(result["shift"])
    assert result["pd_late_error"] > 0.7 * target  # one posture: the base stays put
    assert result["mppi_late_error"] < 0.5 * result["pd_late_error"]
    for name in ("mppi", "pd"):  # standing: the base neither fell nor flew
        z = result[name][:, 2]
        assert np.all((z > 0.15) & (z < 0.35))
