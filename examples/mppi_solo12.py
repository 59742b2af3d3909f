"""Sampling-based model predictive control (MPPI) of solo12 standing on the ground, with
batched contact rollouts of ``cgadyn.simulate`` as its model: it keeps the robot standing
through a push on its base that tips it, then moves the base to a target over its feet,
which the same joint PD alone, holding one posture, cannot.

This is what the CGA paper says its forward dynamics are for. Every control period the
controller

1. draws ``samples`` perturbations ``ε_k`` of its nominal plan ``U`` (feed-forward joint
   torques, piecewise constant over ``knots`` periods, added to a joint PD around the
   standing posture),
2. rolls them all out from the measured state in one parallel ``simulate`` call with the
   ground (``world=cgadyn.World()``, solo12's collision hulls; the contact step of
   ``docs/contact.md``),
3. scores each rollout ``S_k`` (base position and height against the target, base
   orientation, base velocity, torque) and averages the perturbations with the weights of
   path-integral control (Williams et al., 2017), ``w_k ∝ exp(-(S_k - min S) / λ)``,
   ``U ← U + Σ w_k ε_k``,
4. applies the first period of ``U`` to the robot (another ``simulate`` call, the "real"
   robot, which alone feels the push) and shifts the plan by one period.

The same robot under the same PD alone is the baseline. Run::

    python examples/mppi_solo12.py [--seconds 1.5] [--samples 64] [--knots 10]
                                   [--plot validation/results/mppi_solo12.png]

``run(...)`` does it without printing or plotting and returns a dict of the results, for
tests. The push is a constant force on the base during ``push`` seconds; the target a base
position within reach of the standing feet (walking is not planned here).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import cgadyn

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_PLOT = ROOT / "validation" / "results" / "mppi_solo12.png"
STAND = np.tile([0.0, 0.8, -1.6], 4)
"""solo12's standing posture: hip abduction, hip flexion, knee of each leg (rad)."""
KP, KD = 20.0, 0.5
"""The joint PD around ``STAND`` (N m / rad, N m s / rad), the same with and without MPPI."""
WEIGHTS = {"position": 2000.0, "height": 2000.0, "tilt": 200.0, "velocity": 2.0,
           "torque": 0.001}
"""Running-cost weights: base position error in the ground plane (m), base height error
(m), base tilt (the rotation's x, y quaternion components), base velocity (twist), and the
feed-forward torque (N m)."""


def standing(model, shapes):
    """solo12 in ``STAND`` with its lowest foot on the ground, at rest."""
    q = cgadyn.neutral(model)
    q[7:] = STAND
    q[2] -= cgadyn.ground_contacts(model, shapes, q, margin=1.0).distance.min()
    return q, np.zeros(model.nv)


def cost(traj, target: np.ndarray, u: np.ndarray) -> np.ndarray:
    """``S_k`` of each rollout (B,): the running cost summed over its kept states
    (``WEIGHTS``) plus, per kept state, the mean squared torque of its plan ``u`` (B,
    steps, nv)."""
    q, v = np.asarray(traj.q), np.asarray(traj.v)
    xy = np.sum((q[..., :2] - target[:2]) ** 2, axis=-1)
    z = (q[..., 2] - target[2]) ** 2
    tilt = np.sum(q[..., 3:5] ** 2, axis=-1)
    speed = np.sum(v[..., :6] ** 2, axis=-1)
    running = (WEIGHTS["position"] * xy + WEIGHTS["height"] * z + WEIGHTS["tilt"] * tilt
               + WEIGHTS["velocity"] * speed)
    # a rollout that stopped early (NaN after its last state) scores its worst
    running = np.where(np.isfinite(running), running, np.nan)
    effort = np.mean(np.sum(u ** 2, axis=-1), axis=-1)  # per step, as the states are kept
    total = np.nansum(running, axis=-1) + WEIGHTS["torque"] * running.shape[-1] * effort
    return np.where(np.isfinite(total) & (traj.completed == u.shape[1]), total, np.inf)


