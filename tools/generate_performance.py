"""Generate ``docs/performance.md`` from the benchmark runs recorded in ``validation/results/``.

Timings live in the recorded results, each written by the script that measured it, with the
machine and the date where that script records them; the docs and the docstrings say what
the code does and why, not how fast it was. This page gathers the recorded runs in one place:
for each, what it measures, the command that produced it, the machine and date as recorded,
and its figures and ratios (against Pinocchio, its Python loop, MuJoCo). Every number on the
page is read from a results file: the benchmark's JSON is tabulated here, the other runs'
markdown tables and notes are copied as they were written. Nothing is measured here.

Usage::

    python tools/generate_performance.py            # rewrite docs/performance.md
    python tools/generate_performance.py --check    # exit 1 if the committed page is stale

Rerun it after any script in ``validation/`` rewrites its results.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path
from typing import NamedTuple

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "validation" / "results"
TARGET = ROOT / "docs" / "performance.md"
LINK = "../validation/results"
"""The results folder as a link from ``docs/``."""

BENCHMARK = "benchmark.json"
OPS = ("rnea", "aba", "crba", "rnea_derivatives", "aba_derivatives", "minverse")


class Recorded(NamedTuple):
    """A markdown result written by a validation script, copied onto the page as it is."""

    file: str
    title: str
    command: str
    """Markdown: the command in backticks, with any note."""
    measures: str


RECORDED = (
    Recorded("batch_isolated_all.md", "Batches with each library alone in its process",
             "`python validation/batch_isolated.py --robot ROBOT`, once per robot",
             "µs per sample of a batch of 4096 (rnea, aba), each library timed in a fresh "
             "process of its own, so that no other thread pool spins beside it"),
    Recorded("simulate.md", "Rollouts: cgadyn.simulate, a Python loop over pin.aba, "
             "mujoco.rollout, dask", "`python validation/simulate_benchmark.py`",
             "µs per rollout-step of RK4 rollouts on the panda, against the same integrator "
             "over Pinocchio's ABA from Python and MuJoCo's rollout, and dask's worker "
             "processes against one process"),
    Recorded("contact.md", "Speed against MuJoCo: rollouts with ground contact",
             "`python validation/contact_benchmark.py` (`--rollouts`, `--steps` to shrink it, "
             "`--quick` for a smoke run)",
             "µs per rollout-step of `cgadyn.simulate(..., world=World(), collisions=...)` "
             "against `mujoco.rollout` on Gymnasium's Ant under random controls and solo12 "
             "dropped under joint PD, at the same time step and thread count, with the deepest "
             "penetration and the base height at the end of both engines beside the times"),
    Recorded("ik_panda.md", "Inverse kinematics on the panda",
             "`python validation/ik_benchmark.py`",
             "µs per solve, success rate and iterations of cgadyn's compiled "
             "Levenberg-Marquardt against Pinocchio's closed-loop inverse kinematics in Python"),
    Recorded("startup.md", "Cold and warm start",
             "`python validation/startup.py`",
             "the time of a first call and of `cgadyn validate` with an empty cache and "
             "with a filled one"),
)
"""The markdown results, in page order; a file not (yet) recorded is left out."""


def _link(name: str) -> str:
    return f"[`validation/results/{name}`]({LINK}/{name})"


def _ratio_table(results: dict, robots: list[str], cell) -> list[str]:
    """A table with one row per algorithm and one column per robot; ``cell(res, op)`` is
    the text of an entry, or None where the run has no such figure."""
    head = "| algorithm | " + " | ".join(
        f"{r} (nv {results[r]['nv']})" for r in robots) + " |"
    rows = [head, "|---|" + "---:|" * len(robots)]
    for op in OPS:
        cells = [cell(results[r], op) for r in robots]
        if any(c is not None for c in cells):
            rows.append(f"| {op} | " + " | ".join(c or "—" for c in cells) + " |")
    return rows


def _single(res: dict, op: str) -> str | None:
    us = res["single_us"].get(op)
    ratio = res["ratios"]["single"].get(op, {}).get("pinocchio")
    if not us or ratio is None:
        return None
    return f"{us['cgadyn']:.2f} / {us['pinocchio']:.2f} ({ratio:.2f})"


def _batch(key: str):
    def cell(res: dict, op: str) -> str | None:
        big = str(max(res["batches"]))
        ratio = res["ratios"]["batch"][big].get(op, {}).get(key)
        if ratio is None:
            return None
        us = res["batch_us_per_sample"][big][op]
        return f"{us['cgadyn']:.3f} / {us[key]:.3f} ({ratio:.2f})"
    return cell


def _machines(results: dict, robots: list[str]) -> list[str]:
    """The machine of each robot's run, one line per distinct machine, as recorded."""
    lines, seen = [], {}
    for r in robots:
        m = results[r]["machine"]
        key = (m["cpu"], m["cores"], m["threads"], m["python"], m["numpy"], m["numba"],
               m["pinocchio"], m["cgadyn"], m["platform"], m["commit"])
        seen.setdefault(key, []).append((r, m["date"], m["load_average"]))
    for key, runs in seen.items():
        cpu, cores, threads, py, npv, nb, pin, cg, plat, commit = key
        lines += [f"- {cpu}, {cores} cores, {threads} threads for batches; {plat}; Python "
                  f"{py}, numpy {npv}, numba {nb}, Pinocchio {pin}, cgadyn {cg} at commit "
                  f"{commit}"]
        lines += [f"  - {r}: {date}, load average at the end {load}" for r, date, load in runs]
    return lines


