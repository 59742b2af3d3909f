"""How long a first run takes: cold and warm first calls, an edit's recompilation, a cold
``cgadyn validate``, each in a fresh cache directory, for this checkout and optionally for
another git revision measured in the same run (old and new alternating).

For each source tree (this checkout; ``--baseline REV``, checked out and built in a
temporary directory), in fresh ``NUMBA_CACHE_DIR`` and ``CGADYN_CACHE_DIR`` directories:

- ``cold aba`` / ``cold rnea``: a new process's first ``cgadyn.aba`` (then ``rnea``) on the
  panda, with nothing cached; ``warm aba``: the same in a second process;
- ``rnea after editing aba.py``: a comment appended to ``algorithms/aba.py`` of a copy of
  the package, then a new process's first ``rnea`` (numba's cache keeps what the edit does
  not reach, so this loads from the cache);
- ``cold validate`` (with ``--validate``): ``cgadyn validate`` on the default robot, with the
  time until its first output on stderr (a progress line begun) and its first whole line.

With ``--breakdown``, also where the cold compilation goes (``compile_breakdown.py``: numba's
compile events, CPU seconds of the process) for a first ``aba`` and a cold ``validate``, per
kind of compiled function, each tree in a fresh cache directory.

Writes ``validation/results/startup.{md,json}``.

    python validation/startup.py [--baseline REV] [--variant NAME=VALUE] [--validate]
                                 [--breakdown] [--repeats N]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def machine_cpu() -> str:
    """``cgadyn.bench.measure.cpu_model``, imported here: this script times cold imports in
    processes of their own and keeps cgadyn out of its own until it reports."""
    from cgadyn.bench.measure import cpu_model

    return cpu_model()

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "validation" / "results"

FIRST_CALLS = """
import sys, time
import numpy as np
t = time.perf_counter()
import cgadyn
m = cgadyn.load("panda")
q = np.full(m.nq, 0.3)
times = {"import and load": time.perf_counter() - t}
for name in sys.argv[1:]:
    t = time.perf_counter()
    getattr(cgadyn, name)(m, q, q, q)
    times[name] = time.perf_counter() - t
