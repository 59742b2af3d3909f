"""Benchmark cgadyn against Pinocchio (and pygafro): panda, ur5, anymal, solo12, talos.

Writes validation/results/benchmark_<robot>.{md,json,png} per robot and a summary
validation/results/benchmark.{md,json} with both robots' tables, the machine, the git
commit and what the numbers say about where the time goes. Timing on a shared machine is
noisy: the libraries alternate case by case and every figure is a median over repeats.

    python validation/benchmark.py [--repeats R] [--robots panda ur5 anymal solo12 talos]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from cgadyn._json import dumps
from cgadyn.bench import benchmark, format_tables, write_report

OUT = Path(__file__).parent / "results"


def notes(res: dict) -> list[str]:
    """Where the time goes, read off one robot's result."""
    big = str(max(res["batches"]))
    lines = []
    for op in ("rnea", "aba", "crba"):
        single = res["single_us"][op]["cgadyn"]
        comp = res["compute_us_per_sample"][op]["cgadyn"]
        pin_single = res["single_us"][op]["pinocchio"]
        pin_comp = res["compute_us_per_sample"][op].get("pinocchio_parallel")
        pc = f", Pinocchio's {pin_comp:.2f} µs" if pin_comp else ""
        lines.append(
            f"- {op}: a single call costs {single:.2f} µs of which about {comp:.2f} µs is "
            f"compute (batch of {res['compute_batch']} on one thread{pc}); the other "
            f"{single - comp:.2f} µs ({100 * (single - comp) / single:.0f} %) are the cost of the "
            f"call from Python (the wrapper's routing of the input and allocation of the result, "
            f"numba's type check and unboxing of its array arguments, caches cold after the "
            f"interpreter). "
            f"Pinocchio's whole single call is {pin_single:.2f} µs.")
    b1 = res["batch_us_per_sample"].get("1", {}).get("aba", {})
    if b1:
        lines.append(
            f"- A (1, n) batch costs {b1['cgadyn']:.0f} µs (cgadyn) and "
            f"{b1.get('pinocchio_parallel', float('nan')):.0f} µs (Pinocchio InParallel) for "
            "aba: a float64 (1, n) batch goes straight to the one-sample entry, on views of "
            "its row, and the wrapper then checks that the result is finite; larger batches "
            "go to the compiled batch entry, which wakes the thread pool for 8 samples or "
            "more. Use the single-sample call for one sample.")
    r = res["ratios"]["batch"][big]["aba"]
    lines.append(
        f"- At B = {big}, cgadyn aba runs at {r['pinocchio_loop']:.2f}x the time of a Python "
        f"loop over Pinocchio and {r['pinocchio_parallel']:.2f}x Pinocchio's abaInParallel.")
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--robots", nargs="+", default=["panda", "ur5", "anymal", "solo12", "talos"])
    p.add_argument("--repeats", type=int, default=11)
    p.add_argument("--output", type=Path, default=OUT)
    args = p.parse_args(argv)
    results, md = {}, ["# cgadyn benchmark", "",
                       "Ratios are cgadyn / other: below 1 means cgadyn is faster. Targets are "
                       "the issue's, reported, not asserted.", ""]
    for robot in args.robots:
        res = benchmark(robot, repeats=args.repeats)
        results[robot] = res
        write_report(res, args.output, stem=f"benchmark_{robot}")
        md += [f"## {robot} ({res['base']} base, nv = {res['nv']})", "", format_tables(res),
               "#### Where the time goes", "", *notes(res), "",
               f"![{robot}](benchmark_{robot}.png)", ""]
        print(f"{robot}:\n{format_tables(res)}", flush=True)
    m = results[args.robots[0]]["machine"]
    md += ["## Machine", "", f"- CPU: {m['cpu']}, {m['cores']} cores; {m['threads']} threads "
           "for cgadyn batches and Pinocchio InParallel",
           f"- Python {m['python']}, numpy {m['numpy']}, numba {m['numba']}, Pinocchio "
           f"{m['pinocchio']}, pygafro {m['pygafro']}, cgadyn {m['cgadyn']}",
           f"- git commit: {m['commit']}", f"- date: {m['date']}; {m['platform']}",
           f"- load average (1/5/15 min) at the end: {m['load_average']} on {m['cores']} cores",
           f"- medians over {args.repeats} repeats, libraries alternating case by case; other "
           "jobs shared the machine", ""]
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "benchmark.md").write_text("\n".join(md))
    (args.output / "benchmark.json").write_text(dumps(results, indent=1) + "\n")
    print(f"wrote {args.output}/benchmark.md")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
