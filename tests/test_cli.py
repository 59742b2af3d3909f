"""The ``cgadyn`` command in-process (``main([...])``) and once as a subprocess."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from cgadyn import cli
from cgadyn.validate import ALGORITHMS, compare, leaf_links, sample_states, validate_robot


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_validate_panda_table(capsys):
    code, out, _ = run(capsys, "validate", "panda", "--samples", "5")
    assert code == 0
    assert "panda, 9 dof, 5 samples, seed 0" in out and "pinocchio" in out
    assert "max(1, max|pinocchio|)" in out
    for label in ALGORITHMS.values():
        assert label in out
    assert "FAIL" not in out and out.count("pass") == len(ALGORITHMS)


def test_validate_json(capsys):
    code, out, _ = run(capsys, "validate", "ur5", "--samples", "4", "--seed", "3", "--json")
    assert code == 0
    result = json.loads(out)
    assert {"robot", "dof", "samples", "seed", "tolerance", "versions", "relative_error",
            "jacobian_links", "algorithms", "pass"} <= set(result)
    assert (result["robot"], result["dof"], result["samples"], result["seed"]) == ("ur5", 6, 4, 3)
    assert set(result["algorithms"]) == set(ALGORITHMS)
    for row in result["algorithms"].values():
        assert row["pass"] and row["max_rel"] < 1e-10 and row["mean_norm"] < 1e-10


def test_validate_own_robot_with_continuous_and_prismatic_joints(capsys):
    code, out, _ = run(capsys, "validate", "prismatic_tree", "--samples", "5", "--json")
    result = json.loads(out)
    assert code == 0 and result["pass"] and result["dof"] == 7
    assert len(result["jacobian_links"]) >= 2  # a tree: one Jacobian per branch


def test_validate_defaults_to_panda(capsys):
    code, out, _ = run(capsys, "validate", "--samples", "2")
    assert code == 0 and out.startswith("cgadyn validate: panda, 9 dof, 2 samples")


def test_unknown_robot_exits_2_and_lists_robots(capsys):
    code, out, err = run(capsys, "validate", "no_such_robot")
    assert code == 2 and out == ""
    assert "unknown robot 'no_such_robot'" in err
    assert "panda" in err and "skew_arm" in err and "Traceback" not in err


def test_tiny_tolerance_fails(capsys):
    code, out, _ = run(capsys, "validate", "double_pendulum", "--samples", "3",
                       "--tolerance", "1e-30")
    assert code == 1 and "FAIL" in out


@pytest.mark.parametrize("argv", [["validate", "--samples", "0"], ["validate", "panda", "--all"],
                                  ["bogus"], []])
def test_bad_usage_exits_2(capsys, argv):
    assert cli.main(argv) == 2


def test_robots(capsys):
    code, out, _ = run(capsys, "robots")
    names = out.split()
    assert code == 0 and {"panda", "skew_arm", "gripper", "prismatic_tree"} <= set(names)
    assert names == sorted(names)


def test_info_panda(capsys):
    code, out, _ = run(capsys, "info", "panda")
    assert code == 0 and "panda: 9 dof" in out
    assert "panda_joint1" in out and "prismatic" in out and "panda_hand" in out and "kg" in out


def test_info_json(capsys):
    code, out, _ = run(capsys, "info", "skew_arm", "--json")
    info = json.loads(out)
    assert code == 0 and info["dof"] == len(info["joints"]) == 6
    assert "continuous" in {j["kind"] for j in info["joints"]}


def test_version(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.strip().startswith("cgadyn ")


def test_all_summary(capsys, monkeypatch):
    monkeypatch.setattr(cli, "_known_robots", lambda: ["double_pendulum", "gripper"])
    code, out, err = run(capsys, "validate", "--all", "--samples", "2")
    assert code == 0 and "2/2 robots pass" in out
    assert "double_pendulum" in out and "gripper" in out
    assert "] 2/2" in err  # the progress bar


def test_all_reports_a_robot_that_fails_to_run(capsys, monkeypatch):
    monkeypatch.setattr(cli, "_known_robots", lambda: ["double_pendulum", "not_a_robot"])
    code, out, _ = run(capsys, "validate", "--all", "--samples", "2")
    assert code == 1 and "1/2 robots pass" in out and "unknown robot" in out


def test_sampling_respects_limits():
    import cgadyn

    model = cgadyn.load("skew_arm")
    q = sample_states(model, 200, 1).q
    bounded = np.isfinite(model.lower) & np.isfinite(model.upper)
    assert np.all(q[:, bounded] >= model.lower[bounded])
    assert np.all(q[:, bounded] <= model.upper[bounded])
    assert np.all(np.abs(q[:, ~bounded]) <= math.pi) and (~bounded).any()


def test_compare_detects_error_and_nan():
    ref = np.array([[2.0, 0.0], [0.5, 0.5]])
    row = compare(ref + [[0.2, 0.0], [0.0, 0.0]], ref)
    assert row["max_rel"] == pytest.approx(0.1) and row["worst_sample"] == 0
    assert math.isnan(compare(ref * np.nan, ref)["max_rel"])


def test_validate_robot_api_and_leaves():
    import cgadyn

    assert leaf_links(cgadyn.load("panda")) == ["panda_leftfinger", "panda_rightfinger"]
    result = validate_robot("gripper", samples=3, seed=1)
    assert result["pass"] and result["samples"] == 3
    with pytest.raises(ValueError, match="unknown robot"):
        validate_robot("not_a_robot", samples=1)


def test_console_entry_point_subprocess():
    proc = subprocess.run([sys.executable, "-m", "cgadyn.cli", "validate", "double_pendulum",
                           "--samples", "3"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "double_pendulum, 2 dof, 3 samples" in proc.stdout and "PASS" in proc.stdout
