"""Rollout throughput: ``cgadyn.simulate`` against a Python loop over ``pin.aba`` (the same
RK4) and MuJoCo's ``mujoco.rollout`` (its RK4), and dask's two worker processes against one
process. Writes ``validation/results/simulate.md``.

The workload: the panda from example-robot-data, RK4 at dt = 1e-3, open-loop torques
(random, one per step and rollout, the same for every library). MuJoCo loads the same URDF
without meshes (visual and collision elements removed), with contacts, joint limits and
the equality constraint of the fingers' ``mimic`` disabled and the URDF's joint damping set
to zero (cgadyn and the Pinocchio loop have none of them), torques applied as
``qfrc_applied``; and once more with contacts disabled only, as MuJoCo imports the URDF
(other dynamics, timed for reference). Each library runs at the same thread count
(cgadyn: numba's threads; MuJoCo: one ``MjData`` per thread). The Python loop is timed on
fewer rollouts (it is the slowest by far) and compared per step. Time is the best of
``--repeat`` runs; the machine's load average is recorded, since it is shared.

What is timed: ``cgadyn.simulate`` returns q, v and q̈ at every state, as the Pinocchio
loop and MuJoCo do; a ``Trajectory`` computes its energies only when they are read, so the
row "cgadyn.simulate, then Trajectory.energy" times the same rollouts with the energy of
every state read afterwards (one more parallel compiled call), for reference.

Run:  python validation/simulate_benchmark.py [--rollouts 1024] [--steps 1000]
      [--pin-rollouts 16] [--repeat 5] [--dask-rollouts 256]
"""

from __future__ import annotations

import argparse
import os
import re
import time
from pathlib import Path

import numba
import numpy as np
import pinocchio as pin

import cgadyn
from cgadyn import oracle
from cgadyn.bench.measure import cpu_model
from cgadyn.multibody import registry

RESULTS = Path(__file__).resolve().parent / "results"
DT = 1e-3
ENERGY = "cgadyn.simulate, then Trajectory.energy (every state)"


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def pin_rk4(pm, d, q, v, taus, dt):
    """The RK4 of ``cgadyn.sim.rollout`` written on ``pin.aba`` and ``pin.integrate``."""
    for u in taus:
        a1 = pin.aba(pm, d, q, v, u).copy()
        v2 = v + 0.5 * dt * a1
        a2 = pin.aba(pm, d, pin.integrate(pm, q, 0.5 * dt * v), v2, u).copy()
        v3 = v + 0.5 * dt * a2
        a3 = pin.aba(pm, d, pin.integrate(pm, q, 0.5 * dt * v2), v3, u).copy()
        v4 = v + dt * a3
        a4 = pin.aba(pm, d, pin.integrate(pm, q, dt * v3), v4, u).copy()
        q = pin.integrate(pm, q, dt / 6 * (v + 2 * v2 + 2 * v3 + v4))
        v = v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
    return q, v


def mujoco_model(same_dynamics: bool = True):
    """The panda in MuJoCo, contacts disabled, RK4; ``same_dynamics``: also joint limits,
    the fingers' mimic (an equality constraint) and joint damping off, as in cgadyn."""
    import mujoco

    text = Path(registry.robot_path("panda")).read_text()
    text = re.sub(r"<visual>.*?</visual>|<collision>.*?</collision>", "", text, flags=re.S)
    mm = mujoco.MjModel.from_xml_string(text)
    mm.opt.timestep = DT
    mm.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    mm.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    if same_dynamics:
        mm.opt.disableflags |= (mujoco.mjtDisableBit.mjDSBL_LIMIT
                                | mujoco.mjtDisableBit.mjDSBL_EQUALITY)  # the fingers' mimic
        mm.dof_damping[:] = 0.0
    return mm


