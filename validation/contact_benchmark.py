"""Rollouts with ground contact: ``cgadyn.simulate(..., world=World(), collisions=...)``
against MuJoCo's ``mujoco.rollout`` on the same scenes, at the same time step and thread
count. Writes ``validation/results/contact.md`` and ``contact.json``.

The scenes:

- **ant**: Gymnasium's Ant (``robots/mujoco/gymnasium/ant.xml``, loaded by both engines
  through MuJoCo's compiler) at ant.xml's time step, from its initial pose (``qpos0``) with
  Gymnasium's reset noise on the legs (uniform ±0.1 rad, speeds 0.1 N(0, 1)), driven by
  uniform random controls in the motors' range, the same array for both engines (cgadyn:
  ``ctrl=``, MuJoCo: ``data.ctrl``). ant.xml asks for RK4; a contact step is semi-implicit
  Euler in cgadyn, so both run Euler (MuJoCo's ``mjINT_EULER``). MuJoCo runs twice: as
  ant.xml has it (joint limits on, its implicit joint damping) and with the dynamics cgadyn
  has (limits off, explicit damping: ``mjDSBL_LIMIT | mjDSBL_EULERDAMP``).
- **solo12**: example-robot-data's solo12 in its standing posture, its lowest foot
  ``--drop`` above the ground, dropped under joint PD holding that posture (``cgadyn.PD``,
  no gravity compensation). MuJoCo builds it from the same URDF through ``mujoco.MjSpec``:
  mesh paths made absolute, visuals dropped, a free joint on the root body, a floor plane,
  collision from the meshes' convex hulls (MuJoCo's own), the robot's geoms touching the
  floor only (as cgadyn's ground), and the PD as ``general`` actuators with an affine bias
  (``τ = k_p ctrl - k_p q - k_d q̇``, ctrl the posture), so both close the loop inside their
  compiled step. Euler at 1 ms for both.

Both engines return every state (cgadyn: q, v, q̈ and each contact slot's force; MuJoCo:
its full physics state). Time is wall clock, the best of ``--repeat`` runs after a warm-up
(compile time excluded), as µs per rollout-step. Thread counts: numba's threads for cgadyn,
``mujoco.rollout.Rollout(nthread=...)`` (the calling thread for 1) for MuJoCo.

Physical criteria on the same scenes, not timed: the deepest penetration over the run
(cgadyn: ``ground_contacts`` at every state of ``--check-rollouts`` rollouts; MuJoCo: the
least ``data.contact.dist`` of the same rollouts re-run with ``mj_step``) and the base
height at the end (every rollout of the timed run). The contact models differ: cgadyn's
contacts are rigid (a velocity-level complementarity problem with a Baumgarte-like
correction of the overlap), MuJoCo's are soft (``solref``/``solimp``: a contact force grows
with the penetration), and ant.xml's geoms carry a 1 cm margin inside which MuJoCo's
contacts already push.

Run:  python validation/contact_benchmark.py [--rollouts 1024] [--steps 1000] [--repeat 2]
      [--solo12-rollouts B] [--solo12-steps N] [--scenes ant solo12] [--quick]
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import subprocess
import time
import warnings
from pathlib import Path
from typing import NamedTuple

import numba
import numpy as np

import cgadyn
from cgadyn.bench.measure import cpu_model
from cgadyn.multibody import registry

RESULTS = Path(__file__).resolve().parent / "results"
STAND = np.tile([0.0, 0.8, -1.6], 4)
"""solo12's standing posture: hip abduction, hip flexion, knee of each leg."""
KP, KD = 20.0, 0.5
"""solo12's joint PD gains (N m / rad, N m s / rad)."""
SOLO_DT = 1e-3


