"""examples/ik_primitives.py: the panda's tool on a plane, on a sphere and along a line, each
checked by the tool's placement measured independently of the task residuals."""

from __future__ import annotations

import importlib.util
from pathlib import Path

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