def mujoco_run(mm, datas, q0, v0, taus):
    import mujoco
    from mujoco import rollout

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    d = datas[0]
    state0 = np.empty((q0.shape[0], mujoco.mj_stateSize(mm, spec)))
    for b in range(q0.shape[0]):
        mujoco.mj_resetData(mm, d)
        d.qpos[:], d.qvel[:] = q0[b], v0[b]
        mujoco.mj_getState(mm, d, state0[b], spec)
    state, _ = rollout.rollout(mm, datas if len(datas) > 1 else datas[0], state0, taus,
                               control_spec=mujoco.mjtState.mjSTATE_QFRC_APPLIED)
    return state, spec


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rollouts", type=int, default=1024)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--pin-rollouts", type=int, default=16)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--dask-rollouts", type=int, default=256)
    args = p.parse_args()
    B, H = args.rollouts, args.steps
    threads = sorted({1, numba.config.NUMBA_NUM_THREADS})
    load = [os.getloadavg()[0]]
    model, pm = oracle.models("panda")
    rng = np.random.default_rng(0)
    q0 = oracle.sample(model, B, 1).q
    v0 = 0.1 * rng.standard_normal((B, model.nv))
    taus = rng.normal(0.0, 1.0, (B, H, model.nv))
    cgadyn.simulate(model, q0[:4], v0[:4], DT, 10, tau=taus[:4, :10])  # compile or load
    d = pm.createData()
    P = args.pin_rollouts
    cases = {}  # (what, threads, rollouts) -> a function timed in every round

    def cgadyn_case(t):
        numba.set_num_threads(t)
        cgadyn.simulate(model, q0, v0, DT, H, tau=taus)

    def cgadyn_energy_case(t):
        numba.set_num_threads(t)
        return cgadyn.simulate(model, q0, v0, DT, H, tau=taus).energy

    for t in threads:
        cases[("cgadyn.simulate", t, B)] = lambda t=t: cgadyn_case(t)
        cases[(ENERGY, t, B)] = lambda t=t: cgadyn_energy_case(t)
    cases[("Python loop over pin.aba (RK4)", 1, P)] = lambda: [
        pin_rk4(pm, d, q0[b], v0[b], taus[b], DT) for b in range(P)]
    agree = {}
    version = None
    try:
        import mujoco

        mm = mujoco_model()
        version = mujoco.__version__
        full = mujoco_model(same_dynamics=False)
        for t in threads:
            datas = [mujoco.MjData(mm) for _ in range(t)]
            cases[(f"mujoco.rollout (RK4, MuJoCo {version})", t, B)] = \
                lambda datas=datas: mujoco_run(mm, datas, q0, v0, taus)
            datas = [mujoco.MjData(full) for _ in range(t)]
            cases[("mujoco.rollout, contacts off only (limits, mimic, damping on)", t, B)] = \
                lambda datas=datas: mujoco_run(full, datas, q0, v0, taus)
        state, _ = mujoco_run(mm, [mujoco.MjData(mm)], q0[:1], v0[:1], taus[:1])
        agree["mujoco"] = state[0, -1, 1:1 + mm.nq + mm.nv]  # (time, qpos, qvel, ...)
    except ImportError:
        pass
    times = {key: [] for key in cases}
    for _ in range(args.repeat):  # rounds, each case once per round: load hits all alike
        for key, fn in cases.items():
            t0 = time.perf_counter()
            fn()
            times[key].append(time.perf_counter() - t0)
    numba.set_num_threads(threads[-1])
    rows = [(w, t, b, min(times[(w, t, b)]), min(times[(w, t, b)]) / (b * H) * 1e6)
            for (w, t, b) in cases]
    pq, pv = pin_rk4(pm, d, q0[0], v0[0], taus[0], DT)
    mine = cgadyn.simulate(model, q0[0], v0[0], DT, H, tau=taus[0])
    agree["pin"] = max(oracle.relative_error(mine.q[-1][None], pq[None])[0],
                       oracle.relative_error(mine.v[-1][None], pv[None])[0])
    if "mujoco" in agree:
        mq, mv = agree["mujoco"][:model.nq], agree["mujoco"][model.nq:]
        agree["mujoco"] = max(oracle.relative_error(mine.q[-1][None], mq[None])[0],
                              oracle.relative_error(mine.v[-1][None], mv[None])[0])
    dask_rows = dask_throughput(model, args.dask_rollouts, H, args.repeat)
    load.append(os.getloadavg()[0])
    write(rows, dask_rows, agree, load, B, H, P, version, args.repeat)


def _warm(model) -> None:
    cgadyn.simulate(model, np.zeros((2, model.nq)), np.zeros((2, model.nv)), DT, 2)


