"""examples/ik_primitives.py: the panda's tool on a plane, on a sphere and along a line, each
checked by the tool's placement measured independently of the task residuals; and
examples/dual_arm_baxter.py: baxter's hands keep their relative pose along a circle."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "ik_primitives.py"


def test_tool_on_plane_sphere_and_line():
    spec = importlib.util.spec_from_file_location("ik_primitives", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    results = module.run()
    assert set(results) == {"plane", "sphere", "line"}
    for name, (res, geometric_error) in results.items():
        assert res.converged, name
        assert res.error <= 1e-10 and geometric_error <= 1e-9, name


DUAL_ARM = EXAMPLE.parent / "dual_arm_baxter.py"


def test_dual_arm_example_holds_the_relative_pose():
    spec = importlib.util.spec_from_file_location("dual_arm_baxter", DUAL_ARM)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    rows = module.run(waypoints=4)
    assert len(rows) == 4
    for r in rows:
        assert r["converged"]
        assert r["relative_drift"] <= 1e-9 and r["absolute_error"] <= 1e-9
    # the hands really moved (the waypoints are a quarter of the circle apart)
    assert np.linalg.norm(rows[1]["left"] - rows[0]["left"]) > 0.05
