"""The physical criteria of our contact steps (docs/contact.md, K31-K34) on the contact
benchmark's scenes (``contact_benchmark.py``: Gymnasium's Ant under uniform random controls,
solo12 dropped under joint PD), and MuJoCo's penetration and cone numbers on the same
scenes. Writes ``validation/results/contact_criteria.md``.

cgadyn: ``Trajectory.contact_criteria()`` of each rollout (every state kept), the largest
of each criterion over every step, and over the steps whose solver met its tolerance (the
others end within ``ContactSettings.accept``). MuJoCo (the scene as the benchmark builds it,
Euler, re-run with ``mj_step`` from the same states with the same controls): at each step,
each contact's force in its frame (``mj_contactForce``: normal, then the two tangents) gives
K32's cone violation ``max(0, ‖f_T‖ - μ f_N, -f_N)`` and its ``dist`` K34's penetration.
MuJoCo's contacts are soft (a force that grows with the penetration and acts within a
margin) with a pyramidal cone by default: its Signorini numbers are not zero by design, so
they are not computed here.

Run:  python validation/contact_criteria.py [--rollouts 4] [--steps 1000] [--drop 0.1]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import contact_benchmark as bench  # noqa: E402

from cgadyn.contact.criteria import CRITERIA  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
UNITS = {"signorini": "W", "approach": "m/s", "cone": "N", "dissipation": "W",
         "friction_direction": "N", "penetration": "m"}


def ours(scene, steps: int) -> dict:
    """The largest of each criterion over every rollout's steps, all and solved ones."""
    import cgadyn

    tr = bench.run_cgadyn(scene, steps, 2)
    history = tr.contact_criteria()
    solved = tr.contact_residual[:, :-1] <= cgadyn.ContactSettings().tolerance
    out = {"all": history.maxima(), "solved_share": float(np.mean(solved)),
           "stopped": int(np.count_nonzero(tr.diverged)), "unmatched": history.unmatched,
           "reordered": history.reordered,
           "contacts": float(np.mean(history.contacts[history.contacts >= 0]))}
    out["solved"] = {n: float(np.nanmax(np.where(solved, getattr(history, n), np.nan)))
                     for n in CRITERIA}
    return out


def mujoco(scene, steps: int) -> dict:
    """MuJoCo's largest cone violation and penetration over the same rollouts."""
    import mujoco as mj

    mm = next(iter(scene.mujoco.values()))
    d = mj.MjData(mm)
    spec = mj.mjtState.mjSTATE_FULLPHYSICS
    B = scene.q0.shape[0]
    state0 = bench.mujoco_states(scene, mm)
    ctrl = bench.mujoco_ctrl(scene, slice(None), steps)
    cone = depth = 0.0
    f = np.zeros(6)
    for b in range(B):
        mj.mj_setState(mm, d, state0[b], spec)
        for k in range(steps):
            d.ctrl[:] = ctrl[min(b, ctrl.shape[0] - 1), min(k, ctrl.shape[1] - 1)]
            mj.mj_step(mm, d)
            for i in range(d.ncon):  # the contacts and forces of the step just taken
                c = d.contact[i]
                mj.mj_contactForce(mm, d, i, f)
                mu = c.friction[0]
                cone = max(cone, np.linalg.norm(f[1:3]) - mu * f[0], -f[0])
                depth = max(depth, -c.dist)
    return {"cone": cone, "penetration": depth, "variant": next(iter(scene.mujoco)),
            "cone_type": "elliptic" if mm.opt.cone == mj.mjtCone.mjCONE_ELLIPTIC
            else "pyramidal"}


def write(rows: list[tuple], args) -> Path:
    lines = ["# Physical criteria of the contact steps (K31-K34)", "",
             f"`python validation/contact_criteria.py --rollouts {args.rollouts} --steps "
             f"{args.steps} --drop {args.drop}`: the benchmark's scenes "
             "(`contact_benchmark.py`), the largest value of each criterion over every step "
             "of every rollout (docs/contact.md, \"The physical criteria of a step\"). "
             "cgadyn: all steps, and the steps whose solver met its tolerance (1e-10; the "
             "others end with residuals within `accept`, 1e-6). MuJoCo: its soft contacts, "
             "the same states and controls, `mj_step`.", "",
             "| scene | engine | steps | " + " | ".join(f"{n} ({UNITS[n]})" for n in CRITERIA)
             + " |", "|---|---|---|" + "---|" * len(CRITERIA)]
    for name, o, m in rows:
        for label, key in (("cgadyn, all steps", "all"), ("cgadyn, solved steps", "solved")):
            lines.append(f"| {name} | {label} | "
                         + ("all" if key == "all" else f"{100 * o['solved_share']:.1f} %")
                         + " | " + " | ".join(f"{o[key][n]:.2e}" for n in CRITERIA) + " |")
        mj = {"cone": f"{m['cone']:.2e}", "penetration": f"{m['penetration']:.2e}"}
        lines.append(f"| {name} | MuJoCo ({m['cone_type']} cone) | all | "
                     + " | ".join(mj.get(n, "—") for n in CRITERIA) + " |")
    lines += ["", "cgadyn's rollouts: " + "; ".join(
        f"{n}: {o['stopped']} stopped, {o['contacts']:.1f} contacts per step on average, "
        f"{o['unmatched']} steps whose contacts found again differ from the loop's, "
        f"{o['reordered']} whose slots were matched to the points in another order"
        for n, o, _ in rows) + ".", "",
        "MuJoCo's Signorini and dissipation numbers are left out: its contacts are soft "
        "(`solref`/`solimp`: a force that grows with the penetration, acting within the "
        "geoms' margin), so a force on an opening contact and a penetration are part of its "
        "model, not errors of its solver; its default cone is a pyramid, inside Coulomb's "
        "circular cone."]
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / "contact_criteria.md"
    path.write_text("\n".join(lines) + "\n")
    return path


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rollouts", type=int, default=4)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--drop", type=float, default=0.1)
    args = p.parse_args()
    rng = np.random.default_rng(0)
    rows = []
    for scene in (bench.ant(args.rollouts, args.steps, rng),
                  bench.solo12(args.rollouts, args.steps, rng, args.drop)):
        o, m = ours(scene, args.steps), mujoco(scene, args.steps)
        print(scene.name, o, m, flush=True)
        rows.append((scene.name, o, m))
    print(write(rows, args))


if __name__ == "__main__":
    main()