def dask_throughput(model, B, H, repeat):
    """Rollouts per second: one process (numba's threads) against a LocalCluster of two
    worker processes of one thread each, on chunks of B / 8 rollouts; only the final
    states come back to the client."""
    try:
        import dask.array as da
        from distributed import Client, LocalCluster
    except ImportError:
        return None
    rng = np.random.default_rng(2)
    q0 = oracle.sample(model, B, 3).q
    v0 = 0.1 * rng.standard_normal((B, model.nv))
    out = []
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    s = best(lambda: cgadyn.simulate(model, q0, v0, DT, H).q[:, -1], repeat)
    out.append((f"one process, numpy, {numba.config.NUMBA_NUM_THREADS} numba threads", s))
    numba.set_num_threads(1)
    s = best(lambda: cgadyn.simulate(model, q0, v0, DT, H).q[:, -1], repeat)
    out.append(("one process, numpy, 1 numba thread", s))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    chunks = (max(B // 8, 1), model.nq)
    env = {"NUMBA_NUM_THREADS": "1", "PYTHONPATH": os.environ.get("PYTHONPATH", "")}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, env=env) as cluster, Client(cluster) as client:
        qd = da.from_array(q0, chunks=chunks)
        vd = da.from_array(v0, chunks=(chunks[0], model.nv))
        client.run(_warm, model)  # every worker loads the compiled code before timing
        s = best(lambda: client.compute(cgadyn.simulate(model, qd, vd, DT, H).q[:, -1],
                                        sync=True), repeat)
        out.append(("dask LocalCluster, 2 worker processes x 1 thread", s))
    return [(what, B, s, B / s) for what, s in out]


def write(rows, dask_rows, agree, load, B, H, P, version, repeat) -> None:
    per_step = {(w, t): us for w, t, _, _, us in rows}
    lines = [
        "# Rollouts: cgadyn.simulate, a Python loop over pin.aba, mujoco.rollout, dask",
        "",
        f"Generated by `validation/simulate_benchmark.py`: the panda (nv 9), RK4, dt = {DT}, "
        f"{H} steps, random open-loop torques; {B} rollouts for cgadyn and MuJoCo, {P} for "
        f"the Python loop over `pin.aba` (too slow for more; compared per rollout-step). "
        f"Best of {repeat} rounds, every case once per round. Machine: "
        f"{cpu_model()}, "
        f"{os.cpu_count()} cores, shared with other jobs: load average {load[0]:.2f} "
        f"before, {load[1]:.2f} after.",
        "",
        "cgadyn.simulate returns q, v and q̈ at every state (as the other two do); its "
        "`Trajectory` computes the energies when first read, timed in the row "
        f"\"{ENERGY}\".",
        "",
        "| what | threads | rollouts | seconds | µs per rollout-step |",
        "|---|---:|---:|---:|---:|",
    ]
    lines += [f"| {w} | {t} | {b} | {s:.3f} | {us:.3f} |" for w, t, b, s, us in rows]
    lines += ["", "Ratios (the other's time per rollout-step / cgadyn's, same thread count):", ""]
    loop = next(us for (w, _), us in per_step.items() if w.startswith("Python loop"))
    for (w, t), us in per_step.items():
        if w == "cgadyn.simulate":
            lines.append(f"- {t} thread(s): Python loop over pin.aba / cgadyn = "
                         f"{loop / us:.1f}x" + ("" if t == 1 else " (the loop on 1 thread)"))
            for (w2, t2), v in per_step.items():
                if w2.startswith("mujoco") and t2 == t:
                    lines.append(f"- {t} thread(s): {w2} / cgadyn = {v / us:.2f}x")
            with_energy = per_step[(ENERGY, t)]
            lines.append(f"- {t} thread(s), energy of every state read as well: Python loop "
                         f"over pin.aba / cgadyn = {loop / with_energy:.1f}x"
                         + "".join(f"; {w2} / cgadyn = {v / with_energy:.2f}x"
                                   for (w2, t2), v in per_step.items()
                                   if w2.startswith("mujoco") and t2 == t))
    if version is None:
        lines.append("- MuJoCo: not installed, not measured.")
    lines += ["", f"Agreement: the state of rollout 0 after {H} steps against the Pinocchio loop "
              f"(the same integrator), relative error {agree['pin']:.1e}"
              + (f"; against MuJoCo's rollout (the same URDF through MuJoCo's importer, its "
                 f"RK4), {agree['mujoco']:.1e}: the same dynamics and the same integrator"
                 if "mujoco" in agree else "") + "."]
    if dask_rows:
        lines += ["", f"## dask: {dask_rows[0][1]} rollouts of {H} steps, chunks of "
                  f"{max(dask_rows[0][1] // 8, 1)}, final states returned", "",
                  "| how | seconds | rollouts per second |", "|---|---:|---:|"]
        lines += [f"| {w} | {s:.3f} | {r:.0f} |" for w, _, s, r in dask_rows]
        lines += ["", f"Two workers / one process with 1 thread: "
                  f"{dask_rows[2][3] / dask_rows[1][3]:.2f}x the throughput; two workers / "
                  f"one process with all threads: {dask_rows[2][3] / dask_rows[0][3]:.2f}x."]
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "simulate.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
