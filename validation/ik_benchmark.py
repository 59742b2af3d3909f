"""Inverse kinematics on the panda: cgadyn against the classic Pinocchio loop, same run.

Targets: the poses of ``panda_hand`` at random configurations within the joint limits
(reachable by construction). Every solver starts from the middle of the joint ranges and may
restart from random configurations within the limits (up to 20 times; restarts count in the
time). A solve succeeds when Pinocchio's own ``log6(oMdes⁻¹ oMf(q))`` has norm ≤ 1e-10 and q
lies within the limits; cgadyn's answers are judged by Pinocchio.

The Pinocchio loop is the closed-loop inverse kinematics of its documentation: the error
``log6`` of the frame's pose relative to the target, the frame Jacobian times ``Jlog6``, a
damped pseudo-inverse ``Jᵀ (J Jᵀ + λ 1)⁻¹``, ``integrate``. It is run with the
documentation's step ``DT = 0.1`` and with a full step ``DT = 1``; the faster of the two that
succeeds at least as often is the reference.

    PYTHONPATH=src /work/main/.venv/bin/python validation/ik_benchmark.py [--targets 1000]

Writes validation/results/ik_panda.md.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numba
import numpy as np
import pinocchio as pin

import cgadyn
from cgadyn import oracle
from cgadyn.algorithms._workspace import chunks
from cgadyn.bench.measure import cpu_model
from cgadyn.tasks.ik import middle_configuration

OUT = Path(__file__).parent / "results" / "ik_panda.md"
LINK = "panda_hand"
TOL = 1e-10
RESTARTS = 20
REPEATS = 5
"""cgadyn's single solves and batches are each timed this many times, interleaved, and the
best of each is reported (as ``timeit`` advises and ``simulate_benchmark`` does: on a shared
machine the slower runs are those that other jobs interrupted, and a batch on two threads
is interrupted whenever either core is)."""


def pin_clik(pm, d, fid, oMdes, q0, rng, dt, it_max, damp=1e-12):
    """The classic loop, with restarts: (q, success, iterations, restarts)."""
    its = 0
    q = q0.copy()
    for attempt in range(RESTARTS + 1):
        if attempt:
            q = pin.randomConfiguration(pm)
        for _ in range(it_max):
            pin.framesForwardKinematics(pm, d, q)
            iMd = d.oMf[fid].actInv(oMdes)
            err = pin.log6(iMd).vector
            if np.linalg.norm(err) <= TOL:
                break
            its += 1
            J = pin.computeFrameJacobian(pm, d, q, fid, pin.LOCAL)
            J = -pin.Jlog6(iMd.inverse()) @ J
            v = -J.T @ np.linalg.solve(J @ J.T + damp * np.eye(6), err)
            q = pin.integrate(pm, q, v * dt)
        if _success(pm, d, fid, oMdes, q):
            return q, True, its, attempt
    return q, False, its, RESTARTS


def _error(pm, d, fid, oMdes, q) -> float:
    pin.framesForwardKinematics(pm, d, q)
    return float(np.linalg.norm(pin.log6(oMdes.actInv(d.oMf[fid])).vector))


def _success(pm, d, fid, oMdes, q) -> bool:
    inside = np.all(q >= pm.lowerPositionLimit) and np.all(q <= pm.upperPositionLimit)
    return bool(inside) and _error(pm, d, fid, oMdes, q) <= TOL


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=1000)
    ap.add_argument("--batch", type=int, default=4096)
    args = ap.parse_args()
    model, pm = oracle.models("panda")
    d = pm.createData()
    fid = pm.getFrameId(LINK, pin.BODY)
    rng = np.random.default_rng(2026)
    Q = np.array([cgadyn.random_configuration(model, rng) for _ in range(args.batch)])
    T = cgadyn.link_placements(model, Q)[:, model.link_index(LINK)]
    targets = [pin.SE3(t) for t in T[:args.targets]]
    q_mid = middle_configuration(model)

    cgadyn.inverse_kinematics(model, LINK, T[0])  # compile (or load) before timing
    cgadyn.inverse_kinematics(model, LINK, T[:8])
    t_single, t_batch, t_batch1 = [], [], []
    for _ in range(REPEATS):  # interleaved, best of: the machine's speed drifts
        t0 = time.perf_counter()
        single = [cgadyn.inverse_kinematics(model, LINK, t) for t in T[:args.targets]]
        t_single.append((time.perf_counter() - t0) / args.targets)
        t0 = time.perf_counter()
        batch = cgadyn.inverse_kinematics(model, LINK, T)
        t_batch.append((time.perf_counter() - t0) / args.batch)
        t0 = time.perf_counter()
        cgadyn.inverse_kinematics(model, LINK, T, threads=1)
        t_batch1.append((time.perf_counter() - t0) / args.batch)
    t_single, t_batch, t_batch1 = (min(x) for x in (t_single, t_batch, t_batch1))
    threads = numba.get_num_threads()
    shares = [int(np.sum(batch.iterations[a:b])) for a, b in zip(*chunks(args.batch, threads),
                                                                  strict=True)]
    ok = [_success(pm, d, fid, o, r.q) for o, r in zip(targets, single, strict=True)]
    rows = {"cgadyn": (np.mean(ok), t_single, np.mean([r.iterations for r in single]),
                       sum(r.restarts for r in single))}
    ok_b = np.mean([_success(pm, d, fid, pin.SE3(T[b]), batch.q[b]) for b in range(args.batch)])

    np.random.seed(7)  # pin.randomConfiguration draws from numpy's global generator
    for dt, it_max in [(1.0, 100), (0.1, 1000)]:
        t0 = time.perf_counter()
        res = [pin_clik(pm, d, fid, o, q_mid, rng, dt, it_max) for o in targets]
        t = (time.perf_counter() - t0) / args.targets
        rows[f"Pinocchio CLIK, DT = {dt:g}"] = (np.mean([r[1] for r in res]), t,
                                               np.mean([r[2] for r in res]),
                                               sum(r[3] for r in res))
    pins = {k: v for k, v in rows.items() if k != "cgadyn"}
    fair = [k for k, v in pins.items() if v[0] <= rows["cgadyn"][0]] or list(pins)
    ref = min(fair, key=lambda k: pins[k][1])

    lines = [
        "# Inverse kinematics, panda (`panda_hand`): cgadyn against the Pinocchio loop",
        "",
        f"`validation/ik_benchmark.py`, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
        f"{cpu_model()}, {os.cpu_count()} cores, numba "
        f"threads {threads}, Pinocchio {pin.__version__}. One run "
        f"(cgadyn's timings: best of {REPEATS}, interleaved): every ratio below compares "
        "timings of the same run (a shared machine: absolute times vary with its load).",
        "",
        f"{args.targets} reachable full poses (the pose of a random configuration within the "
        "limits), start at the middle of the joint ranges, up to 20 random restarts within "
        f"the limits (counted in the time). Success: Pinocchio's `|log6(oMdes⁻¹ oMf(q))|` ≤ "
        f"{TOL:g} and q within the limits.",
        "",
        "| solver | success | µs per solve | mean iterations | restarts (all targets) |",
        "|---|---|---|---|---|",
    ]
    for k, (s, t, it, rs) in rows.items():
        lines.append(f"| {k} | {100 * s:.1f} % | {1e6 * t:.0f} | {it:.1f} | {rs} |")
    lines += [
        "",
        f"- cgadyn time per solve / the reference ({ref}): "
        f"**{rows['cgadyn'][1] / pins[ref][1]:.3f}x**; successes "
        f"{round(rows['cgadyn'][0] * args.targets)} against {round(pins[ref][0] * args.targets)}.",
        f"- A batch of {args.batch} targets in one compiled call: {1e6 * t_batch:.1f} µs per "
        f"target, success {100 * ok_b:.2f} %; single solves "
        f"{1e6 * t_single:.1f} µs: the batch is **{t_single / t_batch:.2f}x** faster per "
        f"target (on {threads} threads). The same batch on one thread: "
        f"{1e6 * t_batch1:.1f} µs per target ({t_single / t_batch1:.2f}x): what a single "
        "call adds is its Python side (argument checks, the task, the result).",
        f"- {threads} threads against one in this run: {t_batch1 / t_batch:.2f}x. The batch "
        f"splits into one contiguous chunk a thread, with {', '.join(map(str, shares))} "
        f"iterations: at most {sum(shares) / max(shares):.2f}x from the split. The batch's "
        f"ratio to single solves is {t_single / t_batch1:.2f} times what the threads give.",
        "",
    ]
    OUT.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
