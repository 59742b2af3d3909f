"""The ``cgadyn`` command in-process (``main([...])``), and every user error in a subprocess:
``cgadyn: error: ...`` on stderr, exit status 2, never a traceback."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from cgadyn import cli, oracle
from cgadyn.commands import validate as validate_command
from cgadyn.multibody import robot_path
from cgadyn.validate import leaf_links, validate_robot


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def strict_json(text: str):
    """Parse as standard JSON: ``NaN`` and ``Infinity`` are refused."""
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_validate_panda_table(capsys):
    code, out, _ = run(capsys, "validate", "panda", "--samples", "3")
    assert code == 0
    assert out.startswith("cgadyn validate: panda, fixed base, nq 9, nv 9, 3 samples, seed 0")
    assert oracle.RELATIVE in out
    for check in oracle.CHECKS:
        assert check.label in out
    assert "FAIL" not in out and out.count("  pass") == len(oracle.CHECKS)


def test_validate_runs_sample_by_sample(monkeypatch):
    """validate's cgadyn side takes the one-sample entries, never a batch entry: a cold
    validate then compiles no parallel batch entry and no lane group."""
    from cgadyn.algorithms import calls

    def refuse(*args, **kwargs):
        raise AssertionError("validate called a batch entry")

    monkeypatch.setattr(calls.Entry, "many", refuse)
    result = validate_robot("panda", samples=3)
    assert result["pass"] and set(result["checks"]) == {c.key for c in oracle.CHECKS}


def test_validate_json_floating_base(capsys):
    code, out, _ = run(capsys, "validate", "solo12", "--samples", "3", "--seed", "3", "--json")
    assert code == 0
    result = strict_json(out)
    assert (result["robot"], result["base"], result["nq"], result["nv"]) == \
        ("solo12", "free flyer", 19, 18)
    assert set(result["checks"]) == {c.key for c in oracle.CHECKS} | {"constrained"}
    assert result["labels"] == {"constrained": "constrained, feet held (q̈, λ)"}
    for row in result["checks"].values():
        assert row["pass"] and row["max_rel"] < 1e-10


def test_validate_fixed_base_override(capsys):
    code, out, _ = run(capsys, "validate", "solo12", "--fixed-base", "--samples", "2")
    assert code == 0 and "solo12, fixed base, nq 12, nv 12" in out


def test_validate_own_robot_with_continuous_and_prismatic_joints(capsys):
    code, out, _ = run(capsys, "validate", "prismatic_tree", "--samples", "3", "--json")
    result = strict_json(out)
    assert code == 0 and result["pass"] and result["nv"] == 7
    assert len(result["jacobian_links"]) >= 2  # a tree: one Jacobian per branch


def test_tiny_tolerance_fails_with_status_1(capsys):
    code, out, _ = run(capsys, "validate", "double_pendulum", "--samples", "3",
                       "--tolerance", "1e-30")
    assert code == 1 and "FAIL" in out


MASSLESS_TIP = """<robot name="massless_tip">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1"/><origin xyz="0 0 -0.5"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="tip"/>
    <origin xyz="0 0 -1"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""


def test_validate_nan_says_why_and_json_is_standard(tmp_path, capsys):
    """A massless movable subtree makes M singular: the checks that need M⁻¹ say why, and as
    Pinocchio's results are NaN too, report the quantity undefined rather than a mismatch;
    the JSON holds null where a number could not be computed."""
    path = tmp_path / "massless_tip.urdf"
    path.write_text(MASSLESS_TIP)
    code, out, _ = run(capsys, "validate", str(path), "--samples", "2")
    assert code == 0 and "why: sample 0: singular articulated-body inertia at joint 'elbow'" in out
    assert "has no mass" in out
    assert "undefined for this robot: aba, aba_derivatives, minverse" in out
    code, out, _ = run(capsys, "validate", str(path), "--samples", "2", "--json")
    aba = strict_json(out)["checks"]["aba"]
    assert aba["max_rel"] is None and "no mass" in aba["error"] and "not_applicable" in aba
    assert strict_json(out)["checks"]["rnea"]["pass"]


