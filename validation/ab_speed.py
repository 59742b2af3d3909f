"""Single calls and one-thread batches of this checkout against another git revision, in
one run: the check that a change to compiled code keeps every call within 5 % (issue 32).

For each robot and each tree (this checkout's ``src``; ``--baseline REV`` checked out and
built in a temporary directory, as ``startup.py`` does), a worker process in its own
``NUMBA_CACHE_DIR`` compiles, then times the single calls (``cgadyn.rnea``, ``aba``,
``crba``, ``minverse``, ``rnea_derivatives``, ``aba_derivatives``, ``forward_kinematics``)
and batches of 4096 samples on one thread (``rnea``, ``aba``, ``crba``, ``minverse``,
``aba_derivatives``). The trees alternate, ``--repeats`` times; each figure is the median
of its repeats, each repeat the best of five timed loops.
Writes ``validation/results/ab_speed.{md,json}`` (``--output NAME``: ``NAME.{md,json}``).
``--new REV`` measures the tree of git revision REV in place of this checkout: the cost of
one change, e.g. issue 33's joints (``--new ba08c3f --baseline 1ce7229``, the i33-joints
branch against its base).

    python validation/ab_speed.py --baseline REV [--new REV] [--robots panda ur5 ...]
                                  [--repeats N] [--output NAME]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from startup import OUT, ROOT, machine_cpu, source_tree  # noqa: E402

ROBOTS = ("panda", "ur5", "anymal", "solo12", "talos")

WORKER = r"""
import json, sys, time
import numba
import numpy as np
import cgadyn

numba.set_num_threads(1)
robot = sys.argv[1]
m = cgadyn.load(robot)
rng = np.random.default_rng(0)
q = cgadyn.random_configuration(m, rng=rng)
v, a = rng.standard_normal(m.nv), rng.standard_normal(m.nv)
B = 4096
Q = np.stack([q] * B)
V, A = np.tile(v, (B, 1)), np.tile(a, (B, 1))
single = {
    "rnea": lambda: cgadyn.rnea(m, q, v, a),
    "aba": lambda: cgadyn.aba(m, q, v, a),
    "crba": lambda: cgadyn.crba(m, q),
    "minverse": lambda: cgadyn.minverse(m, q),
    "rnea_derivatives": lambda: cgadyn.rnea_derivatives(m, q, v, a),
    "aba_derivatives": lambda: cgadyn.aba_derivatives(m, q, v, a),
    "forward_kinematics": lambda: cgadyn.forward_kinematics(m, q),
}
batch = {
    "rnea": lambda: cgadyn.rnea(m, Q, V, A),
    "aba": lambda: cgadyn.aba(m, Q, V, A),
    "crba": lambda: cgadyn.crba(m, Q),
    "minverse": lambda: cgadyn.minverse(m, Q),
    "aba_derivatives": lambda: cgadyn.aba_derivatives(m, Q, V, A),
}
out = {}
for kind, calls, n, per in (("single", single, 2000, 1), ("batch", batch, 3, B)):
    for name, f in calls.items():
        f()
        best = float("inf")
        for _ in range(5):
            t = time.perf_counter()
            for _ in range(n):
                f()
            best = min(best, (time.perf_counter() - t) / n / per)
        out[f"{kind} {name}"] = best * 1e6
print(json.dumps(out))
"""


def run(src: Path, cache: Path, robot: str) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache),
           "CGADYN_CACHE_DIR": str(cache / "models"), "PYTHONDONTWRITEBYTECODE": "1",
           "CGADYN_PROGRESS": "0"}
    proc = subprocess.run([sys.executable, "-c", WORKER, robot], env=env, cwd=cache,
                          capture_output=True, text=True)
    if proc.returncode != 0:  # the worker's own error, not only its exit status
        raise SystemExit(f"ab_speed: the worker for {robot} on {src} failed "
                         f"(exit status {proc.returncode}):\n{proc.stderr.strip()}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, help="the git revision to compare with")
    parser.add_argument("--robots", nargs="+", default=list(ROBOTS))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--new", help="a git revision to measure instead of this checkout")
    parser.add_argument("--output", default="ab_speed",
                        help="the results' name in validation/results/ (default ab_speed)")
    args = parser.parse_args()
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True, check=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "src"],
                           capture_output=True, text=True, check=True).stdout.strip()
    new_tag = (f"revision ({args.new})" if args.new else
               f"this checkout ({head}{' + edits' if dirty else ''})")
    old_tag = f"baseline ({args.baseline})"
    found: dict[str, dict[str, dict[str, list[float]]]] = {}
    with tempfile.TemporaryDirectory() as tmp_:
        tmp = Path(tmp_)
        trees = {new_tag: source_tree(args.new, tmp), old_tag: source_tree(args.baseline, tmp)}
        caches = {tag: tmp / f"cache-{i}" for i, tag in enumerate(trees)}
        for c in caches.values():
            c.mkdir()
        for robot in args.robots:
            for _ in range(args.repeats):
                for tag, src in trees.items():
                    for key, us in run(src, caches[tag], robot).items():
                        found.setdefault(robot, {}).setdefault(key, {}).setdefault(
                            tag, []).append(us)
    what = f"Revision {args.new}" if args.new else "This checkout"
    lines = [f"# {what} against a baseline: single calls and one-thread batches", "",
             f"Generated by `python validation/ab_speed.py --baseline {args.baseline} "
             f"{'--new ' + args.new + ' ' if args.new else ''}"
             f"--robots {' '.join(args.robots)} --repeats {args.repeats}"
             f"{' --output ' + args.output if args.output != 'ab_speed' else ''}` on "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"
             f", {machine_cpu()}, {os.cpu_count()} cores. µs per call (single) or per "
             f"sample (batches of 4096 on one thread); medians of {args.repeats} alternating "
             f"runs, each the best of five loops. Ratio: {what.lower()}'s time over the "
             f"baseline's.", ""]
    worst = 0.0
    for robot, cases in found.items():
        lines += [f"## {robot}", "", f"| call | {new_tag} | {old_tag} | ratio |",
                  "|---|---:|---:|---:|"]
        for key, per in cases.items():
            new, old = (sorted(per[t])[len(per[t]) // 2] for t in (new_tag, old_tag))
            worst = max(worst, new / old)
            lines.append(f"| {key} | {new:.3f} | {old:.3f} | {new / old:.3f} |")
        lines.append("")
    lines.append(f"Largest ratio: {worst:.3f}.")
    OUT.mkdir(exist_ok=True)
    (OUT / f"{args.output}.md").write_text("\n".join(lines) + "\n")
    (OUT / f"{args.output}.json").write_text(json.dumps(found, indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
