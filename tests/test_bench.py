"""Smoke test of the benchmark harness: structure and positive times, never speed."""

from __future__ import annotations

import json

import pytest

from cgadyn import bench
from cgadyn.cli import main

OPS = bench.OPS


@pytest.fixture(scope="module")
def result() -> dict:
    return bench.benchmark("double_pendulum", batches=(1, 8), repeats=1, quick=True)


def test_keys_and_positive_times(result: dict) -> None:
    for key in ("robot", "nv", "threads", "first_call_ms", "single_us", "batch_us_per_sample",
                "compute_us_per_sample", "ratios", "targets", "machine", "pygafro"):
        assert key in result
    assert result["robot"] == "double_pendulum" and result["nv"] == 2
    for op in OPS:
        assert result["single_us"][op]["cgadyn"] > 0
        assert result["single_us"][op]["pinocchio"] > 0
        assert result["first_call_ms"][op]["single"] > 0
        for b in ("1", "8"):
            t = result["batch_us_per_sample"][b][op]
            assert t["cgadyn"] > 0 and t["pinocchio_loop"] > 0
            assert (t.get("pinocchio_parallel", 1.0) > 0) and (op in ("rnea", "aba")) == (
                "pinocchio_parallel" in t)
        assert result["compute_us_per_sample"][op]["cgadyn"] > 0
    assert result["single_us"]["aba"].get("pygafro") is None  # pygafro only for panda
    assert all(t["ratio"] is None or t["ratio"] > 0 for t in result["targets"])


def test_report_files_and_json(result: dict, tmp_path) -> None:
    files = bench.write_report(result, tmp_path)
    assert [p.name for p in files] == ["benchmark.md", "benchmark.json", "benchmark.png"]
    assert all(p.stat().st_size > 0 for p in files)
    assert "Pinocchio" in (tmp_path / "benchmark.md").read_text()
    assert json.loads((tmp_path / "benchmark.json").read_text())["robot"] == "double_pendulum"


def test_floating_base_and_bad_arguments(capsys) -> None:
    res = bench.benchmark("solo", batches=(4,), repeats=1, quick=True)
    assert (res["base"], res["nq"], res["nv"]) == ("free flyer", 15, 14)
    assert all(res["single_us"][op]["pinocchio"] > 0 for op in OPS)
    assert main(["bench", "double_pendulum", "--batch", "2", "--threads", "999"]) == 2
    assert "threads must be in 1.." in capsys.readouterr().err
    with pytest.raises(ValueError, match="batch"):
        bench.benchmark("double_pendulum", batches=(0,))


def test_plot_tick_labels_do_not_overlap() -> None:
    """The bar chart's names under the bars stay apart (the derivatives' long names ran into
    each other)."""
    import matplotlib.pyplot as plt

    from cgadyn.bench import report

    libs = {"cgadyn": 1.0, "pinocchio": 2.0, "pinocchio_loop": 3.0, "pinocchio_parallel": 0.5}
    res = {"robot": "panda", "threads": 2, "batches": [1, 4096],
           "single_us": {op: dict(libs) for op in OPS},
           "batch_us_per_sample": {"4096": {op: dict(libs) for op in OPS}}}
    fig = report.figure(res)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            boxes = [t.get_window_extent(renderer) for t in ax.get_xticklabels()]
            assert len(boxes) == len(OPS)
            for a, b in zip(boxes, boxes[1:], strict=False):
                assert not a.overlaps(b), (a, b)
    finally:
        plt.close(fig)
