"""``simulate-body`` subcommand: add_parser/run, text and JSON output, plot, bad input."""

import argparse
import json

import pytest

from cgadyn.cli import main
from cgadyn.commands import simulate_body as cli


def parse(argv):
    parser = argparse.ArgumentParser(prog="cgadyn")
    sub = parser.add_subparsers(dest="command")
    cli.add_parser(sub)
    return parser.parse_args(["simulate-body", *argv])


def test_json_summary(capsys):
    args = parse(["--dim", "2", "--steps", "50", "--no-contact", "--no-damping", "--json"])
    assert cli.run(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["dim"] == 2 and summary["steps"] == 50
    assert abs(summary["energy_drift"]) < 1e-8
    assert {"final_motor", "final_rate", "energy_final", "motor_norm_error"} <= set(summary)


def test_text_summary_and_plot(tmp_path, capsys):
    png = tmp_path / "body.png"
    args = parse(["--dim", "4", "--steps", "20", "--integrator", "euler", "--plot", str(png)])
    assert cli.run(args) == 0
    out = capsys.readouterr().out
    assert "4D PGA" in out and "energy drift" in out
    assert png.stat().st_size > 1000


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--dim", "7"], "dimension must be an integer in 1..4"),
        (["--integrator", "leapfrog"], "unknown integrator"),
        (["--dt", "-1"], "dt must be finite and > 0"),
    ],
)
def test_bad_arguments_exit_2(argv, message, capsys):
    assert main(["simulate-body", *argv, "--steps", "1"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.startswith("cgadyn: error:")


@pytest.mark.parametrize("plot, message", [("no_such_dir/x.png", "does not exist"),
                                            ("x.notaformat", "not a format matplotlib")])
def test_bad_plot_path_exit_2_before_simulating(plot, message, tmp_path, capsys):
    assert main(["simulate-body", "--steps", "1", "--plot", str(tmp_path / plot)]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and captured.out == ""


def test_main_entry_point(capsys):
    assert main(["simulate-body", "--dim", "1", "--steps", "5"]) == 0
    assert "1D PGA" in capsys.readouterr().out
