"""``cgadyn bench``: time rnea / aba / crba against Pinocchio (and pygafro where installed).

One run alternates the libraries case by case and reports medians over repeats, so that the
noise of a shared machine hits every library alike:

- single calls from Python (µs per call), warmed up; numba's first call (compile or cache
  load) is reported apart;
- batch throughput (µs per sample) for B samples: cgadyn's batch call, a Python loop over
  Pinocchio, and Pinocchio's ``rneaInParallel`` / ``abaInParallel`` at the same thread count;
- an estimate of pure compute per sample: a batch of 4096 on one thread, divided by 4096.

Ratios are cgadyn / other: below 1 means cgadyn is faster. The issue's targets are printed
next to them, never asserted. The lead wires ``add_parser``/``run`` into the main CLI;
``python -m cgadyn.bench panda`` runs it standalone.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import statistics
import subprocess
import sys
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["add_parser", "run", "benchmark", "format_tables", "write_report"]

OPS = ("rnea", "aba", "crba")
GAFRO_ROBOT = "panda"  # pygafro's FrankaEmikaRobot = panda with the fingers fixed (7 dof)
COMPUTE_BATCH = 4096
TARGETS = {  # the issue's targets, as ratios cgadyn / other
    "single_pinocchio": 1.0,
    "batch_loop": 0.25,
    "batch_parallel": 1.0,
    "fd_pygafro": 0.2,
}


# --------------------------------------------------------------------------- timing


def _timer(fn: Callable, args: Sequence) -> timeit.Timer:
    """A ``timeit.Timer`` calling ``fn(*args)`` with the arguments bound as globals."""
    names = [f"a{i}" for i in range(len(args))]
    stmt = f"f({', '.join(names)})"
    return timeit.Timer(stmt, globals={"f": fn, **dict(zip(names, args, strict=True))})


def _calibrate(timer: timeit.Timer, target_s: float) -> int:
    """Number of calls so that one repeat lasts about ``target_s``."""
    n = 1
    while True:
        t = timer.timeit(n)
        if t >= 0.2 * target_s or n >= 10**7:
            return max(1, round(n * target_s / max(t, 1e-9)))
        n *= 10


def _time_cases(cases: dict[Any, tuple[Callable, Sequence]], repeats: int,
                target_s: float) -> dict[Any, float]:
    """Median seconds per call of every case, the cases alternating within each repeat."""
    timers = {k: _timer(fn, args) for k, (fn, args) in cases.items()}
    numbers = {k: _calibrate(t, target_s) for k, t in timers.items()}
    samples: dict[Any, list[float]] = {k: [] for k in cases}
    for _ in range(repeats):
        for k, t in timers.items():
            samples[k].append(t.timeit(numbers[k]) / numbers[k])
    return {k: statistics.median(v) for k, v in samples.items()}


def _first_call_ms(fn: Callable, args: Sequence) -> float:
    """Wall time of one call in ms (the first call includes numba's compile or cache load)."""
    return 1e3 * timeit.Timer(lambda: fn(*args)).timeit(1)


# --------------------------------------------------------------------------- setup


def _pin_q(pm, q: np.ndarray) -> np.ndarray:
    """Pinocchio configuration(s) from joint angles: continuous joints become (cos, sin)."""
    cols = []
    for j in range(1, pm.njoints):
        x = q[..., pm.joints[j].idx_v]
        cols += [np.cos(x), np.sin(x)] if pm.joints[j].nq == 2 else [x]
    return np.stack(cols, axis=-1)


def _states(nv: int, batch: int, pm, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Random (q, v, a) for ``batch`` samples, cgadyn's rows and Pinocchio's columns."""
    q = rng.uniform(-1.0, 1.0, (batch, nv))
    v = rng.normal(size=(batch, nv))
    a = rng.normal(size=(batch, nv))
    qp = _pin_q(pm, q)
    cols = {k + "F": np.asfortranarray(x.T) for k, x in (("q", qp), ("v", v), ("a", a))}
    return {"q": q, "v": v, "a": a, "qp": qp, **cols, "out": np.zeros((nv, batch), order="F")}


def _gafro(robot: str) -> tuple[Any, str]:
    """pygafro's Franka robot for ``panda``, else None, with a status string."""
    try:
        import pygafro
    except ImportError:
        return None, "not installed"
    if robot != GAFRO_ROBOT:
        return None, f"n/a (pygafro's model is the Franka, compared on {GAFRO_ROBOT})"
    version = getattr(pygafro, "__version__", None) or _dist_version("pygafro")
    return pygafro.FrankaEmikaRobot(), f"pygafro {version} (FrankaEmikaRobot, 7 dof)"


def _dist_version(name: str) -> str:
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "?"


def _single_cases(cg, model, pm, pdata, gafro, s: dict) -> dict[tuple[str, str], tuple]:
    """(op, library) -> (function, args) for one sample."""
    import pinocchio as pin

    q, v, a, qp = s["q"][0], s["v"][0], s["a"][0], s["qp"][0]
    cases = {
        ("rnea", "cgadyn"): (cg.rnea, (model, q, v, a)),
        ("rnea", "pinocchio"): (pin.rnea, (pm, pdata, qp, v, a)),
        ("aba", "cgadyn"): (cg.aba, (model, q, v, a)),
        ("aba", "pinocchio"): (pin.aba, (pm, pdata, qp, v, a)),
        ("crba", "cgadyn"): (cg.crba, (model, q)),
        ("crba", "pinocchio"): (pin.crba, (pm, pdata, qp)),
    }
    if gafro is not None:
        q7, v7, a7 = (np.ascontiguousarray(x[:7]) for x in (q, v, a))
        cases[("rnea", "pygafro")] = (gafro.getJointTorques, (q7, v7, a7))
        cases[("aba", "pygafro")] = (gafro.getJointAccelerations, (q7, v7, a7))
        cases[("crba", "pygafro")] = (gafro.getMassMatrix, (list(q7),))
    return cases


def _loop3(f: Callable, pm, pdata, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> None:
    """A Python loop of ``f(model, data, q[i], v[i], a[i])`` over the samples."""
    for i in range(len(q)):
        f(pm, pdata, q[i], v[i], a[i])


def _loop1(f: Callable, pm, pdata, q: np.ndarray) -> None:
    """A Python loop of ``f(model, data, q[i])`` over the samples."""
    for i in range(len(q)):
        f(pm, pdata, q[i])


def _batch_cases(cg, model, pm, pdata, pool, threads: int, s: dict,
                 parallel_only: bool = False) -> dict[tuple[str, str], tuple]:
    """(op, library) -> (function, args) for a batch of samples."""
    import pinocchio as pin

    q, v, a, qp = s["q"], s["v"], s["a"], s["qp"]
    par = (threads, pool, s["qF"], s["vF"], s["aF"], s["out"])
    cases = {
        ("rnea", "cgadyn"): (cg.rnea, (model, q, v, a)),
        ("rnea", "pinocchio_parallel"): (pin.rneaInParallel, par),
        ("aba", "cgadyn"): (cg.aba, (model, q, v, a)),
        ("aba", "pinocchio_parallel"): (pin.abaInParallel, par),
        ("crba", "cgadyn"): (cg.crba, (model, q)),
    }
    if not parallel_only:
        cases[("rnea", "pinocchio_loop")] = (_loop3, (pin.rnea, pm, pdata, qp, v, a))
        cases[("aba", "pinocchio_loop")] = (_loop3, (pin.aba, pm, pdata, qp, v, a))
        cases[("crba", "pinocchio_loop")] = (_loop1, (pin.crba, pm, pdata, qp))
    return cases


def _nest(flat: dict[tuple[str, str], float], scale: float) -> dict[str, dict[str, float]]:
    """{(op, lib): seconds} -> {op: {lib: seconds * scale}}."""
    out: dict[str, dict[str, float]] = {op: {} for op in OPS}
    for (op, lib), t in flat.items():
        out[op][lib] = t * scale
    return out


# --------------------------------------------------------------------------- benchmark


def benchmark(robot: str = "panda", batches: Sequence[int] = (1, 64, 4096),
              threads: int | None = None, repeats: int | None = None,
              quick: bool = False) -> dict:
    """Time cgadyn against Pinocchio (and pygafro) on ``robot``; returns a JSON-able dict.

    ``threads``: numba and Pinocchio thread count for batches (default
    ``numba.get_num_threads()``). ``repeats``: timed repeats per case (median reported;
    default 11, or 3 with ``quick``). ``quick``: ~1 ms per repeat instead of ~25 ms, and the
    compute estimate uses the largest batch instead of 4096 (for smoke tests).
    """
    import numba

    saved = numba.get_num_threads()
    threads = saved if threads is None else int(threads)
    if not 1 <= threads <= numba.config.NUMBA_NUM_THREADS:
        raise ValueError(f"threads must be in 1..{numba.config.NUMBA_NUM_THREADS}, got {threads}")
    if not batches or min(batches) < 1:
        raise ValueError(f"batch sizes must be positive, got {list(batches)}")
    repeats = (3 if quick else 11) if repeats is None else int(repeats)
    if repeats < 1:
        raise ValueError(f"repeats must be >= 1, got {repeats}")
    numba.set_num_threads(threads)
    try:
        return _benchmark(robot, [int(b) for b in batches], threads, repeats, quick)
    finally:
        numba.set_num_threads(saved)


def _benchmark(robot: str, batches: list[int], threads: int, repeats: int,
               quick: bool) -> dict:
    import numba
    import pinocchio as pin

    import cgadyn as cg
    from cgadyn.multibody import robot_path

    model = cg.load(robot)
    pm = pin.buildModelFromUrdf(str(robot_path(robot)))
    pdata = pm.createData()
    pool = pin.ModelPool(pm, threads)
    gafro, gafro_status = _gafro(robot)
    rng = np.random.default_rng(0)
    target_s = 0.001 if quick else 0.025
    res: dict[str, Any] = {
        "robot": robot, "nv": model.nv, "threads": threads, "repeats": repeats,
        "quick": quick, "batches": batches, "pygafro": gafro_status,
    }
    s1 = _states(model.nv, 2, pm, rng)
    res["first_call_ms"] = _first_calls(cg, model, s1)
    single = _time_cases(_single_cases(cg, model, pm, pdata, gafro, s1), repeats, target_s)
    res["single_us"] = _nest(single, 1e6)
    res["batch_us_per_sample"] = {}
    for b in batches:
        s = _states(model.nv, b, pm, rng)
        cases = _batch_cases(cg, model, pm, pdata, pool, threads, s)
        res["batch_us_per_sample"][str(b)] = _nest(_time_cases(cases, repeats, target_s), 1e6 / b)
    nc = max(batches) if quick else COMPUTE_BATCH
    numba.set_num_threads(1)
    s = _states(model.nv, nc, pm, rng)
    cases = _batch_cases(cg, model, pm, pdata, pool, 1, s, parallel_only=True)
    res["compute_batch"] = nc
    res["compute_us_per_sample"] = _nest(_time_cases(cases, repeats, target_s), 1e6 / nc)
    res["ratios"], res["targets"] = _ratios(res)
    res["machine"] = machine_info(threads)
    return res


def _first_calls(cg, model, s: dict) -> dict[str, dict[str, float]]:
    """First single and batch call of each algorithm in this process, in ms."""
    q, v, a = s["q"], s["v"], s["a"]
    args = {"rnea": (q, v, a), "aba": (q, v, a), "crba": (q,)}
    out = {}
    for op in OPS:
        fn = getattr(cg, op)
        single = _first_call_ms(fn, (model, *(x[0] for x in args[op])))
        batch = _first_call_ms(fn, (model, *args[op]))
        out[op] = {"single": single, "batch": batch}
    return out


def _ratio(x: float | None, y: float | None) -> float | None:
    return None if x is None or y is None else x / y


def _ratios(res: dict) -> tuple[dict, list[dict]]:
    """Ratios cgadyn / other, and the issue's targets next to the measured ratios."""
    single = {op: {lib: _ratio(t["cgadyn"], t[lib]) for lib in t if lib != "cgadyn"}
              for op, t in res["single_us"].items()}
    batch = {b: {op: {lib: _ratio(t["cgadyn"], t[lib]) for lib in t if lib != "cgadyn"}
                 for op, t in ops.items()}
             for b, ops in res["batch_us_per_sample"].items()}
    targets = [_target(f"single-call {op} vs Pinocchio", single[op].get("pinocchio"),
                       TARGETS["single_pinocchio"]) for op in OPS]
    big = str(max(res["batches"]))
    for op in OPS:
        targets.append(_target(f"batch {big} {op} vs Pinocchio Python loop",
                               batch[big][op].get("pinocchio_loop"), TARGETS["batch_loop"]))
    for op in ("rnea", "aba"):
        targets.append(_target(f"batch {big} {op} vs Pinocchio InParallel ({res['threads']} thr)",
                               batch[big][op].get("pinocchio_parallel"),
                               TARGETS["batch_parallel"]))
    targets.append(_target("single-call FD (aba) vs pygafro", single["aba"].get("pygafro"),
                           TARGETS["fd_pygafro"]))
    return {"single": single, "batch": batch}, targets


def _target(what: str, ratio: float | None, limit: float) -> dict:
    met = None if ratio is None else bool(ratio <= limit)
    return {"what": what, "ratio": ratio, "target": f"<= {limit:g}", "met": met}


def machine_info(threads: int) -> dict[str, Any]:
    """CPU model, cores, versions, thread count, date and git commit of this run."""
    import numba
    import pinocchio as pin

    import cgadyn

    return {
        "cpu": _cpu_model(), "cores": os.cpu_count(), "threads": threads,
        "python": platform.python_version(), "numpy": np.__version__,
        "numba": numba.__version__, "pinocchio": pin.__version__,
        "pygafro": _dist_version("pygafro"), "cgadyn": _dist_version("cgadyn"),
        "platform": platform.platform(), "commit": _git_commit(Path(cgadyn.__file__).parent),
        "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds"),
        "load_average": _load_average(),
    }


def _load_average() -> str:
    """1/5/15-minute load average (other jobs on the machine slow parallel regions)."""
    try:
        return " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _git_commit(where: Path) -> str:
    """Short commit hash, with a note if src/ has uncommitted changes; 'unknown' outside git."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=where, text=True,
                              capture_output=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "."], cwd=where,
                               text=True, capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    files = [line[3:].strip() for line in dirty.splitlines() if line.strip()]
    return head + (f" + uncommitted changes in {', '.join(files)}" if files else "")


# --------------------------------------------------------------------------- report

LIB_NAMES = {"cgadyn": "cgadyn", "pinocchio": "Pinocchio", "pygafro": "pygafro",
             "pinocchio_loop": "Pinocchio loop", "pinocchio_parallel": "Pinocchio InParallel"}


def _f(x: float | None, fmt: str = ".2f") -> str:
    return "—" if x is None else format(x, fmt)


def _met(ratio: float | None, limit: float) -> str:
    if ratio is None:
        return "—"
    return "yes" if ratio <= limit else "no"


def _single_table(res: dict) -> list[str]:
    g = "not installed" if res["pygafro"] == "not installed" else "n/a"
    lines = [
        f"### Single call from Python, µs per call ({res['robot']}, {res['nv']} dof)", "",
        "| op | cgadyn | Pinocchio | pygafro | cgadyn/Pinocchio | target | met "
        "| cgadyn/pygafro | target | met |",
        "|---|---:|---:|---:|---:|---:|---|---:|---:|---|",
    ]
    for op in OPS:
        t, r = res["single_us"][op], res["ratios"]["single"][op]
        rp, rg = r.get("pinocchio"), r.get("pygafro")
        gt = _f(t.get("pygafro")) if t.get("pygafro") is not None else g
        tg = f"<= {TARGETS['fd_pygafro']:g}" if op == "aba" else ""
        mg = _met(rg, TARGETS["fd_pygafro"]) if op == "aba" else ""
        lines.append(f"| {op} | {_f(t['cgadyn'])} | {_f(t['pinocchio'])} | {gt} | {_f(rp)} "
                     f"| <= {TARGETS['single_pinocchio']:g} "
                     f"| {_met(rp, TARGETS['single_pinocchio'])} | {_f(rg)} | {tg} | {mg} |")
    return lines


def _batch_table(res: dict) -> list[str]:
    thr, tl, tp = res["threads"], TARGETS["batch_loop"], TARGETS["batch_parallel"]
    lines = [
        f"### Batch throughput, µs per sample ({thr} threads for cgadyn and InParallel)", "",
        "| op | B | cgadyn | Pinocchio loop | Pinocchio InParallel | cgadyn/loop | target "
        "| cgadyn/InParallel | target |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for op in OPS:
        for b, ops in res["batch_us_per_sample"].items():
            t, r = ops[op], res["ratios"]["batch"][b][op]
            lines.append(
                f"| {op} | {b} | {_f(t['cgadyn'], '.3f')} | {_f(t.get('pinocchio_loop'), '.3f')} "
                f"| {_f(t.get('pinocchio_parallel'), '.3f')} | {_f(r.get('pinocchio_loop'))} "
                f"| <= {tl:g} | {_f(r.get('pinocchio_parallel'))} "
                f"| {'<= ' + format(tp, 'g') if op != 'crba' else '—'} |")
    return lines


def _compute_table(res: dict) -> list[str]:
    nc = res["compute_batch"]
    lines = [
        f"### Where the time goes: compute per sample (batch of {nc} on 1 thread / {nc}) "
        "vs a single call", "",
        "| op | cgadyn compute | Pinocchio compute (InParallel, 1 thread) | cgadyn single call "
        "| cgadyn call overhead | cgadyn first call, single / batch (ms; compile or cache load) |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for op in OPS:
        c = res["compute_us_per_sample"][op]
        s = res["single_us"][op]["cgadyn"]
        fc = res["first_call_ms"][op]
        lines.append(f"| {op} | {_f(c['cgadyn'], '.3f')} | {_f(c.get('pinocchio_parallel'), '.3f')}"
                     f" | {_f(s)} | {_f(s - c['cgadyn'])} | {fc['single']:.1f} / "
                     f"{fc['batch']:.1f} |")
    return lines


def _target_table(res: dict) -> list[str]:
    lines = ["### The issue's targets (ratio cgadyn / other; below 1: cgadyn faster)", "",
             "| target | measured ratio | target | met |", "|---|---:|---:|---|"]
    for t in res["targets"]:
        met = "—" if t["met"] is None else ("yes" if t["met"] else "no")
        lines.append(f"| {t['what']} | {_f(t['ratio'])} | {t['target']} | {met} |")
    return lines


def format_tables(res: dict) -> str:
    """The result's tables as markdown (also readable as plain text)."""
    parts = [_single_table(res), _batch_table(res), _compute_table(res), _target_table(res)]
    return "\n\n".join("\n".join(p) for p in parts) + "\n"


def _machine_lines(res: dict) -> list[str]:
    m = res["machine"]
    return [
        "### Machine", "",
        f"- CPU: {m['cpu']}, {m['cores']} cores; threads for batches: {m['threads']}",
        f"- Python {m['python']}, numpy {m['numpy']}, numba {m['numba']}, "
        f"Pinocchio {m['pinocchio']}, cgadyn {m['cgadyn']}",
        f"- pygafro: {res['pygafro']}",
        f"- git commit: {m['commit']}",
        f"- date: {m['date']}; {m['platform']}; load average at the end: {m['load_average']}",
        f"- medians over {res['repeats']} repeats, libraries alternating case by case"
        + (" (quick mode)" if res["quick"] else ""),
    ]


def write_report(res: dict, outdir: str | Path, stem: str = "benchmark") -> list[Path]:
    """Write ``<stem>.md``, ``<stem>.json`` and ``<stem>.png`` into ``outdir``."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    md = out / f"{stem}.md"
    md.write_text(f"## cgadyn benchmark: {res['robot']}\n\n" + format_tables(res) + "\n"
                  + "\n".join(_machine_lines(res)) + "\n")
    js = out / f"{stem}.json"
    js.write_text(json.dumps(res, indent=1) + "\n")
    png = out / f"{stem}.png"
    plot(res, png)
    return [md, js, png]


def plot(res: dict, path: str | Path) -> None:
    """Bar chart (log scale): single-call µs and per-sample µs at the largest batch."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    big = str(max(res["batches"]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    _bars(axes[0], res["single_us"], ("cgadyn", "pinocchio", "pygafro"),
          f"single call, µs ({res['robot']})")
    _bars(axes[1], res["batch_us_per_sample"][big],
          ("cgadyn", "pinocchio_loop", "pinocchio_parallel"),
          f"batch {big}, µs per sample ({res['threads']} threads)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _bars(ax, table: dict[str, dict[str, float]], libs: Sequence[str], title: str) -> None:
    width = 0.8 / len(libs)
    for k, lib in enumerate(libs):
        ys = [table[op].get(lib) for op in OPS]
        xs = [i + (k - (len(libs) - 1) / 2) * width for i in range(len(OPS))]
        pts = [(x, y) for x, y in zip(xs, ys, strict=True) if y is not None]
        if pts:
            ax.bar(*zip(*pts, strict=True), width=width, label=LIB_NAMES[lib])
    ax.set_xticks(range(len(OPS)), OPS)
    ax.set_yscale("log")
    ax.set_title(title)
    ax.legend()
    ax.grid(axis="y", which="both", alpha=0.3)


# --------------------------------------------------------------------------- CLI


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register the ``bench`` subcommand on an ``add_subparsers()`` object."""
    p = subparsers.add_parser(
        "bench",
        help="time rnea/aba/crba against Pinocchio (and pygafro)",
        description="Time single calls and batches of rnea, aba and crba in cgadyn and "
        "Pinocchio (and pygafro's Franka for panda), alternating libraries, medians over "
        "repeats. Ratios are cgadyn / other: below 1 means cgadyn is faster.",
    )
    _add_arguments(p)
    p.set_defaults(func=run)
    return p


def _add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("robot", nargs="?", default="panda", help="robot name (default panda)")
    p.add_argument("--batch", type=int, nargs="+", default=[1, 64, 4096], metavar="B",
                   help="batch sizes (default 1 64 4096)")
    p.add_argument("--threads", type=int, default=None,
                   help="threads for batches (default numba.get_num_threads())")
    p.add_argument("--repeats", type=int, default=None, help="timed repeats (default 11)")
    p.add_argument("--quick", action="store_true", help="short repeats, for a smoke run")
    p.add_argument("--json", action="store_true", help="print the result dict as JSON")
    p.add_argument("--output", metavar="DIR",
                   help="write benchmark.md, benchmark.json and benchmark.png into DIR")


def run(args: argparse.Namespace) -> int:
    """Run the benchmark and print the tables (or JSON); returns the exit code."""
    try:
        res = benchmark(args.robot, args.batch, args.threads, args.repeats, args.quick)
    except (ValueError, KeyError, FileNotFoundError) as exc:
        print(f"bench: error: {exc}", file=sys.stderr)
        return 2
    if args.output:
        res["files"] = [str(p) for p in write_report(res, args.output)]
    if args.json:
        print(json.dumps(res, indent=1))
    else:
        print(format_tables(res))
        if args.output:
            print("wrote " + ", ".join(res["files"]))
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="cgadyn")
    sub = parser.add_subparsers(dest="command", required=True)
    add_parser(sub)
    return run(parser.parse_args(["bench", *(sys.argv[1:] if argv is None else argv)]))


if __name__ == "__main__":
    sys.exit(main())