ONE_JOINT_ARM = """<robot name="one_joint_arm">
  <link name="base"><inertial><mass value="3"/>
    <inertia ixx="0.2" iyy="0.3" izz="0.4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><mass value="1"/><origin xyz="0.1 0 -0.5"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""
ONE_BODY = """<robot name="one_body">
  <link name="body"><inertial><mass value="2"/><origin xyz="0.01 0.02 0.03"/>
    <inertia ixx="0.1" iyy="0.2" izz="0.3" ixy="0.01" ixz="0" iyz="0"/></inertial></link>
</robot>
"""


@pytest.mark.parametrize("urdf, argv, nv", [(ONE_JOINT_ARM, [], 1),
                                            (ONE_BODY, ["--floating-base"], 6),
                                            (ONE_JOINT_ARM, ["--floating-base"], 7)])
def test_validate_robots_of_one_joint(tmp_path, capsys, urdf, argv, nv):
    """Pinocchio returns a 6 x 1 Jacobian or centroidal matrix as a vector (6,): the oracle
    reshapes it, so a one-joint arm passes (it failed the Jacobians and the centroidal
    check broke on broadcasting), and so does a lone free body (one joint, the root)."""
    path = tmp_path / "robot.urdf"
    path.write_text(urdf)
    code, out, _ = run(capsys, "validate", str(path), "--samples", "3", *argv, "--json")
    result = strict_json(out)
    assert result["nv"] == nv
    for key, row in result["checks"].items():
        assert row["pass"] and "error" not in row and row["max_rel"] < 1e-12, (key, row)
    assert code == 0 and result["pass"]


def test_info_says_whether_the_c_extension_is_there(capsys):
    from cgadyn.algorithms import calls

    code, out, _ = run(capsys, "info", "double_pendulum", "--json")
    native = strict_json(out)["native_extension"]
    assert code == 0 and native["status"] == calls.NATIVE_STATUS
    assert native["fast_single_calls"] == (calls.NATIVE_STATUS == "loaded")
    code, out, _ = run(capsys, "info", "double_pendulum")
    assert f"C extension (fast single calls): {calls.NATIVE_STATUS}" in out


def test_robots_lists_bases_and_refusals(capsys):
    code, out, _ = run(capsys, "robots")
    assert code == 0
    rows = {line.split()[0]: line for line in out.splitlines()[1:-1]}
    assert rows["talos"].split()[1:5] == ["free", "flyer", "39", "38"]
    assert rows["panda"].split()[1:4] == ["fixed", "9", "9"]
    # the longest name keeps a space before its base
    assert rows["gymnasium:inverted_double_pendulum"].split()[1:5] == ["fixed", "3", "3",
                                                                       "gymnasium"]
    assert "refused" in rows["cassie"] and "loops" in rows["cassie"]
    assert "refused" in rows["romeo_laas_small"]
    code, out, _ = run(capsys, "robots", "--names")
    names = out.split()
    assert {"panda", "skew_arm", "talos", "solo12"} <= set(names) and names == sorted(names)


def test_info_floating_base(capsys):
    code, out, _ = run(capsys, "info", "talos")
    assert code == 0 and out.startswith("talos: free flyer base, nq = 39, nv = 38")
    assert "root_joint" in out and "free_flyer" in out
    code, out, _ = run(capsys, "info", "skew_arm", "--json")
    info = strict_json(out)
    assert code == 0 and info["nv"] == len(info["joints"]) == 6 and info["base"] == "fixed"
    assert "continuous" in {j["kind"] for j in info["joints"]}


def test_info_shows_an_mjcfs_world_and_its_actuators(capsys):
    """An MJCF's static world: its ground and walls (dm_control's quadruped: four, each
    facing the arena's middle); a URDF has none; each actuator's kind (fish's servos)."""
    pytest.importorskip("mujoco")
    code, out, _ = run(capsys, "info", "dm_control:quadruped", "--json")
    world = strict_json(out)["world"]
    assert code == 0 and world["ground"]["height"] == 0.0
    walls = {o["name"]: o for o in world["obstacles"]}
    assert set(walls) == {"wall_px", "wall_py", "wall_nx", "wall_ny"}
    assert all(o["shape"].startswith("wall, facing") for o in walls.values())
    assert "wall_px                   wall, facing (0.7071, 0, 0.7071)" in \
        run(capsys, "info", "dm_control:quadruped")[1]
    code, out, _ = run(capsys, "info", "double_pendulum", "--json")
    assert strict_json(out)["world"] is None
    code, out, _ = run(capsys, "info", "dm_control:fish")
    assert "position kp 0.0005" in out


def test_info_accepts_a_path_with_any_extension(tmp_path, capsys):
    path = tmp_path / "arm.description"
    path.write_text(robot_path("ur5").read_text())
    code, out, _ = run(capsys, "info", str(path))
    assert code == 0 and "nv = 6" in out


def test_version(capsys):
    code, out, _ = run(capsys, "--version")
    assert code == 0 and out.strip().startswith("cgadyn ")


def test_all_summary_and_refused(capsys, monkeypatch):
    from cgadyn.multibody import registry

    monkeypatch.setattr(registry, "robots", lambda: ["double_pendulum", "romeo_laas_small",
                                                     "solo"])
    code, out, _ = run(capsys, "validate", "--all", "--samples", "2")
    assert code == 0 and "2/2 robots pass; 1 refused" in out
    assert "romeo_laas_small" in out and "solo" in out


def test_all_reports_a_robot_that_fails_to_run(capsys, monkeypatch):
    from cgadyn.multibody import registry

    monkeypatch.setattr(registry, "robots", lambda: ["double_pendulum", "not_a_robot"])
    code, out, _ = run(capsys, "validate", "--all", "--samples", "2", "--json")
    result = strict_json(out)
    assert code == 1 and not result["pass"]
    assert "unknown robot" in result["results"][1]["error"]
    assert validate_command.SHORT.keys() == {c.key for c in oracle.CHECKS} | {"constrained"}


def test_all_summary_shows_the_mujoco_checks_of_an_mjcf_model():
    import argparse

    from cgadyn import mujoco_oracle

    def row(rel):
        return {"max_rel": rel, "pass": True}

    checks = {c.key: row(1e-16) for c in oracle.CHECKS}
    mjcf = {"robot": "gymnasium:inverted_double_pendulum", "nv": 3, "base": "fixed",
            "pass": True, "checks": checks | {key: row(3.25e-15 + i * 1e-16)
                                              for i, key in enumerate(mujoco_oracle.CHECKS)}}
    urdf = {"robot": "panda", "nv": 9, "base": "fixed", "pass": True, "checks": checks}
    args = argparse.Namespace(samples=2, seed=0, tolerance=1e-10)
    lines = validate_command.format_summary([urdf, mjcf], args).splitlines()
    head = next(line for line in lines if line.startswith("robot"))
    assert all(title in head for title in validate_command.MUJOCO_SHORT.values())
    assert validate_command.MUJOCO_SHORT.keys() == mujoco_oracle.CHECKS.keys()
    mine = next(line for line in lines if line.startswith(mjcf["robot"] + " "))
    assert [f"{3.25e-15 + i * 1e-16:.2e}" for i in range(5)] == mine.split()[-6:-1]
    # the name fits its column: each cell ends where its title does
    assert mine.index("3.25e-15") + 8 == head.index("mj x") + 4
    assert mine.index(" 3 fixed") + 2 == head.index(" nv") + 3
    panda = next(line for line in lines if line.startswith("panda "))
    assert "3.25e-15" not in panda and panda.split()[-1] == "pass"
    no_mjcf = validate_command.format_summary([urdf], args)
    assert "mj rnea" not in no_mjcf and "mujoco" not in no_mjcf


def test_validate_robot_api_and_leaves():
    import cgadyn

    assert leaf_links(cgadyn.load("panda")) == ["panda_leftfinger", "panda_rightfinger"]
    result = validate_robot("gripper", samples=3, seed=1)
    assert result["pass"] and result["samples"] == 3
    with pytest.raises(ValueError, match="unknown robot"):
        validate_robot("not_a_robot", samples=1)


def test_sampling_respects_limits():
    import cgadyn

    model = cgadyn.load("skew_arm")
    q = oracle.sample(model, 200, 1).q
    bounded = np.isfinite(model.lower) & np.isfinite(model.upper)
    assert np.all(q[:, bounded] >= model.lower[bounded])
    assert np.all(q[:, bounded] <= model.upper[bounded])
    assert np.all(np.abs(q[:, ~bounded]) <= math.pi) and (~bounded).any()


ZERO_DOF = '<robot name="statue"><link name="base"/></robot>'
NEGATIVE_MASS = MASSLESS_TIP.replace('<mass value="1"/>', '<mass value="-1"/>')


def _user_errors(tmp) -> list[tuple[list[str], str]]:
    (tmp / "statue.urdf").write_text(ZERO_DOF)
    (tmp / "negative.urdf").write_text(NEGATIVE_MASS)
    return [
        (["validate", "--seed", "-1"], "--seed: must be an integer >= 0"),
        (["validate", "--tolerance", "0"], "--tolerance: must be a positive finite number"),
        (["validate", "--tolerance", "nan"], "--tolerance: must be a positive finite number"),
        (["validate", "--tolerance", "inf"], "--tolerance: must be a positive finite number"),
        (["validate", "--samples", "0"], "--samples: must be an integer >= 1"),
        (["validate", "panda", "--all"], "give a ROBOT or --all, not both"),
        (["validate", str(tmp / "statue.urdf")], "no degree of freedom"),
        (["validate", str(tmp / "negative.urdf")], "mass"),
        (["validate", "romeo_laas_small"], "not positive semi-definite"),
        (["validate", str(tmp / "missing.urdf")], "file not found"),
        (["info", str(tmp / "missing.xml")], "file not found"),
        (["bench", str(tmp / "missing")], "file not found"),
        (["bench", str(tmp / "statue.urdf")], "no degree of freedom"),
        (["validate", "no_such_robot"], "unknown robot 'no_such_robot'"),
        (["simulate-body", "--plot", str(tmp / "no_dir" / "x.png")], "does not exist"),
        (["simulate-body", "--plot", str(tmp / "x.unknown")], "not a format matplotlib"),
        (["bogus"], "invalid choice"),
    ]


@pytest.mark.slow
@pytest.mark.cli
def test_every_user_error_in_a_subprocess(tmp_path):
    """Each error: status 2, one ``cgadyn: error:`` line naming the problem, no traceback.
    The subprocesses run side by side."""
    cases = _user_errors(tmp_path)
    procs = [subprocess.Popen([sys.executable, "-m", "cgadyn.cli", *argv], text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE)
             for argv, _ in cases]
    for (argv, message), proc in zip(cases, procs, strict=True):
        out, err = proc.communicate(timeout=600)
        assert proc.returncode == 2, (argv, out, err)
        assert "Traceback" not in out + err, argv
        assert "cgadyn: error: " in err and message in err, (argv, err)


@pytest.mark.slow
@pytest.mark.cli
def test_console_entry_point_subprocess():
    proc = subprocess.run([sys.executable, "-m", "cgadyn.cli", "validate", "double_pendulum",
                           "--samples", "3"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "double_pendulum, fixed base, nq 2, nv 2, 3 samples" in proc.stdout
    assert "PASS" in proc.stdout
