"""``cgadyn ik`` in a subprocess: a position, a pose as JSON, an unreachable target, errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cgadyn

pytestmark = [pytest.mark.cli, pytest.mark.slow]

SRC = str(Path(cgadyn.__file__).resolve().parents[1])


def _cgadyn(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "cgadyn.cli", "ik", *args], env=env,
                          capture_output=True, text=True, timeout=600)


def test_ik_position_and_pose():
    p = _cgadyn("panda", "panda_hand", "--position", "0.4", "0.1", "0.5")
    assert p.returncode == 0, p.stderr
    assert "converged" in p.stdout and "panda_joint1" in p.stdout
    p = _cgadyn("panda", "panda_hand", "--position", "0.4", "0.1", "0.5", "--orientation",
                "0", "1", "0", "0", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["converged"] and out["error"] <= 1e-10 and out["target"] == "pose"
    model = cgadyn.load("panda")
    T = cgadyn.link_placements(model, np.array(out["q"]))[model.link_index("panda_hand")]
    assert np.allclose(T[:3, 3], [0.4, 0.1, 0.5], atol=1e-10)
    assert np.allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-10)  # w=0, x=1


def test_ik_unreachable_and_errors():
    p = _cgadyn("panda", "panda_hand", "--position", "3", "0", "0", "--restarts", "1")
    assert p.returncode == 1 and "NOT converged" in p.stdout
    p = _cgadyn("panda", "no_link", "--position", "0.4", "0.1", "0.5")
    assert p.returncode == 2 and p.stderr.startswith("cgadyn: error: no link 'no_link'")
    p = _cgadyn("panda", "panda_hand", "--position", "0.4", "nan", "0.5")
    assert p.returncode == 2 and "finite" in p.stderr
    p = _cgadyn("panda", "panda_hand", "--position", "0.4", "0", "0.5", "--orientation", "0",
                "0", "0", "0")
    assert p.returncode == 2 and "cgadyn: error: --orientation: the quaternion is zero" in p.stderr