def benchmark_section(results: dict) -> list[str]:
    """The tables of ``validation/benchmark.py``'s summary JSON."""
    robots = list(results)
    first = results[robots[0]]
    big = max(first["batches"])
    return [
        "## Single calls and batches against Pinocchio", "",
        f"Source: {_link(BENCHMARK)} (tables and plots per robot: `benchmark_<robot>.md`, "
        f"`.json`, `.png` beside it; the summary with notes: {_link('benchmark.md')}).", "",
        "Command: `python validation/benchmark.py` (the five robots below; `cgadyn bench "
        "ROBOT` times one).", "",
        f"What it measures: µs per call of a single call from Python, warmed up, and µs per "
        f"sample of a batch of {big}, cgadyn's batch call against a Python loop over "
        f"Pinocchio and Pinocchio's `*InParallel` ({first['threads']} threads each); medians "
        f"over {first['repeats']} repeats, the libraries alternating case by case in one "
        "process. Each entry reads `cgadyn / other (ratio)`; a ratio below 1 means cgadyn "
        "takes less time.", "",
        "Machine and date, as recorded:", "", *_machines(results, robots), "",
        "### Single call, µs: cgadyn / Pinocchio (ratio)", "",
        *_ratio_table(results, robots, _single), "",
        f"### Batch of {big}, µs per sample: cgadyn / Python loop over Pinocchio (ratio)", "",
        *_ratio_table(results, robots, _batch("pinocchio_loop")), "",
        f"### Batch of {big}, µs per sample: cgadyn / Pinocchio `*InParallel` (ratio)", "",
        *_ratio_table(results, robots, _batch("pinocchio_parallel")), "",
    ]


_RELATIVE = re.compile(r"\]\((?![a-z]+:|/|#|\.\./)([^)\s]+)\)")


def recorded_section(rec: Recorded, text: str) -> list[str]:
    """A markdown result as it was written: its title replaced by ours, its headings one
    level deeper, its relative links pointing into the results folder."""
    lines = text.rstrip("\n").splitlines()
    if lines and lines[0].startswith("# "):
        lines = lines[1:]
    body = []
    for line in lines:
        if line.startswith("#"):
            line = "#" + line
        body.append(_RELATIVE.sub(rf"]({LINK}/\1)", line))
    while body and not body[0].strip():
        body.pop(0)
    return [f"## {rec.title}", "", f"Source: {_link(rec.file)}.", "",
            f"Command: {rec.command}.", "", f"What it measures: {rec.measures}.", "",
            "As recorded (the machine and the date are those the file states; where it "
            "states none, they are not known):", "", *body, ""]


def generate() -> str:
    """The page, from the files in ``validation/results/`` as they are now."""
    out = ["# Performance", "",
           "<!-- generated by tools/generate_performance.py from validation/results/: "
           "do not edit -->", "",
           "What the recorded benchmark runs in `validation/results/` measured, gathered from "
           "the files each validation script wrote; every figure below is copied or "
           "tabulated from those files, with the machine and the date they record. A run on "
           "another machine gives other times: rerun the command of a section to measure "
           "yours, then `python tools/generate_performance.py` to refresh this page.", ""]
    bench = RESULTS / BENCHMARK
    if bench.exists():
        out += benchmark_section(json.loads(bench.read_text()))
    for rec in RECORDED:
        path = RESULTS / rec.file
        if path.exists():
            out += recorded_section(rec, path.read_text())
    return "\n".join(out).rstrip("\n") + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if the page is stale")
    args = parser.parse_args(argv)
    text = generate()
    if args.check:
        if (TARGET.read_text() if TARGET.exists() else "") != text:
            print(f"{TARGET} is stale: run python tools/generate_performance.py",
                  file=sys.stderr)
            return 1
        print(f"{TARGET} is up to date")
        return 0
    TARGET.write_text(text)
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
