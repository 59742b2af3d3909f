"""Benchmark cgadyn against Pinocchio (and pygafro): panda, ur5, anymal, solo12, talos.

Writes validation/results/benchmark_<robot>.{md,json,png} per robot and a summary
validation/results/benchmark.{md,json} with both robots' tables, the machine, the git
commit and what the numbers say about where the time goes. Timing on a shared machine is
noisy: the libraries alternate case by case and every figure is a median over repeats.

    python validation/benchmark.py [--repeats R] [--robots panda ur5 anymal solo12 talos]

``--spherical-humanoid`` times, instead, issue 33's humanoid of spherical joints: Pinocchio's
``buildSampleModelHumanoid`` (free flyer) with each hip, each shoulder and the neck one
``JointModelSpherical`` in place of its chain of revolute joints, against the sample
humanoid itself in the same run, and writes ``benchmark_spherical_humanoid.{md,json}``
(with ``benchmark_humanoid_spherical.*`` and ``benchmark_humanoid_revolute.*``, one per
model); the issue's targets: single rnea, aba and crba at most 0.7x Pinocchio's time,
batches at most 0.6x its ``*InParallel``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

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


SPHERICAL = {"shoulder1_joint": ("shoulder2_joint", "shoulder3_joint"),
             "head1_joint": ("head2_joint",)}
"""The sample humanoid's joints that lead a chain made one spherical joint (its legs' and
arms' ``shoulder`` joints, the neck's ``head`` joints), and the joints they absorb."""
SPHERICAL_TARGETS = {"single": 0.7, "batch_parallel": 0.6}
"""Issue 33's targets for the humanoid of spherical joints, as ratios cgadyn / Pinocchio."""


def spherical_humanoid():
    """Pinocchio's ``buildSampleModelHumanoid(True)`` with every chain of ``SPHERICAL`` one
    ``JointModelSpherical`` at the chain's first joint, carrying the chain's bodies (the
    chain's joints sit at one point, so at q = 0 they are where the sample model has them);
    the other joints, limits and bodies as the sample model has them."""
    import pinocchio as pin

    sample = pin.buildSampleModelHumanoid(True)
    pm = pin.Model()
    pm.name = "humanoid_spherical"
    absorbed = {f"{side}{tail}" for side in ("rleg_", "lleg_", "rarm_", "larm_", "")
                for tails in SPHERICAL.values() for tail in tails}
    new, below = {0: 0}, {0: pin.SE3.Identity()}  # sample joint -> joint, body placement
    for i in range(1, sample.njoints):
        name, parent = sample.names[i], sample.parents[i]
        X = below[parent] * sample.jointPlacements[i]
        if name in absorbed:  # carried by the spherical joint its chain became
            new[i], below[i] = new[parent], X
        else:
            joint = sample.joints[i]
            if any(name.endswith(lead) for lead in SPHERICAL):
                joint, lo, hi = pin.JointModelSpherical(), -np.ones(4), np.ones(4)
            else:
                q = slice(joint.idx_q, joint.idx_q + joint.nq)
                lo, hi = sample.lowerPositionLimit[q], sample.upperPositionLimit[q]
            nv = joint.nv
            new[i] = pm.addJoint(new[parent], joint, X, name, np.full(nv, 1e3),
                                 np.full(nv, 1e3), lo, hi)
            below[i] = pin.SE3.Identity()
        pm.appendBodyToJoint(new[i], sample.inertias[i], below[i])
        pm.addBodyFrame(name.replace("_joint", "_body"), new[i], below[i], 0)
    return pm