print(times)
"""


def source_tree(rev: str | None, tmp: Path) -> Path:
    """The ``src`` directory of this checkout, or of ``rev`` checked out and built in ``tmp``
    (the C extension built in place)."""
    if rev is None:
        return ROOT / "src"
    tree = tmp / f"rev-{rev}"
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True,
                             capture_output=True).stdout
    tree.mkdir()
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    subprocess.run([sys.executable, "setup.py", "-q", "build_ext", "--inplace"], cwd=tree,
                   check=True, capture_output=True)
    return tree / "src"


def copy_package(src: Path, tmp: Path, name: str) -> Path:
    """A copy of the ``src`` tree (without caches), so that edits leave the original alone."""
    dst = tmp / name
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    return dst


EXTRA: dict[str, str] = {}
"""Variables of the tree being measured (``--variant``)."""


def env(src: Path, cache: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache),
            "CGADYN_CACHE_DIR": str(cache / "models"), "PYTHONDONTWRITEBYTECODE": "1",
            "CGADYN_PROGRESS": "1", **EXTRA}


def first_calls(src: Path, cache: Path, *names: str) -> dict[str, float]:
    run = subprocess.run([sys.executable, "-c", FIRST_CALLS, *names], env=env(src, cache),
                         capture_output=True, text=True, check=True, cwd=cache)
    return eval(run.stdout.strip().splitlines()[-1])


def validate(src: Path, cache: Path) -> dict[str, float]:
    """A cold ``cgadyn validate``: its total time, the time to its first output on stderr
    (a progress line starts, "cgadyn: compiling ...", when a compilation does) and to its
    first whole stderr line (when that compilation ends)."""
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "cgadyn.cli", "validate", "--json"],
                            env=env(src, cache), cwd=cache, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, bufsize=0)
    first = line = None
    while byte := proc.stderr.read(1):
        now = time.perf_counter() - start
        first = now if first is None else first
        line = now if line is None and byte == b"\n" else line
    proc.wait()
    total = time.perf_counter() - start
    return {"cold validate": total,
            "first stderr output": first if first is not None else float("nan"),
            "first stderr line": line if line is not None else float("nan"),
            "validate status": proc.returncode}


def measure(src: Path, tmp: Path, tag: str, with_validate: bool) -> dict[str, float]:
    caches = tmp / f"cache-{tag}-{time.monotonic_ns()}"
    cold, edit = caches / "cold", caches / "edit"
    for d in (cold, edit):
        d.mkdir(parents=True)
    row = {}
    c = first_calls(src, cold, "aba", "rnea")
    row |= {"cold import and load": c["import and load"], "cold aba": c["aba"],
            "cold rnea (after aba)": c["rnea"]}
    row["warm aba"] = first_calls(src, cold, "aba")["aba"]
    copy = copy_package(src, caches, "edited")
    row["cold rnea (alone)"] = first_calls(copy, edit, "rnea")["rnea"]
    aba = copy / "cgadyn" / "algorithms" / "aba.py"
    aba.write_text(aba.read_text() + "\n# an edit\n")
    row["rnea after editing aba.py"] = first_calls(copy, edit, "rnea")["rnea"]
    if with_validate:
        v = caches / "validate"
        v.mkdir()
        row |= validate(src, v)
    shutil.rmtree(caches, ignore_errors=True)
    return row


KINDS = (
    ("cores (`<name>_core`, one sample)", lambda f: f.endswith("_core")),
    ("one-sample entries (`_single`, `_native`)",
     lambda f: ".entries." in f and f.endswith(("_single", "_native"))),
    ("parallel batch entries (`_batch`)", lambda f: ".entries." in f and f.endswith("_batch")),
    ("lane groups (`*_lanes`)", lambda f: "_lanes." in f),
    ("everything else", lambda f: True),
)
"""How the breakdown sorts compiled functions, the first kind that matches."""

BREAKDOWN = Path(__file__).with_name("compile_breakdown.py")


def breakdown(src: Path, tmp: Path, tag: str, workload: str) -> dict:
    """``compile_breakdown.py workload`` in fresh cache directories: its JSON."""
    cache = tmp / f"breakdown-{tag}-{workload}-{time.monotonic_ns()}"
    cache.mkdir(parents=True)
    run = subprocess.run([sys.executable, str(BREAKDOWN), workload],
                         env=env(src, cache) | {"CGADYN_PROGRESS": "0"},
                         capture_output=True, text=True, check=True, cwd=cache)
    shutil.rmtree(cache, ignore_errors=True)
    return json.loads(run.stdout.strip().splitlines()[-1])


def kind(function: str) -> str:
    return next(name for name, test in KINDS if test(function))


def breakdown_table(found: dict[str, dict[str, dict]]) -> list[str]:
    """Per kind of function: specialisations compiled and their exclusive CPU seconds, for
    each tree and workload; then, for each, what it compiled from Python."""
    cols = [(tag, w) for tag, per in found.items() for w in per]
    lines = ["| kind: count, CPU s | " + " | ".join(f"{w}, {tag}" for tag, w in cols) + " |",
             "|---|" + "---:|" * len(cols)]
    for name, _ in KINDS:
        cells = []
        for tag, w in cols:
            recs = [r for r in found[tag][w]["records"] if kind(r["function"]) == name]
            cells.append(f"{len(recs)}, {sum(r['exclusive'] for r in recs):.1f}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    cells = []
    for tag, w in cols:
        recs = found[tag][w]["records"]
        cells.append(f"{len(recs)}, {sum(r['exclusive'] for r in recs):.1f}")
    lines.append("| all compiled | " + " | ".join(cells) + " |")
    lines.append("| whole process (CPU s; its compilations only if unfinished) | " + " | ".join(
        f"{found[tag][w]['cpu']:.1f}" for tag, w in cols) + " |")
    for tag, w in cols:
        top = [r for r in found[tag][w]["records"] if r["depth"] == 0 and r["inclusive"] >= 0.5]
        lines += ["", f"`{w}`, {tag}: what it compiled from Python, in order (CPU s, with the "
                      "functions compiled inside):", ""]
        lines += [f"- {r['inclusive']:.1f} `{r['function'].removeprefix('cgadyn.')}`"
                  for r in top]
    return lines


BREAKDOWN_TEXT = (
    "numba's compile events (`validation/compile_breakdown.py`) in a fresh cache: per kind of "
    "compiled function, the specialisations compiled and the CPU seconds of the process spent "
    "compiling them (exclusive of the functions compiled inside them). CPU time still grows "
    "with the load of the machine (the same core has taken 2.5 times the CPU seconds in one "
    "run as in another at the same time): compare the kinds within a column, and the counts "
    "across columns.")


def tabulate_records(records: list[str]) -> int:
    """``--records``: the breakdown section alone, from runs recorded before."""
    found: dict[str, dict[str, dict]] = {}
    for record in records:
        label, workload_file = record.split("=", 1)
        workload, _, path = workload_file.partition(":")
        lines = [json.loads(x) for x in Path(path).read_text().splitlines() if x.strip()]
        data = lines[-1] if "workload" in lines[-1] else {  # a run stopped before its end
            "workload": workload, "records": lines, "unfinished": True,
            "cpu": sum(r["exclusive"] for r in lines)}  # its compilations only
        found.setdefault(label + (" (unfinished)" if data.get("unfinished") else ""),
                         {})[workload] = data
    machine = f"{machine_cpu()}, {os.cpu_count()} cores"
    when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    lines = ["# First runs: where the cold compilation goes", "",
             "Generated by `python validation/startup.py "
             + " ".join(f"--records '{r.partition('=')[0]}=...'" for r in records)
             + f"` on {when}, {machine}, from `compile_breakdown.py` runs each in fresh "
             "cache directories, old and new run at the same time (other jobs were running). "
             + BREAKDOWN_TEXT, "", *breakdown_table(found), ""]
    OUT.mkdir(exist_ok=True)
    (OUT / "startup.md").write_text("\n".join(lines))
    (OUT / "startup.json").write_text(json.dumps({"machine": machine, "date": when,
                                                  "breakdown": found}, indent=1) + "\n")
    print("\n".join(lines))
    return 0


def table(results: dict[str, list[dict]]) -> list[str]:
    keys = list(next(iter(results.values()))[0])
    tags = list(results)
    lines = ["| s | " + " | ".join(tags) + " |", "|---|" + "---:|" * len(tags)]
    for k in keys:
        cells = []
        for tag in tags:
            vals = sorted(r[k] for r in results[tag])
            cells.append(f"{vals[len(vals) // 2]:.1f}")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", help="a git revision to measure in the same run")
    parser.add_argument("--validate", action="store_true", help="also a cold cgadyn validate")
    parser.add_argument("--breakdown", action="store_true",
                        help="also where a cold aba and a cold validate spend compiling")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--variant", action="append", default=[], metavar="NAME=VALUE",
                        help="also this checkout with an environment variable set "
                             "(e.g. CGADYN_INLINE=llvm); may be repeated")
    parser.add_argument("--records", action="append", default=[],
                        metavar="LABEL=WORKLOAD:FILE",
                        help="only tabulate the output of a compile_breakdown.py run made "
                             "before (in a fresh cache), under LABEL; may be repeated")
    args = parser.parse_args()
    if args.records:
        return tabulate_records(args.records)
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory(prefix="cgadyn-startup-") as t:
        tmp = Path(t)
        trees = {f"this checkout ({head})": (source_tree(None, tmp), {})}
        for variant in args.variant:
            name, _, value = variant.partition("=")
            trees[f"{head}, {variant}"] = (trees[f"this checkout ({head})"][0], {name: value})
        if args.baseline:
            trees[f"baseline ({args.baseline})"] = (source_tree(args.baseline, tmp), {})
        results: dict[str, list[dict]] = {tag: [] for tag in trees}
        for r in range(args.repeats):
            for i, (tag, (src, extra)) in enumerate(trees.items()):
                EXTRA.clear()
                EXTRA.update(extra)
                row = measure(src, tmp, f"{r}-{i}", args.validate)
                print(tag, json.dumps(row), flush=True)
                results[tag].append(row)
        found: dict[str, dict[str, dict]] = {tag: {} for tag in trees}
        if args.breakdown:
            for workload in ("aba", "validate"):
                for i, (tag, (src, extra)) in enumerate(trees.items()):
                    EXTRA.clear()
                    EXTRA.update(extra)
                    found[tag][workload] = breakdown(src, tmp, str(i), workload)
                    print(tag, workload, round(found[tag][workload]["cpu"], 1), flush=True)
    machine = f"{machine_cpu()}, {os.cpu_count()} cores"
    when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    lines = ["# First runs: cold and warm", "",
             f"Generated by `python validation/startup.py"
             f"{' --baseline ' + args.baseline if args.baseline else ''}"
             f"{' --validate' if args.validate else ''}"
             f"{''.join(' --variant ' + v for v in args.variant)} --repeats {args.repeats}` "
             f"on {when}, "
             f"{machine} (medians of {args.repeats}; other jobs may have been running). "
             "Seconds; each column in its own fresh cache directories.", "", *table(results),
             ""]
    if args.breakdown:
        lines += ["## Where the cold compilation goes", "", BREAKDOWN_TEXT, "",
                  *breakdown_table(found), ""]
    OUT.mkdir(exist_ok=True)
    (OUT / "startup.md").write_text("\n".join(lines))
    (OUT / "startup.json").write_text(json.dumps({"machine": machine, "date": when,
                                                  "results": results, "breakdown": found},
                                                 indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
