"""Benchmark cgadyn's constraints against Pinocchio 4.1 in the same run: ``delassus``,
``constrained_dynamics`` and ``impulse_dynamics`` (one call from Python each) against
``computeDelassusMatrix``, ``constraintDynamics`` and ``impulseDynamics``, on solo12 on its
four feet (point contacts) and talos_reduced on both soles (frame contacts), at a random
state; then batches (``--batch`` random states, one call of cgadyn against a Python loop
over Pinocchio's function, wall-clock time, cgadyn on all of numba's threads). Writes
validation/results/constraints.md with the times and ratios. Timing on a
shared machine is noisy: the libraries alternate, each figure is the best of the repeats,
and the clock is this process's CPU time (``time.process_time``), so that the time other
jobs take the cores from it is not counted.

    python validation/constraints_benchmark.py [--repeats R] [--number N] [--batch B]
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import time
import timeit
from pathlib import Path

import numba
import numpy as np

import cgadyn
from cgadyn import oracle
from cgadyn.bench.measure import cpu_model

OUT = Path(__file__).parent / "results"
CASES = {"solo12": ("point", ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")),
         "talos_reduced": ("frame", ("left_sole_link", "right_sole_link"))}


def case(robot: str, kind: str, links: tuple[str, ...]) -> dict:
    """The calls of both libraries on one robot, each a function of no argument."""
    import pinocchio as pin

    model, pm = oracle.models(robot)
    rng = np.random.default_rng(0)
    q = cgadyn.random_configuration(model, rng)
    v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
    cs = [cgadyn.Constraint(model, kind, link, q=q, frame="local") for link in links]
    d = pm.createData()
    qp = oracle.pin_configuration(model, q)
    models, datas = oracle.pin_constraints(model, pm, cs)
    pin.initConstraintDynamics(pm, d, models, datas)
    prox = pin.ProximalSettings(1e-12, 1e-12, 0.0, 1)
    calls = {
        "delassus": (lambda: cgadyn.delassus(model, q, cs),
                     lambda: pin.computeDelassusMatrix(pm, d, qp, models, datas, 0.0)),
        "constrained_dynamics": (
            lambda: cgadyn.constrained_dynamics(model, q, v, tau, cs),
            lambda: pin.constraintDynamics(pm, d, qp, v, tau, models, datas, prox)),
        "impulse_dynamics": (
            lambda: cgadyn.impulse_dynamics(model, q, v, cs),
            lambda: pin.impulseDynamics(pm, d, qp, v, models, datas, 0.0, prox)),
    }
    for ours, theirs in calls.values():  # compile, warm the caches
        ours()
        theirs()
    return calls


def batch_case(robot: str, kind: str, links: tuple[str, ...], size: int) -> dict:
    """The batch calls of both libraries on one robot: cgadyn one call on ``size`` random
    states, Pinocchio a Python loop over them; each a function of no argument."""
    import pinocchio as pin

    model, pm = oracle.models(robot)
    rng = np.random.default_rng(1)
    q0 = cgadyn.random_configuration(model, rng)
    cs = [cgadyn.Constraint(model, kind, link, q=q0, frame="local") for link in links]
    Q = np.stack([cgadyn.random_configuration(model, rng) for _ in range(size)])
    V, T = rng.normal(size=(size, model.nv)), rng.normal(size=(size, model.nv))
    d = pm.createData()
    Qp = [oracle.pin_configuration(model, q) for q in Q]
    models, datas = oracle.pin_constraints(model, pm, cs)
    pin.initConstraintDynamics(pm, d, models, datas)
    prox = pin.ProximalSettings(1e-12, 1e-12, 0.0, 1)

    def loop_delassus():
        for q in Qp:
            pin.computeDelassusMatrix(pm, d, q, models, datas, 0.0)

    def loop_dynamics():
        for q, v, t in zip(Qp, V, T, strict=True):
            pin.constraintDynamics(pm, d, q, v, t, models, datas, prox)

    calls = {"delassus": (lambda: cgadyn.delassus(model, Q, cs), loop_delassus),
             "constrained_dynamics": (
                 lambda: cgadyn.constrained_dynamics(model, Q, V, T, cs), loop_dynamics)}
    for ours, _ in calls.values():
        ours()  # compile
    return calls


def best_us(fn, number: int, repeats: int) -> list[float]:
    return [t / number * 1e6 for t in timeit.repeat(fn, number=number, repeat=repeats,
                                                     timer=time.process_time)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--number", type=int, default=20000)
    parser.add_argument("--batch", type=int, default=4096)
    args = parser.parse_args()
    rows = []
    for robot, (kind, links) in CASES.items():
        for name, (ours, theirs) in case(robot, kind, links).items():
            a, b = [], []
            for _ in range(args.repeats):  # alternate the libraries
                a += best_us(ours, args.number, 1)
                b += best_us(theirs, args.number, 1)
            rows.append((robot, name, min(a), min(b)))
            print(f"{robot:14s} {name:22s} cgadyn {min(a):7.2f} us  Pinocchio {min(b):7.2f} us"
                  f"  ratio {min(a) / min(b):.2f}", flush=True)
    batch_rows = []
    for robot, (kind, links) in CASES.items():
        for name, (ours, theirs) in batch_case(robot, kind, links, args.batch).items():
            a, b = [], []
            for _ in range(3):
                a.append(min(timeit.repeat(ours, number=1, repeat=2)) * 1e3)
                b.append(min(timeit.repeat(theirs, number=1, repeat=1)) * 1e3)
            batch_rows.append((robot, name, min(a), min(b)))
            print(f"{robot:14s} {name:22s} batch of {args.batch}: cgadyn {min(a):8.2f} ms  "
                  f"Pinocchio loop {min(b):8.2f} ms  ratio {min(a) / min(b):.2f}", flush=True)
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=False).stdout.strip()
    except OSError:
        commit = "?"
    lines = [
        "# Constraints: cgadyn against Pinocchio 4.1",
        "",
        "One call from Python each, at one random state (`validation/constraints_benchmark.py`"
        f", best of {args.repeats} repeats of {args.number} calls, the libraries alternating, "
        "CPU time of the process).",
        "solo12: four point contacts on the feet; talos_reduced: two frame contacts on the "
        "soles; both in the `local` frame. Ratio: cgadyn's time over Pinocchio's (below 1: "
        "cgadyn is faster).",
        "",
        f"Machine: {cpu_model()}, {platform.system()}; "
        f"commit {commit}; cgadyn's C extension: "
        f"{cgadyn.algorithms.calls.NATIVE_STATUS}.",
        "",
        "| robot | cgadyn | Pinocchio | cgadyn µs | Pinocchio µs | ratio |",
        "|---|---|---|---:|---:|---:|",
    ]
    pin_names = {"delassus": "computeDelassusMatrix", "constrained_dynamics": "constraintDynamics",
                 "impulse_dynamics": "impulseDynamics"}
    for robot, name, a, b in rows:
        lines.append(f"| {robot} | `{name}` | `{pin_names[name]}` | {a:.2f} | {b:.2f} | "
                     f"{a / b:.2f} |")
    lines += [
        "",
        f"## Batches of {args.batch} random states",
        "",
        f"One cgadyn call on all of numba's threads ({numba.get_num_threads()} here) against "
        "a Python loop over Pinocchio's function on the same states; wall-clock time, best "
        "of 3 rounds.",
        "",
        "| robot | cgadyn | Pinocchio loop | cgadyn ms | Pinocchio ms | ratio |",
        "|---|---|---|---:|---:|---:|",
    ]
    for robot, name, a, b in batch_rows:
        lines.append(f"| {robot} | `{name}` | `{pin_names[name]}` | {a:.2f} | {b:.2f} | "
                     f"{a / b:.2f} |")
    OUT.mkdir(exist_ok=True)
    (OUT / "constraints.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT / 'constraints.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
