"""``cgadyn simulate``: its JSON equals ``simulate`` called directly, the chunked run with its
progress bar equals one call, passive runs print their energy drift, ``--plot`` and
``--html`` write their files, and every user error is one ``cgadyn: error:`` line with
status 2 (a subprocess each, never a traceback)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cgadyn
from cgadyn import PD, cli, simulate
from cgadyn.commands import simulate as command
from cgadyn.sim import html

Q0, V0 = np.array([1.0, -0.5]), np.array([0.3, 0.0])


def cgadyn_cmd(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "cgadyn.cli", *argv], capture_output=True,
                          text=True, timeout=300)


def strict_json(text: str):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


@pytest.mark.cli
def test_json_equals_simulate():
    r = cgadyn_cmd("simulate", "double_pendulum", "--seconds", "0.5", "--dt", "0.002",
                   "--q0", "1,-0.5", "--v0", "0.3", "0", "--json")
    assert r.returncode == 0, r.stderr
    out = strict_json(r.stdout)
    model = cgadyn.load("double_pendulum")
    traj = simulate(model, Q0, V0, 0.002, 250)
    assert out["steps"] == out["completed"] == 250 and not out["diverged"]
    for key in ("q", "v", "a", "energy", "kinetic", "potential", "t"):
        np.testing.assert_array_equal(np.array(out[key]), getattr(traj, key), err_msg=key)
    drift = np.max(np.abs(traj.energy - traj.energy[0])) / abs(traj.energy[0])
    assert out["energy_drift"] == pytest.approx(drift, rel=1e-12) and 0 < drift
    # the pendulum's URDF dampers (applied by default) only ever take energy out
    assert np.all(np.diff(traj.energy) <= 1e-6 * abs(traj.energy[0]))
    assert out["controller"] == "none" and out["gains"] is None


def test_text_prints_the_drift_of_passive_runs_only(capsys):
    assert cli.main(["simulate", "double_pendulum", "--seconds", "0.2", "--q0", "1", "-0.5",
                     "--v0", "0.3,0"]) == 0
    out = capsys.readouterr().out
    assert "energy drift (passive run): max |E(t) - E(0)| / |E(0)| = " in out
    assert "200 steps" in out and "controller none" in out
    assert cli.main(["simulate", "double_pendulum", "--seconds", "0.2", "--controller",
                     "gravity", "--q0", "1", "-0.5"]) == 0
    out = capsys.readouterr().out
    assert "controller gravity" in out and "energy drift" not in out


def test_chunked_run_with_progress_bar_equals_one_call(monkeypatch, capsys):
    model = cgadyn.load("double_pendulum")
    monkeypatch.setattr(command, "PROGRESS_AFTER", 0.0)  # draw the bar however fast
    ctrl = PD([30.0, 10.0], [3.0, 1.0], q_ref=np.zeros(2))
    chunked = command.simulate_chunked(model, Q0, V0, 1e-3, 1500, "rk4", ctrl)
    assert chunked.message == "" and not chunked.diverged and chunked.completed == 1500
    assert "simulate |" in capsys.readouterr().err
    traj = simulate(model, Q0, V0, 1e-3, 1500, controller=ctrl)
    for key in ("q", "v", "a", "energy", "t"):
        np.testing.assert_array_equal(getattr(chunked, key), getattr(traj, key), err_msg=key)
    assert np.abs(traj.q[-1]).max() < 0.75 * np.abs(Q0).max()  # the PD (and the URDF's
    # dampers, which slow this overdamped return) pulls it in


def test_pd_gains_follow_the_mass_matrix():
    model = cgadyn.load("panda")
    q = np.asarray(cgadyn.neutral(model), float)
    kp, kd = command.pd_gains(model, q, 10.0)
    M = np.asarray(cgadyn.crba(model, q))
    np.testing.assert_allclose(kp, 100.0 * np.diag(M))
    np.testing.assert_allclose(kd, 20.0 * np.diag(M))
    assert kp[-1] < 1e-2 * kp[1]  # a finger weighs little next to the arm


def test_plot_and_html_files(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    png = tmp_path / "run.png"
    argv = ["simulate", "double_pendulum", "--seconds", "0.3", "--plot", str(png)]
    try:
        html.require_viewer()
        page = tmp_path / "run.html"
        argv += ["--html", str(page)]
    except html.MissingViewer:
        page = None
    assert cli.main(argv) == 0
    out = capsys.readouterr().out
    assert png.stat().st_size > 10_000 and f"plot: {png}" in out
    if page is not None:
        text = page.read_text(encoding="utf-8")
        assert "MeshCat.Viewer" in text and '"frames": 10' in text


@pytest.mark.cli
def test_a_run_that_blows_up_stops_and_says_so():
    r = cgadyn_cmd("simulate", "double_pendulum", "--seconds", "5", "--dt", "0.05",
                   "--controller", "pd", "--kp", "1e9", "--kd", "1e9", "--q0", "1", "0",
                   "--json")
    assert r.returncode == 1, r.stderr
    assert "Traceback" not in r.stderr + r.stdout
    assert "cgadyn: simulation stopped early: stopped after" in r.stderr
    out = strict_json(r.stdout)
    assert out["diverged"] and out["completed"] < 100
    assert len(out["q"]) == out["completed"] + 1
    assert np.all(np.isfinite(np.array(out["q"])))


@pytest.mark.slow
@pytest.mark.cli
@pytest.mark.parametrize("argv, expected", [
    (["--dt", "0"], "argument --dt: must be a positive finite number"),
    (["--dt=-1e-3"], "argument --dt: must be a positive finite number"),
    (["--seconds", "nan"], "argument --seconds: must be a positive finite number"),
    (["--seconds", "1e-4"], "--seconds 0.0001 is shorter than one step of --dt 0.001"),
    (["--integrator", "leapfrog"], "argument --integrator: invalid choice: 'leapfrog'"),
    (["--controller", "lqr"], "argument --controller: invalid choice: 'lqr'"),
    (["--q0", "1", "2", "3"], "--q0 needs 2 numbers for this robot, got 3"),
    (["--q0", "1,x"], "--q0 must be numbers separated by spaces or commas"),
    (["--v0", "inf", "0"], "--v0 must be finite numbers"),
    (["--controller", "pd", "--kp", "-1"], "--kp must be >= 0"),
    (["--controller", "pd", "--kd", "1", "2", "3"], "--kd needs 2 numbers for this robot"),
    (["--plot", "/nonexistent-dir/a.png"], "directory '/nonexistent-dir' does not exist"),
    (["--plot", "a.xyz"], "extension '.xyz' is not a format matplotlib writes"),
    (["--html", "/nonexistent-dir/a.html"], "directory '/nonexistent-dir' does not exist"),
    (["--html", "a.png"], "expected a file ending in .html"),
    (["--kp", "10"], "--kp sets the gains of the PD controller, but the controller is 'none': "
                     "add --controller pd"),
    (["--controller", "gravity", "--kd", "1", "--wn", "3"], "add --controller pd"),
    (["--ground", "--integrator", "rk4"], "--integrator rk4 cannot take contact: with "
                                          "--ground the run is the contact step"),
    (["--drop", "0.1"], "--drop lifts a floating base, but 'double_pendulum' has a fixed base"),
    (["--drop", "-1"], "expected a height in metres >= 0, got '-1'"),
    (["--controls", "random"], "--controls random drives the motors of an MJCF model, but "
                               "'double_pendulum' has none"),
    (["--ground", "--q0", "0", "2.5"], "starts 0.0"),
    (["--soft", "1e5"], "--soft makes the soles on the ground compliant: add --ground"),
    (["--ground", "--soft", "0"], "argument --soft: must be a positive finite number, got '0'"),
    (["--plot", "/proc/a.png"], "cannot write the plot '/proc/a.png': directory '/proc' is not "
                                "writable"),
    (["--html", "/proc/a.html"], "cannot write the animation '/proc/a.html': directory '/proc' "
                                 "is not writable"),
])
def test_user_errors(argv, expected):
    r = cgadyn_cmd("simulate", "double_pendulum", *argv)
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr + r.stdout
    assert r.stderr.strip().splitlines()[-1].startswith("cgadyn: error: ")
    assert expected in r.stderr, r.stderr


def test_html_without_meshcat_says_how_to_install(monkeypatch, capsys, tmp_path):
    for name in ("meshcat", "meshcat.geometry", "umsgpack"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails as if not installed
    code = cli.main(["simulate", "double_pendulum", "--html", str(tmp_path / "a.html")])
    err = capsys.readouterr().err
    assert code == 2 and not (tmp_path / "a.html").exists()
    assert "cgadyn: error: --html: the HTML animation needs meshcat" in err
    assert "pip install 'cgadyn[viewer]'" in err


@pytest.mark.cli
def test_unknown_robot():
    r = cgadyn_cmd("simulate", "no_such_robot")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "cgadyn: error: unknown robot 'no_such_robot'" in r.stderr


@pytest.mark.parametrize("argv, expected", [
    (["--plot", "/proc/a.png"], "cannot write the plot '/proc/a.png'"),
    (["--html", "/proc/a.html"], "cannot write the animation '/proc/a.html'"),
])
def test_unwritable_outputs_are_refused_before_the_run(monkeypatch, capsys, argv, expected):
    """An output that cannot be written is a user error found before any computing (it was
    "file not found" after the whole simulation)."""
    if argv[0] == "--html":
        pytest.importorskip("meshcat")

    def must_not_run(*args, **kwargs):
        raise AssertionError("the simulation ran before the output was checked")

    monkeypatch.setattr(command, "simulate_chunked", must_not_run)
    code = cli.main(["simulate", "double_pendulum", *argv])
    err = capsys.readouterr().err
    assert code == 2 and f"cgadyn: error: {expected}" in err and "not writable" in err


def test_bench_output_is_checked_before_timing(monkeypatch, capsys, tmp_path):
    import cgadyn.bench

    def must_not_run(*args, **kwargs):
        raise AssertionError("the benchmark ran before --output was checked")

    monkeypatch.setattr(cgadyn.bench, "benchmark", must_not_run)
    code = cli.main(["bench", "double_pendulum", "--output", "/proc/cgadyn-bench"])
    err = capsys.readouterr().err
    assert code == 2 and "cgadyn: error: cannot write the benchmark report into " \
        "'/proc/cgadyn-bench': directory '/proc' is not writable" in err
    (tmp_path / "file").write_text("")
    code = cli.main(["bench", "double_pendulum", "--output", str(tmp_path / "file")])
    assert code == 2 and "exists and is not a directory" in capsys.readouterr().err


def test_html_of_an_mjcf_model(tmp_path, capsys):
    """An MJCF model (no URDF visuals to read) is animated as a skeleton of its joints."""
    pytest.importorskip("meshcat")
    page = tmp_path / "arm.html"
    arm = str(Path(__file__).resolve().parents[1] / "robots" / "slide_arm.xml")
    code = cli.main(["simulate", arm, "--seconds", "0.2", "--html", str(page)])
    out, err = capsys.readouterr()
    assert code == 0, err
    text = page.read_text(encoding="utf-8")
    meta = json.loads(text.split('id="cgadyn-animation">')[1].split("</script>")[0])
    assert meta["robot"] == "slide_arm" and meta["frames"] == 7
    assert len(meta["links"]) >= 4  # the moving links, each animated
    assert meta["floor"] == 0.0  # the floor grid at z = 0, near the arm


def test_a_plot_names_every_coordinate():
    """Above 12 coordinates (solo12: q 19, v 18) every curve is in a legend, in columns."""
    import matplotlib.pyplot as plt

    from cgadyn.sim.plot import trajectory_figure

    solo = cgadyn.load("solo12")
    q0 = cgadyn.neutral(solo)
    traj = simulate(solo, q0, np.zeros(solo.nv), 1e-3, 5)
    fig = trajectory_figure(solo, traj)
    try:
        ax_q, ax_v, _ = fig.axes
        labels = [t.get_text() for t in ax_q.get_legend().get_texts()]
        assert len(labels) == solo.nq == len(set(labels))
        assert labels[:3] == ["root_joint.x", "root_joint.y", "root_joint.z"]
        assert len(ax_v.get_legend().get_texts()) == solo.nv
        colours = {(str(line.get_color()), line.get_linestyle()) for line in ax_q.lines}
        assert len(colours) == solo.nq  # no two curves drawn alike
    finally:
        plt.close(fig)


def test_a_long_run_keeps_every_kth_state(monkeypatch):
    """The chunked run keeps the states of one ``simulate`` call with ``record_every``, and
    a run too long for ``MAX_KEPT`` states keeps every k-th by default."""
    model = cgadyn.load("double_pendulum")
    monkeypatch.setattr(command, "PROGRESS_AFTER", 0.0)
    chunked = command.simulate_chunked(model, Q0, V0, 1e-3, 1537, "rk4", None, every=100)
    traj = simulate(model, Q0, V0, 1e-3, 1537, record_every=100)
    assert chunked.completed == 1537 and len(chunked.t) == 17
    for key in ("q", "v", "a", "energy"):
        np.testing.assert_array_equal(getattr(chunked, key), getattr(traj, key), err_msg=key)
    np.testing.assert_allclose(chunked.t, traj.t, rtol=1e-14)
    from cgadyn.sim.rollout import kept_rows

    every = command.record_every(10 ** 8, None)
    assert kept_rows(10 ** 8, every) <= command.MAX_KEPT < kept_rows(10 ** 8, every - 1)
    assert command.record_every(1000, None) == 1 and command.record_every(1000, 7) == 7


@pytest.mark.slow
@pytest.mark.cli
def test_a_floating_robot_under_pd_falls():
    """The PD controller of the command drives the joints, never the free base: solo12 falls
    (no ground yet), its base by about g t² / 2."""
    r = cgadyn_cmd("simulate", "solo12", "--controller", "pd", "--seconds", "0.3", "--json",
                   "--record-every", "50", "--no-progress")
    assert r.returncode == 0, r.stderr
    out = strict_json(r.stdout)
    q = np.array(out["q"])
    assert len(q) == 7 and out["record_every"] == 50
    assert q[0, 2] - q[-1, 2] == pytest.approx(0.5 * 9.81 * 0.3 ** 2, rel=0.05)
    assert out["actuated"] == [False] * 6 + [True] * 12
    assert np.all(np.array(out["gains"]["kp"])[:6] == 0.0)


@pytest.mark.cli
@pytest.mark.parametrize("value", ["0", "-3", "2.5", "x"])
def test_record_every_must_be_a_positive_integer(value):
    r = cgadyn_cmd("simulate", "double_pendulum", "--record-every", value)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "argument --record-every: expected a positive integer" in r.stderr


@pytest.mark.slow
def test_solo12_stands_on_the_ground_and_lands_when_dropped(capsys):
    """``--ground``: solo12 starts on its feet and its PD (gains for a standing robot) holds
    it: the contact forces carry its weight; ``--drop 0.1`` lands it on the same height."""
    runs = {}
    for extra in ([], ["--drop", "0.1"]):
        assert cli.main(["simulate", "solo12", "--ground", "--controller", "pd", "--seconds",
                         "1", "--json", "--no-progress", *extra]) == 0
        runs[bool(extra)] = out = strict_json(capsys.readouterr().out)
        assert out["integrator"] == "semi_implicit_euler" and out["completed"] == 1000
        z = np.array(out["q"])[:, 2]
        assert np.ptp(z[500:]) < 1e-4
        force = np.array(out["contact_force"])
        assert force[-1, 2] == pytest.approx(out["weight"], rel=1e-6)
        assert np.abs(force[-1, :2]).max() < 1e-4 * out["weight"]  # settling still
    standing, dropped = runs[False], runs[True]
    assert dropped["q0"][2] - standing["q0"][2] == pytest.approx(0.1, abs=1e-12)
    assert dropped["q_final"][2] == pytest.approx(standing["q_final"][2], abs=1e-3)
    assert np.array(dropped["contact_count"])[0] == 0  # it starts in the air


def test_talos_stands_on_soft_soles(capsys):
    """``--soft``: talos_reduced on compliant soles (1e5 N/m a point) under its PD for 1 s:
    the run completes, its soles sink by about a millimetre and hold it, and the summary
    names the soles."""
    argv = ["simulate", "talos_reduced", "--ground", "--soft", "1e5", "--controller", "pd",
            "--seconds", "1", "--no-progress"]
    assert cli.main([*argv, "--json"]) == 0
    out = strict_json(capsys.readouterr().out)
    assert out["soft"] == 1e5 and out["completed"] == 1000
    assert 2e-4 < out["q0"][2] - out["q_final"][2] < 5e-3
    assert np.array(out["contact_count"])[-1] >= 6
    assert cli.main(argv) == 0
    assert "ground (soft soles, 100000 N/m a point): " in capsys.readouterr().out


@pytest.mark.slow
def test_the_ant_falls_and_is_pushed_around_by_random_controls(capsys):
    """Gymnasium's ant on the ground under uniform random controls: the run completes, its
    legs touch the ground, and the seed fixes the controls (two runs agree to the bit)."""
    argv = ["simulate", "gymnasium:ant", "--ground", "--controls", "random", "--seed", "3",
            "--seconds", "0.5", "--dt", "0.005", "--json", "--no-progress"]
    outs = []
    for _ in range(2):
        assert cli.main(argv) == 0
        outs.append(strict_json(capsys.readouterr().out))
    out = outs[0]
    assert out["completed"] == 100 and out["seed"] == 3 and out["energy_drift"] is None
    assert max(out["contact_count"]) > 0
    np.testing.assert_array_equal(outs[0]["q"], outs[1]["q"])


def test_the_dm_control_quadruped_stands_under_pd(capsys):
    """dm_control's quadruped (its hips' yaw joints carry no link: each is the first of a
    body's chain of joints) under the command's PD on the ground: the gains take each
    joint's own frame, and the robot is held up by its legs (its base above its start's
    half height after 0.3 s)."""
    argv = ["simulate", "dm_control:quadruped", "--ground", "--controller", "pd",
            "--seconds", "0.3", "--json", "--no-progress"]
    assert cli.main(argv) == 0
    captured = capsys.readouterr()
    out = strict_json(captured.out)  # what the model leaves out: one line each on stderr
    assert "cgadyn: warning: 'dm_control:quadruped': the world's geoms 'terrain'" \
        in captured.err  # its height field; its actuators are read (tests/test_activation.py)
    assert "the actuators" not in captured.err
    assert out["completed"] == 300 and max(out["contact_count"]) > 0
    z = np.asarray(out["q"])[:, 2]
    assert z[-1] > 0.5 * z[0]