class Scene(NamedTuple):
    """One scene for both engines: cgadyn's model, collision shapes and arguments, MuJoCo's
    compiled models (by variant) and initial states, the controls of both."""

    name: str
    model: object
    collisions: object
    dt: float
    q0: np.ndarray
    v0: np.ndarray
    ctrl: np.ndarray | None
    """cgadyn's ``ctrl`` (B, steps, na), or None."""
    controller: object
    mujoco: dict
    """variant -> MjModel."""
    mj_ctrl: np.ndarray
    """MuJoCo's controls, (B or 1, steps or 1, nu)."""
    base: int
    """The MuJoCo body of the free base."""


def to_mujoco_qpos(q: np.ndarray) -> np.ndarray:
    """cgadyn's ``[x, y, z, qx, qy, qz, qw, joints]`` as MuJoCo's ``[x, y, z, qw, qx, qy, qz,
    joints]``."""
    out = q.copy()
    out[..., 3], out[..., 4:7] = q[..., 6], q[..., 3:6]
    return out


def to_mujoco_qvel(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """cgadyn's base velocity (linear and angular in the base frame) as MuJoCo's (linear in
    the world frame, angular in the base frame): ``v_lin ← R v_lin``."""
    out = v.copy()
    for b in range(q.shape[0]):
        x, y, z, w = q[b, 3:7]
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        out[b, :3] = R @ v[b, :3]
    return out


def ant(B: int, H: int, rng) -> Scene:
    import mujoco

    model = cgadyn.load("gymnasium:ant")
    collisions = cgadyn.collision_model(model)
    path = registry.robot_path("gymnasium:ant")
    variants = {}
    for name, off in (("as ant.xml (limits on, implicit damping)", 0),
                      ("limits off, explicit damping (cgadyn's dynamics)",
                       mujoco.mjtDisableBit.mjDSBL_LIMIT | mujoco.mjtDisableBit.mjDSBL_EULERDAMP)):
        mm = mujoco.MjModel.from_xml_path(str(path))
        mm.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
        mm.opt.disableflags |= off
        variants[name] = mm
    mm = next(iter(variants.values()))
    q0 = np.tile(mm.qpos0, (B, 1))
    q0[:, 3:7] = [0.0, 0.0, 0.0, 1.0]  # cgadyn's order: qpos0's quaternion is the identity
    q0[:, 7:] += rng.uniform(-0.1, 0.1, (B, model.nq - 7))
    v0 = np.zeros((B, model.nv))
    v0[:, 6:] = 0.1 * rng.standard_normal((B, model.nv - 6))
    lo, hi = mm.actuator_ctrlrange.T
    ctrl = rng.uniform(lo, hi, (B, H, mm.nu))
    return Scene("ant", model, collisions, float(mm.opt.timestep), q0, v0, ctrl, None,
                 variants, ctrl, mm.body("torso").id)


def solo12_mujoco():
    """solo12 in MuJoCo from example-robot-data's URDF (``mujoco.MjSpec``), with joint PD
    actuators: ``τ = KP ctrl - KP q - KD q̇``."""
    import mujoco

    from cgadyn.multibody.meshes import resolve_mesh

    path = Path(registry.robot_path("solo12"))
    text = re.sub(r"<visual>.*?</visual>", "", path.read_text(), flags=re.S)
    text = re.sub(r'filename="([^"]+)"',
                  lambda m: f'filename="{resolve_mesh(m.group(1), path)}"', text)
    text = re.sub(r"(<robot[^>]*>)", r'\1<mujoco><compiler strippath="false" '
                  r'discardvisual="true" fusestatic="false"/></mujoco>', text, count=1)
    spec = mujoco.MjSpec.from_string(text)
    spec.worldbody.first_body().add_freejoint()
    for g in spec.geoms:  # the robot touches the floor only, as cgadyn's ground
        g.contype, g.conaffinity = 1, 0
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1], contype=0,
                            conaffinity=1)
    for j in spec.joints:
        if j.type == mujoco.mjtJoint.mjJNT_HINGE:
            a = spec.add_actuator(target=j.name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            a.gainprm[0] = KP
            a.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            a.biasprm[:3] = [0.0, -KP, -KD]
    mm = spec.compile()
    mm.opt.timestep = SOLO_DT
    mm.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    return mm


def solo12(B: int, H: int, rng, drop: float) -> Scene:
    model = cgadyn.load("solo12")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        collisions = cgadyn.collision_model(model, "solo12")
    q0 = np.tile(cgadyn.neutral(model), (B, 1))
    q0[:, 7:] = STAND + rng.uniform(-0.05, 0.05, (B, 12))
    for b in range(B):  # the lowest foot `drop` above the ground
        q0[b, 2] = 0.3
        q0[b, 2] += drop - cgadyn.ground_contacts(model, collisions, q0[b],
                                                  margin=1.0).distance.min()
    mm = solo12_mujoco()
    mj_names = [mm.joint(i).name for i in range(1, mm.njnt)]
    if mj_names != list(model.joint_names[-12:]):
        raise RuntimeError(f"solo12: MuJoCo's joints {mj_names} are not cgadyn's "
                           f"{model.joint_names}")
    pd = cgadyn.PD(kp=KP, kd=KD, gravity_compensation=False)  # holds each q0's posture
    return Scene("solo12", model, collisions, SOLO_DT, q0, np.zeros((B, model.nv)), None, pd,
                 {"PD actuators, Euler": mm}, q0[:, None, 7:].copy(),
                 mm.body("base_link").id)


# ---------------------------------------------------------------------------------------
# the two engines


def run_cgadyn(s: Scene, steps: int, threads: int, rollouts=slice(None)):
    numba.set_num_threads(threads)
    ctrl = None if s.ctrl is None else s.ctrl[rollouts, :steps]
    return cgadyn.simulate(s.model, s.q0[rollouts], s.v0[rollouts], s.dt, steps, ctrl=ctrl,
                           controller=s.controller, integrator="semi_implicit_euler",
                           world=cgadyn.World(), collisions=s.collisions)


def mujoco_states(s: Scene, mm, rollouts=slice(None)) -> np.ndarray:
    """The initial full physics states of the rollouts, (B, nstate)."""
    import mujoco

    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    q = s.q0[rollouts]
    qpos, qvel = to_mujoco_qpos(q), to_mujoco_qvel(q, s.v0[rollouts])
    d = mujoco.MjData(mm)
    out = np.empty((q.shape[0], mujoco.mj_stateSize(mm, spec)))
    for b in range(q.shape[0]):
        mujoco.mj_resetData(mm, d)
        d.qpos[:], d.qvel[:] = qpos[b], qvel[b]
        mujoco.mj_getState(mm, d, out[b], spec)
    return out


def run_mujoco(pool, mm, datas, state0, ctrl, steps: int) -> np.ndarray:
    state, _ = pool.rollout(mm, datas, state0, ctrl, nstep=steps)
    return state


def mujoco_ctrl(s: Scene, rollouts=slice(None), steps=None) -> np.ndarray:
    c = s.mj_ctrl[rollouts] if s.mj_ctrl.shape[0] > 1 else s.mj_ctrl
    return c[:, :steps] if c.shape[1] > 1 else c


# ---------------------------------------------------------------------------------------
# physical criteria


def cgadyn_criteria(s: Scene, tr, check: int) -> dict:
    """The deepest penetration over every state of the first ``check`` rollouts
    (``ground_contacts``), and the base height at the end over all rollouts ``tr``."""
    deepest = np.inf
    for b in range(min(check, tr.q.shape[0])):
        for k in range(tr.q.shape[1]):
            c = cgadyn.ground_contacts(s.model, s.collisions, tr.q[b, k], margin=1e-3)
            if len(c):
                deepest = min(deepest, float(c.distance.min()))
    z = tr.q[:, -1, 2]
    return {"min_distance": deepest if np.isfinite(deepest) else None, "base_z": _stats(z),
            "contacts_end": float(np.mean(tr.contact_count[:, -1])),
            "stopped": int(np.count_nonzero(tr.diverged))}


def mujoco_criteria(s: Scene, mm, states: np.ndarray, check: int, steps: int) -> dict:
    """The least ``contact.dist`` over the first ``check`` rollouts re-run with ``mj_step``
    (the controls of the timed run), and the base height at the end over all rollouts
    ``states`` (the timed run's, (B, steps, nstate))."""
    import mujoco

    d = mujoco.MjData(mm)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = mujoco_states(s, mm, slice(0, check))
    ctrl = mujoco_ctrl(s, slice(0, check), steps)
    deepest, ncon = np.inf, []
    for b in range(state0.shape[0]):
        mujoco.mj_setState(mm, d, state0[b], spec)
        for k in range(steps):
            d.ctrl[:] = ctrl[min(b, ctrl.shape[0] - 1), min(k, ctrl.shape[1] - 1)]
            mujoco.mj_step(mm, d)
            if d.ncon:
                deepest = min(deepest, float(d.contact.dist[:d.ncon].min()))
        ncon.append(d.ncon)
    z = states[:, -1, 1 + 2]  # state: time, qpos, ...; the base's z is qpos[2]
    return {"min_distance": deepest if np.isfinite(deepest) else None, "base_z": _stats(z),
            "contacts_end": float(np.mean(ncon)), "stopped": 0}


def _depth(distance: float | None) -> str:
    """The deepest penetration in mm (negative: the contacts stayed apart), or "no contact"."""
    return "no contact" if distance is None else f"{-1e3 * distance:.3f}"


def _stats(x: np.ndarray) -> dict:
    x = x[np.isfinite(x)]
    return {"mean": float(np.mean(x)), "min": float(np.min(x)), "max": float(np.max(x))}


# ---------------------------------------------------------------------------------------


def measure(s: Scene, B: int, H: int, threads: list[int], repeat: int, check: int) -> dict:
    from mujoco import MjData, rollout

    run_cgadyn(s, 5, threads[-1], slice(0, 2))  # compile or load the cache
    times: dict = {}
    out: dict = {"scene": s.name, "dt": s.dt, "rollouts": B, "steps": H, "timed": [],
                 "criteria": {}}
    pools = {t: rollout.Rollout(nthread=0 if t == 1 else t) for t in threads}
    try:
        state0 = {v: mujoco_states(s, mm) for v, mm in s.mujoco.items()}
        ctrl = mujoco_ctrl(s, slice(None), H)
        for v, mm in s.mujoco.items():  # warm up
            run_mujoco(pools[threads[-1]], mm, [MjData(mm) for _ in range(threads[-1])],
                       state0[v][:2], mujoco_ctrl(s, slice(0, 2), 5), 5)
        finals: dict = {}
        taken: dict = {}  # threads -> the rollout-steps cgadyn took (a stopped rollout: fewer)
        for _ in range(repeat):  # rounds: every case once per round, load hits all alike
            for t in threads:
                with warnings.catch_warnings():  # a stopped rollout: counted below
                    warnings.simplefilter("ignore", cgadyn.SimulationDiverged)
                    t0 = time.perf_counter()
                    tr = run_cgadyn(s, H, t)
                    times.setdefault(("cgadyn", t), []).append(time.perf_counter() - t0)
                taken[t] = int(np.sum(tr.completed))
                finals["cgadyn"] = tr
                del tr
                for v, mm in s.mujoco.items():
                    datas = [MjData(mm) for _ in range(t)]
                    t0 = time.perf_counter()
                    state = run_mujoco(pools[t], mm, datas, state0[v], ctrl, H)
                    times.setdefault((v, t), []).append(time.perf_counter() - t0)
                    finals[v] = state
    finally:
        for p in pools.values():
            p.close()
    for (what, t), ts in times.items():
        sec = min(ts)
        steps = taken[t] if what == "cgadyn" else B * H
        out["timed"].append({"engine": "cgadyn" if what == "cgadyn" else "mujoco",
                             "variant": what, "threads": t, "seconds": sec,
                             "rollout_steps": steps, "us_per_rollout_step": sec / steps * 1e6})
        print(f"{s.name:7s} {what:55s} {t} thread(s) {sec:8.3f} s "
              f"{sec / steps * 1e6:8.3f} us/rollout-step", flush=True)
    out["criteria"]["cgadyn"] = cgadyn_criteria(s, finals["cgadyn"], check)
    out["cgadyn_message"] = finals["cgadyn"].message  # why rollouts stopped, if any
    for v, mm in s.mujoco.items():
        out["criteria"][v] = mujoco_criteria(s, mm, finals[v], check, H)
    return out


def git_commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, cwd=Path(__file__).parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def write(results: list[dict], meta: dict, name: str) -> None:
    lines = [
        "# Rollouts with ground contact: cgadyn.simulate against mujoco.rollout",
        "",
        f"Generated by `validation/contact_benchmark.py` ({meta['command']}) on "
        f"{meta['date']}, cgadyn at commit {meta['commit']}, MuJoCo {meta['mujoco']}. "
        f"Machine: {meta['machine']}, {meta['cores']} cores, shared with other jobs: load "
        f"average {meta['load'][0]:.2f} before, {meta['load'][1]:.2f} after. Best of "
        f"{meta['repeat']} round(s), every case once per round, compile time excluded.",
        "",
        "The scenes (the script's docstring says more): Gymnasium's Ant under uniform random "
        "controls (the same array for both), and solo12 dropped onto the ground under joint "
        "PD (cgadyn.PD; MuJoCo: the same PD as affine-bias actuators). Both engines step "
        "with Euler at the same time step and return every state.",
        "",
        "## Time, µs per rollout-step",
        "",
        "| scene | engine | MuJoCo variant | threads | rollouts × steps | rollout-steps taken "
        "| dt | seconds | µs per rollout-step | / cgadyn's |",
        "|---|---|---|---:|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        ours = {e["threads"]: e["us_per_rollout_step"] for e in r["timed"]
                if e["engine"] == "cgadyn"}
        for e in sorted(r["timed"], key=lambda e: (e["threads"], e["engine"] != "cgadyn")):
            variant = "" if e["engine"] == "cgadyn" else e["variant"]
            lines.append(f"| {r['scene']} | {e['engine']} | {variant} | {e['threads']} | "
                         f"{r['rollouts']} × {r['steps']} | {e['rollout_steps']} | "
                         f"{r['dt']:g} | {e['seconds']:.2f} "
                         f"| {e['us_per_rollout_step']:.2f} | "
                         f"{e['us_per_rollout_step'] / ours[e['threads']]:.2f} |")
    lines += [
        "",
        "The last column is the engine's time over cgadyn's at the same thread count (below "
        "1: MuJoCo is faster). cgadyn runs with the default `ContactSettings` (PGS, then "
        "ADMM where PGS stops short of the tolerance 1e-10; a step is kept if its residuals "
        "are within `accept` = 1e-6). A cgadyn rollout stops at a step whose residuals exceed "
        "that, or that diverges; the µs per rollout-step divide by the steps taken (column "
        "\"rollout-steps taken\"), and the rollouts stopped are counted below, with why.",
        "",
        "## Physical criteria on the same scenes",
        "",
        f"Deepest penetration: the least signed distance of a contact over every state of the "
        f"first {meta['check']} rollouts (cgadyn: `ground_contacts`; MuJoCo: "
        "`data.contact.dist` after each `mj_step` of the same rollouts re-run); negative: an "
        "overlap. Base height at the end: over every rollout of the timed run. Contacts at "
        "the end: the mean number of contact points at the last step.",
        "",
        "| scene | engine | deepest penetration (mm) | base z at the end: mean [min, max] (m)"
        " | contacts at the end | rollouts stopped |",
        "|---|---|---:|---|---:|---:|",
    ]
    for r in results:
        for who, c in r["criteria"].items():
            z = c["base_z"]
            lines.append(f"| {r['scene']} | {'cgadyn' if who == 'cgadyn' else 'MuJoCo, ' + who}"
                         f" | {_depth(c['min_distance'])} | {z['mean']:.4f} "
                         f"[{z['min']:.4f}, {z['max']:.4f}] | {c['contacts_end']:.1f} | "
                         f"{c['stopped']} |")
    lines += [
        "",
        "What differs between the engines, so that the criteria are read right: cgadyn's "
        "contacts are rigid (each step solves a velocity-level frictional complementarity "
        "problem, PGS then ADMM, and pulls an overlap back over a few steps), MuJoCo's are "
        "soft (a contact pushes in proportion to its penetration through `solref`/`solimp`, "
        "so a resting body sinks by an amount the stiffness sets). Gymnasium's ant.xml gives "
        "its geoms a 1 cm `margin`: MuJoCo's contacts act from 1 cm above the floor, so its "
        "ant rests higher and its distances are larger. cgadyn's meshes are convex hulls of "
        "at most 64 vertices, MuJoCo's its own full hulls. cgadyn holds the ant's joint "
        "limits as rigid unilateral rows of the same problem (K26); the ant's first MuJoCo "
        "variant as soft ones, the second not at all.",
    ]
    for r in results:
        if r.get("cgadyn_message"):
            lines += ["", f"Why cgadyn's {r['scene']} rollouts stopped: {r['cgadyn_message']}"]
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.md").write_text("\n".join(lines) + "\n")
    (RESULTS / f"{name}.json").write_text(json.dumps({"meta": meta, "results": results},
                                                     indent=1) + "\n")
    print("\n".join(lines))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rollouts", type=int, default=1024)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("--solo12-rollouts", type=int, default=None,
                   help="solo12's rollouts where they differ from --rollouts")
    p.add_argument("--solo12-steps", type=int, default=None,
                   help="solo12's steps where they differ from --steps")
    p.add_argument("--check-rollouts", type=int, default=4,
                   help="rollouts whose every state is checked for penetration")
    p.add_argument("--scenes", nargs="+", default=["ant", "solo12"],
                   choices=["ant", "solo12"])
    p.add_argument("--drop", type=float, default=0.1,
                   help="solo12's lowest foot above the ground at the start (m)")
    p.add_argument("--quick", action="store_true",
                   help="a smoke run: 16 rollouts x 100 steps, one round")
    p.add_argument("--name", default="contact", help="the results' file name")
    args = p.parse_args()
    if args.quick:
        args.rollouts, args.steps, args.repeat, args.check_rollouts = 16, 100, 1, 2
    import mujoco

    sizes = {"ant": (args.rollouts, args.steps),
             "solo12": (args.solo12_rollouts or args.rollouts, args.solo12_steps or args.steps)}
    threads = sorted({1, numba.config.NUMBA_NUM_THREADS})
    load = [os.getloadavg()[0]]
    results = []
    for name in args.scenes:
        rng = np.random.default_rng(0)
        B, H = sizes[name]
        s = ant(B, H, rng) if name == "ant" else solo12(B, H, rng, args.drop)
        results.append(measure(s, B, H, threads, args.repeat, args.check_rollouts))
    load.append(os.getloadavg()[0])
    (B, H), (Bs, Hs) = sizes["ant"], sizes["solo12"]
    meta = {"command": " ".join(["python validation/contact_benchmark.py", f"--rollouts {B}",
                                 f"--steps {H}", f"--repeat {args.repeat}"]
                                + ([f"--solo12-rollouts {Bs}", f"--solo12-steps {Hs}"]
                                   if (Bs, Hs) != (B, H) else [])),
            "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "commit": git_commit(), "mujoco": mujoco.__version__,
            "machine": cpu_model(), "cores": os.cpu_count(),
            "threads": threads, "load": load, "repeat": args.repeat,
            "check": args.check_rollouts}
    write(results, meta, args.name)


if __name__ == "__main__":
    main()
