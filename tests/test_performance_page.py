"""``docs/performance.md`` is generated from the recorded runs in ``validation/results/``:
the committed page is what ``tools/generate_performance.py`` writes now, its ``--check``
fails once a result changes, and every figure of its benchmark tables is the JSON's."""

from __future__ import annotations

import importlib.util
import json
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _generator():
    spec = importlib.util.spec_from_file_location(
        "generate_performance", ROOT / "tools" / "generate_performance.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_committed_page_is_fresh():
    gen = _generator()
    assert gen.TARGET.read_text() == gen.generate(), "run python tools/generate_performance.py"


def test_check_fails_when_a_recorded_result_changes(tmp_path, monkeypatch, capsys):
    gen = _generator()
    results = tmp_path / "results"
    shutil.copytree(gen.RESULTS, results)
    monkeypatch.setattr(gen, "RESULTS", results)
    monkeypatch.setattr(gen, "TARGET", tmp_path / "performance.md")
    assert gen.main(["--check"]) == 1  # no page yet
    assert gen.main([]) == 0
    assert gen.main(["--check"]) == 0
    (results / "simulate.md").write_text("# Rollouts\n\n| what | µs |\n|---|---:|\n| x | 1.0 |\n")
    assert gen.main(["--check"]) == 1
    assert "stale" in capsys.readouterr().err


def test_the_benchmark_tables_are_the_recorded_figures():
    """Each robot's single-call entry is its recorded cgadyn and Pinocchio µs and ratio."""
    gen = _generator()
    page = gen.generate()
    results = json.loads((gen.RESULTS / gen.BENCHMARK).read_text())
    for robot, res in results.items():
        assert res["machine"]["date"] in page
        for op, us in res["single_us"].items():
            ratio = res["ratios"]["single"][op]["pinocchio"]
            assert f"{us['cgadyn']:.2f} / {us['pinocchio']:.2f} ({ratio:.2f})" in page, (robot, op)


def test_a_recorded_markdown_result_is_copied_with_its_links_into_the_results_folder(
        tmp_path, monkeypatch):
    gen = _generator()
    monkeypatch.setattr(gen, "RESULTS", tmp_path)
    (tmp_path / "startup.md").write_text(
        "# Startup\n\nMachine: x. ![plot](startup.png)\n\n## Cold\n\n| a | s |\n|---|---:|\n"
        "| validate | 12.5 |\n")
    page = gen.generate()
    assert "| validate | 12.5 |" in page
    assert "](../validation/results/startup.png)" in page
    assert "\n### Cold\n" in page
    assert "Single calls and batches" not in page  # no benchmark.json recorded there
