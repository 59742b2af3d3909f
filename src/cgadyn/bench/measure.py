"""Measuring for ``cgadyn bench``: rnea, aba, crba and the derivatives against Pinocchio
(and pygafro where installed); ``report`` turns the result into tables and a plot.

One run alternates the libraries case by case and reports medians over repeats, so that the
noise of a shared machine hits every library alike:

- single calls from Python (µs per call), warmed up; numba's first call (compile or cache
  load) is reported apart;
- batch throughput (µs per sample) for B samples: cgadyn's batch call, a Python loop over
  Pinocchio, and Pinocchio's ``rneaInParallel`` / ``abaInParallel`` at the same thread count
  (Pinocchio has none for crba and the derivatives);
- an estimate of pure compute per sample: a batch of 4096 on one thread, divided by 4096.

States come from ``cgadyn.oracle`` (the same robot in both libraries, free-flyer roots
included). Ratios are cgadyn / other: below 1 means cgadyn is faster. The issues' targets are
printed next to them, never asserted.
"""

from __future__ import annotations

import datetime as _dt
import os
import platform
import statistics
import subprocess
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .. import oracle

__all__ = ["OPS", "TARGETS", "benchmark", "machine_info"]

OPS = ("rnea", "aba", "crba", "rnea_derivatives", "aba_derivatives", "minverse")
"""Every timed algorithm; Pinocchio's name for each is in ``_PIN``."""
PARALLEL = ("rnea", "aba")
"""The algorithms Pinocchio runs ``*InParallel``."""
GAFRO_ROBOT = "panda"  # pygafro's FrankaEmikaRobot = panda with the fingers fixed (7 dof)
COMPUTE_BATCH = 4096
TARGETS = {  # the issues' targets, as ratios cgadyn / other
    "single_pinocchio": 0.9,  # rnea, aba, crba (hardening issue, "speed margin")
    "single_derivatives": 1.0,  # rnea/aba derivatives, minverse (derivatives issue)
    "batch_loop": 0.25,  # at least 4x a Python loop over Pinocchio
    "batch_parallel": 0.6,  # rnea, aba against *InParallel
    "fd_pygafro": 0.2,
}
_ARGS = {"rnea": "qva", "aba": "qvt", "crba": "q", "rnea_derivatives": "qva",
         "aba_derivatives": "qvt", "minverse": "q"}
"""Which state arrays each algorithm takes: q, v, a (accelerations) or t (torques)."""


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