class MPPI:
    """The controller: a plan of ``knots`` feed-forward torques (knots, nv), each held for
    ``period`` steps of ``dt``, refined from ``samples`` noisy rollouts per period."""

    def __init__(self, model, shapes, dt: float, period: int, knots: int, samples: int,
                 sigma: float, temperature: float, seed: int = 0):
        self.model, self.shapes, self.dt = model, shapes, dt
        self.period, self.knots, self.samples = period, knots, samples
        self.sigma, self.temperature = sigma, temperature
        self.rng = np.random.default_rng(seed)
        self.plan = np.zeros((knots, model.nv))
        self.actuated = np.asarray(model.actuated)
        self.pd = cgadyn.PD(kp=KP, kd=KD, q_ref=self.reference(), gravity_compensation=False)

    def reference(self) -> np.ndarray:
        q = cgadyn.neutral(self.model)
        q[7:] = STAND
        return q

    def torques(self, plans: np.ndarray) -> np.ndarray:
        """(B, knots, nv) plans as (B, steps, nv) torque sequences."""
        return np.repeat(plans, self.period, axis=-2)

    def update(self, q: np.ndarray, v: np.ndarray, target: np.ndarray) -> np.ndarray:
        """One MPPI iteration from the measured state; returns the torques (period, nv) to
        apply now, and shifts the plan."""
        noise = self.rng.normal(0.0, self.sigma, (self.samples, self.knots, self.model.nv))
        noise[..., ~self.actuated] = 0.0
        noise[0] = 0.0  # the nominal plan itself is one of the samples
        plans = self.plan + noise
        u = self.torques(plans)
        traj = cgadyn.simulate(self.model, q, v, self.dt, u.shape[1], tau=u,
                               controller=self.pd, integrator="semi_implicit_euler",
                               world=cgadyn.World(), collisions=self.shapes,
                               record_every=self.period)
        S = cost(traj, target, u)
        finite = np.isfinite(S)
        if not finite.any():
            raise RuntimeError("every MPPI rollout stopped early: " + traj.message)
        S = np.where(finite, S, np.max(S[finite]))
        w = np.exp(-(S - S.min()) / (self.temperature * max(np.ptp(S), 1e-12)))
        w /= w.sum()
        self.plan = self.plan + np.tensordot(w, noise, axes=1)
        now = np.repeat(self.plan[:1], self.period, axis=0)
        self.plan = np.concatenate([self.plan[1:], self.plan[-1:]])  # shift, hold the last
        return now


def push_force(model, q: np.ndarray, force: np.ndarray) -> np.ndarray:
    """``f_ext`` (n, 6) of a world-frame force on the base at its origin: Pinocchio's
    ``[f, τ]`` in the base joint's frame."""
    f = np.zeros((model.njoints, 6))
    x, y, z, w = q[3:7]
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    f[0, :3] = R.T @ force
    return f


def run(seconds: float = 1.5, dt: float = 1e-3, period: int = 20, knots: int = 10,
        samples: int = 64, sigma: float = 2.0, temperature: float = 0.1,
        push: tuple = (0.2, 0.1, (35.0, 0.0, 0.0)), shift: tuple = (0.03, 0.02, -0.02),
        shift_at: float = 0.8, seed: int = 0) -> dict:
    """Simulate ``seconds`` of solo12 standing, pushed on its base at ``push[0]`` s for
    ``push[1]`` s with the world-frame force ``push[2]`` (N), and asked at ``shift_at`` s to
    move its base by ``shift`` (m) from where it stood, once under MPPI and once under the
    PD alone. Returns the times, both base trajectories, the target and the errors."""
    model = cgadyn.load("solo12")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        shapes = cgadyn.collision_model(model, "solo12")
    q0, v0 = standing(model, shapes)
    home = q0[:3].copy()
    periods = int(round(seconds / (dt * period)))
    out = {"t": dt * period * np.arange(periods + 1), "dt": dt, "period": period,
           "samples": samples, "knots": knots, "push": push, "shift": shift,
           "shift_at": shift_at}
    spent = []
    for name in ("mppi", "pd"):
        mppi = MPPI(model, shapes, dt, period, knots, samples, sigma, temperature, seed)
        q, v = q0.copy(), v0.copy()
        base, targets = [q[:3].copy()], [home.copy()]
        for k in range(periods):
            t = k * dt * period
            target = home + (np.asarray(shift) if t >= shift_at else 0.0)
            start = time.perf_counter()
            tau = mppi.update(q, v, target) if name == "mppi" else \
                np.zeros((period, model.nv))
            if name == "mppi":
                spent.append(time.perf_counter() - start)
            pushed = push[0] <= t < push[0] + push[1]
            f = push_force(model, q, np.asarray(push[2], float)) if pushed else None
            traj = cgadyn.simulate(model, q, v, dt, period, tau=tau, controller=mppi.pd,
                                   integrator="semi_implicit_euler", world=cgadyn.World(),
                                   collisions=shapes, f_ext=f, final_only=True)
            if traj.diverged:
                raise RuntimeError(f"{name}: {traj.message}")
            q, v = np.asarray(traj.q)[-1], np.asarray(traj.v)[-1]
            base.append(q[:3].copy())
            targets.append(target)
        out[name] = np.array(base)
        out["target"] = np.array(targets)
    out["update_seconds"] = float(np.median(spent)) if spent else 0.0
    late = out["t"] >= shift_at + 0.5 * (seconds - shift_at)
    for name in ("mppi", "pd"):
        err = np.linalg.norm(out[name] - out["target"], axis=1)
        out[f"{name}_final_error"] = float(err[-1])
        out[f"{name}_late_error"] = float(err[late].mean()) if late.any() else float(err[-1])
        during = (out["t"] >= push[0]) & (out["t"] < shift_at)
        out[f"{name}_push_excursion"] = float(np.max(np.linalg.norm(
            out[name][during] - home, axis=1))) if during.any() else 0.0
        before = np.nonzero(out["t"] < shift_at)[0]  # where the push left it at the shift
        out[f"{name}_recovered"] = float(np.linalg.norm(out[name][before[-1]] - home)) \
            if before.size else 0.0
    return out