def _spherical_humanoid_run(args) -> int:
    """``--spherical-humanoid``: both humanoids timed, one after the other, in this run."""
    import numba
    import pinocchio as pin

    from cgadyn import from_pinocchio
    from cgadyn.bench.measure import _benchmark

    sample = pin.buildSampleModelHumanoid(True)
    sample.name = "humanoid_revolute"
    threads = numba.get_num_threads()
    results, md = {}, ["# cgadyn benchmark: a humanoid of spherical joints (issue 33)", "",
                       "`python validation/benchmark.py --spherical-humanoid"
                       f" --repeats {args.repeats}`", "",
                       "Pinocchio's `buildSampleModelHumanoid` (free flyer) with each hip, "
                       "each shoulder and the neck one `JointModelSpherical` "
                       "(`humanoid_spherical`, nv 35), and the sample humanoid itself "
                       "(`humanoid_revolute`, the same tree with those joints as chains of "
                       "revolute joints, nv 34), converted by `cgadyn.from_pinocchio`. "
                       "Ratios are cgadyn / Pinocchio in the same run: below 1 means cgadyn "
                       "is faster. Issue 33's targets for the spherical humanoid: single "
                       f"rnea, aba and crba at most {SPHERICAL_TARGETS['single']}x Pinocchio, "
                       f"batches at most {SPHERICAL_TARGETS['batch_parallel']}x its "
                       "`*InParallel` (rnea and aba: Pinocchio has no crbaInParallel). The "
                       "per-model tables below judge against the project-wide targets "
                       "instead.", ""]
    summary = ["| model | nv | single rnea | single aba | single crba | "
               "batch 4096 rnea / InParallel | batch 4096 aba / InParallel | targets met |",
               "|---|---:|---:|---:|---:|---:|---:|---|"]
    for pm in (spherical_humanoid(), sample):
        model = from_pinocchio(pm)
        numba.set_num_threads(threads)  # _benchmark leaves one thread, for its compute rows
        res = _benchmark(model, pm, [1, 64, 4096], threads, args.repeats, False)
        results[pm.name] = res
        write_report(res, args.output, stem=f"benchmark_{pm.name}")
        single = [res["ratios"]["single"][op]["pinocchio"] for op in ("rnea", "aba", "crba")]
        batch = [res["ratios"]["batch"]["4096"][op]["pinocchio_parallel"]
                 for op in ("rnea", "aba")]
        met = (all(r <= SPHERICAL_TARGETS["single"] for r in single)
               and all(r <= SPHERICAL_TARGETS["batch_parallel"] for r in batch))
        summary.append(f"| {pm.name} | {model.nv} | "
                       + " | ".join(f"{r:.2f}" for r in single + batch)
                       + f" | {'yes' if met else 'no'} |")
        md += [f"## {pm.name} ({res['base']} base, nv = {res['nv']})", "", format_tables(res),
               ""]
        print(f"{pm.name}:\n{format_tables(res)}", flush=True)
    m = results["humanoid_spherical"]["machine"]
    md += ["## Machine", "", f"- CPU: {m['cpu']}, {m['cores']} cores; {m['threads']} threads "
           "for cgadyn batches and Pinocchio InParallel",
           f"- Python {m['python']}, numpy {m['numpy']}, numba {m['numba']}, Pinocchio "
           f"{m['pinocchio']}, cgadyn {m['cgadyn']}",
           f"- git commit: {m['commit']}", f"- date: {m['date']}; {m['platform']}",
           f"- load average (1/5/15 min) at the end: {m['load_average']} on {m['cores']} cores",
           f"- medians over {args.repeats} repeats, libraries alternating case by case", ""]
    head = md.index("## humanoid_spherical (free flyer base, nv = 35)")
    md[head:head] = ["## Issue 33's targets", "", *summary, ""]
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "benchmark_spherical_humanoid.md").write_text("\n".join(md))
    (args.output / "benchmark_spherical_humanoid.json").write_text(
        dumps(results, indent=1) + "\n")
    print("\n".join(summary))
    print(f"wrote {args.output}/benchmark_spherical_humanoid.md")
    return 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--robots", nargs="+", default=["panda", "ur5", "anymal", "solo12", "talos"])
    p.add_argument("--repeats", type=int, default=11)
    p.add_argument("--output", type=Path, default=OUT)
    p.add_argument("--spherical-humanoid", action="store_true",
                   help="time issue 33's humanoid of spherical joints and the sample "
                   "humanoid instead of --robots")
    args = p.parse_args(argv)
    if args.spherical_humanoid:
        return _spherical_humanoid_run(args)
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