def _states(model, batch: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Random states for ``batch`` samples (``oracle.sample``): cgadyn's rows, Pinocchio's
    configurations ``qp`` and the column-major copies ``*InParallel`` reads."""
    s = oracle.sample(model, batch, rng)
    qp = oracle.pin_configuration(model, s.q)
    cols = {k + "F": np.asfortranarray(x.T) for k, x in (("q", qp), ("v", s.v), ("a", s.a),
                                                         ("t", s.tau))}
    return {"q": s.q, "v": s.v, "a": s.a, "t": s.tau, "qp": qp, **cols,
            "out": np.zeros((model.nv, batch), order="F")}


def _gafro(model) -> tuple[Any, str]:
    """pygafro's Franka robot for the panda, else None, with a status string."""
    try:
        import pygafro
    except ImportError:
        return None, "not installed"
    if model.name != GAFRO_ROBOT or model.floating_base:
        return None, f"n/a (pygafro's model is the Franka, compared on {GAFRO_ROBOT})"
    version = getattr(pygafro, "__version__", None) or _dist_version("pygafro")
    return pygafro.FrankaEmikaRobot(), f"pygafro {version} (FrankaEmikaRobot, 7 dof)"


def _dist_version(name: str) -> str:
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "?"


def _pin_functions() -> dict[str, Callable]:
    import pinocchio as pin

    return {"rnea": pin.rnea, "aba": pin.aba, "crba": pin.crba,
            "rnea_derivatives": pin.computeRNEADerivatives,
            "aba_derivatives": pin.computeABADerivatives, "minverse": pin.computeMinverse}


def _args(op: str, s: dict, rows, pin_side: bool) -> tuple:
    """The state arguments of ``op`` (rows selected by ``rows``), in either layout."""
    keys = ["qp" if pin_side and k == "q" else k for k in _ARGS[op]]
    return tuple(s[k][rows] for k in keys)


def _single_cases(cg, model, pm, pdata, gafro, s: dict) -> dict[tuple[str, str], tuple]:
    """(op, library) -> (function, args) for one sample."""
    pin = _pin_functions()
    cases = {}
    for op in OPS:
        cases[(op, "cgadyn")] = (getattr(cg, op), (model, *_args(op, s, 0, False)))
        cases[(op, "pinocchio")] = (pin[op], (pm, pdata, *_args(op, s, 0, True)))
    if gafro is not None:
        q7, v7, a7 = (np.ascontiguousarray(s[k][0, :7]) for k in "qva")
        cases[("rnea", "pygafro")] = (gafro.getJointTorques, (q7, v7, a7))
        cases[("aba", "pygafro")] = (gafro.getJointAccelerations, (q7, v7, a7))
        cases[("crba", "pygafro")] = (gafro.getMassMatrix, (list(q7),))
    return cases


def _loop(f: Callable, pm, pdata, *columns: np.ndarray) -> None:
    """A Python loop of ``f(model, data, x[i], ...)`` over the samples."""
    for row in zip(*columns, strict=True):
        f(pm, pdata, *row)


def _batch_cases(cg, model, pm, pdata, pool, threads: int, s: dict,
                 parallel_only: bool = False) -> dict[tuple[str, str], tuple]:
    """(op, library) -> (function, args) for a batch of samples."""
    import pinocchio as pin

    every = slice(None)
    cases = {(op, "cgadyn"): (getattr(cg, op), (model, *_args(op, s, every, False)))
             for op in OPS}
    inparallel = {"rnea": (pin.rneaInParallel, "a"), "aba": (pin.abaInParallel, "t")}
    for op, (f, last) in inparallel.items():
        cases[(op, "pinocchio_parallel")] = (f, (threads, pool, s["qF"], s["vF"], s[last + "F"],
                                                 s["out"]))
    if not parallel_only:
        for op, f in _pin_functions().items():
            cases[(op, "pinocchio_loop")] = (_loop, (f, pm, pdata, *_args(op, s, every, True)))
    return cases


def _nest(flat: dict[tuple[str, str], float], scale: float) -> dict[str, dict[str, float]]:
    """{(op, lib): seconds} -> {op: {lib: seconds * scale}}."""
    out: dict[str, dict[str, float]] = {op: {} for op in OPS}
    for (op, lib), t in flat.items():
        out[op][lib] = t * scale
    return out


# --------------------------------------------------------------------------- benchmark


def benchmark(robot="panda", batches: Sequence[int] = (1, 64, 4096),
              threads: int | None = None, repeats: int | None = None,
              quick: bool = False, floating_base: bool | None = None) -> dict:
    """Time cgadyn against Pinocchio (and pygafro) on ``robot`` (a name, a URDF path or
    URDF text, with its natural base unless ``floating_base`` says otherwise); returns a
    JSON-ready dict.

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
    model, pm = oracle.models(robot, floating_base)
    if model.nv == 0:
        raise ValueError(f"{model.name!r} has no degree of freedom: nothing to time")
    numba.set_num_threads(threads)
    try:
        return _benchmark(model, pm, [int(b) for b in batches], threads, repeats, quick)
    finally:
        numba.set_num_threads(saved)


def _benchmark(model, pm, batches: list[int], threads: int, repeats: int,
               quick: bool) -> dict:
    import numba
    import pinocchio as pin

    import cgadyn as cg

    pdata = pm.createData()
    pool = pin.ModelPool(pm, threads)
    gafro, gafro_status = _gafro(model)
    rng = np.random.default_rng(0)
    target_s = 0.001 if quick else 0.025
    res: dict[str, Any] = {
        "robot": model.name, "nq": model.nq, "nv": model.nv,
        "base": "free flyer" if model.floating_base else "fixed", "threads": threads,
        "repeats": repeats, "quick": quick, "batches": batches, "pygafro": gafro_status,
    }
    s1 = _states(model, 2, rng)
    res["first_call_ms"] = _first_calls(cg, model, s1)
    single = _time_cases(_single_cases(cg, model, pm, pdata, gafro, s1), repeats, target_s)
    res["single_us"] = _nest(single, 1e6)
    res["batch_us_per_sample"] = {}
    for b in batches:
        s = _states(model, b, rng)
        cases = _batch_cases(cg, model, pm, pdata, pool, threads, s)
        res["batch_us_per_sample"][str(b)] = _nest(_time_cases(cases, repeats, target_s), 1e6 / b)
    nc = max(batches) if quick else COMPUTE_BATCH
    numba.set_num_threads(1)
    s = _states(model, nc, rng)
    cases = _batch_cases(cg, model, pm, pdata, pool, 1, s, parallel_only=True)
    res["compute_batch"] = nc
    res["compute_us_per_sample"] = _nest(_time_cases(cases, repeats, target_s), 1e6 / nc)
    res["ratios"], res["targets"] = _ratios(res)
    res["machine"] = machine_info(threads)
    return res


def _first_calls(cg, model, s: dict) -> dict[str, dict[str, float]]:
    """First single and batch call of each algorithm in this process, in ms."""
    out = {}
    for op in OPS:
        fn = getattr(cg, op)
        single = _first_call_ms(fn, (model, *_args(op, s, 0, False)))
        batch = _first_call_ms(fn, (model, *_args(op, s, slice(None), False)))
        out[op] = {"single": single, "batch": batch}
    return out


def _ratio(x: float | None, y: float | None) -> float | None:
    return None if x is None or y is None else x / y


def _ratios(res: dict) -> tuple[dict, list[dict]]:
    """Ratios cgadyn / other, and the issues' targets next to the measured ratios."""
    single = {op: {lib: _ratio(t["cgadyn"], t[lib]) for lib in t if lib != "cgadyn"}
              for op, t in res["single_us"].items()}
    batch = {b: {op: {lib: _ratio(t["cgadyn"], t[lib]) for lib in t if lib != "cgadyn"}
                 for op, t in ops.items()}
             for b, ops in res["batch_us_per_sample"].items()}
    targets = [_target(f"single-call {op} vs Pinocchio", single[op].get("pinocchio"),
                       TARGETS["single_pinocchio" if op in ("rnea", "aba", "crba")
                               else "single_derivatives"]) for op in OPS]
    big = str(max(res["batches"]))
    for op in OPS:
        targets.append(_target(f"batch {big} {op} vs Pinocchio Python loop",
                               batch[big][op].get("pinocchio_loop"), TARGETS["batch_loop"]))
    for op in PARALLEL:
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
        "cpu": cpu_model(), "cores": os.cpu_count(), "threads": threads,
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


def cpu_model() -> str:
    """The CPU's model name with its family and model numbers where the kernel gives them
    (a VM's name alone, "AMD EPYC", does not tell one generation from the next, and
    ratios between libraries move with it); the platform's processor string elsewhere."""
    try:
        info = {}
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            info.setdefault(key.strip(), value.strip())
        if "model name" in info:
            numbers = ", ".join(f"{k} {info[k]}" for k in ("cpu family", "model")
                                if k in info)
            return f"{info['model name']} ({numbers})" if numbers else info["model name"]
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


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