def plot(result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = result["t"]
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True, constrained_layout=True)
    labels = ("base x (m)", "base y (m)", "base z (m)")
    for i, (ax, label) in enumerate(zip(axes, labels, strict=True)):
        ax.plot(t, result["mppi"][:, i], lw=1.5, label="MPPI + PD")
        ax.plot(t, result["pd"][:, i], lw=1.2, ls="--", label="PD alone")
        ax.plot(t, result["target"][:, i], lw=0.8, color="k", label="target")
        t0, span, _ = result["push"]
        ax.axvspan(t0, t0 + span, color="tab:red", alpha=0.15,
                   label="push on the base" if i == 0 else None)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("t (s)")
    fig.suptitle(f"solo12 on the ground: MPPI with {result['samples']} contact rollouts of "
                 f"{result['knots'] * result['period']} steps per {result['period']} ms")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=1.5)
    p.add_argument("--samples", type=int, default=64)
    p.add_argument("--knots", type=int, default=10)
    p.add_argument("--plot", type=Path, default=DEFAULT_PLOT)
    args = p.parse_args(argv)
    result = run(seconds=args.seconds, samples=args.samples, knots=args.knots)
    for name in ("mppi", "pd"):
        print(f"{name:4s}: push excursion {result[f'{name}_push_excursion'] * 1e3:.1f} mm, "
              f"from home at {result['shift_at']:g} s {result[f'{name}_recovered'] * 1e3:.1f} "
              f"mm, "
              f"error to the target late {result[f'{name}_late_error'] * 1e3:.1f} mm, "
              f"at the end {result[f'{name}_final_error'] * 1e3:.1f} mm")
    plot(result, args.plot)
    print(f"plot: {args.plot}")
    write(result, args.plot.with_suffix(".md"), argv)
    return 0


def write(result: dict, path: Path, argv: list[str] | None) -> None:
    """The run's numbers as markdown beside its plot."""
    import datetime
    import platform

    import numba

    t0, span, force = result["push"]
    lines = [
        "# MPPI on solo12 with batched contact rollouts",
        "",
        f"`python examples/mppi_solo12.py {' '.join(argv or sys.argv[1:])}`".replace(" `", "`"),
        f"({datetime.date.today()}, {platform.processor() or platform.machine()}, "
        f"{result['samples']} rollouts of {result['knots'] * result['period']} steps of "
        f"{result['dt'] * 1e3:g} ms per {result['period']} ms period; a push of "
        f"{tuple(force)} N on the base from {t0:g} s for {span:g} s; the target "
        f"{tuple(result['shift'])} m from where it stood from {result['shift_at']:g} s). "
        f"One control period's rollouts and update took {result['update_seconds']:.2f} s "
        f"(median, {numba.get_num_threads()} threads): the example runs slower than real "
        f"time.",
        "",
        "| controller | push excursion (mm) | from home at the shift (mm) | "
        "error to the target, late (mm) | at the end (mm) |",
        "|---|---|---|---|---|",
    ]
    for name, label in (("mppi", "MPPI + joint PD"), ("pd", "joint PD alone")):
        lines.append(f"| {label} | {result[f'{name}_push_excursion'] * 1e3:.1f} | "
                     f"{result[f'{name}_recovered'] * 1e3:.1f} | "
                     f"{result[f'{name}_late_error'] * 1e3:.1f} | "
                     f"{result[f'{name}_final_error'] * 1e3:.1f} |")
    lines += ["", f"![base position]({path.with_suffix('.png').name})", ""]
    path.write_text("\n".join(lines))
    print(f"results: {path}")


if __name__ == "__main__":
    sys.exit(main())
