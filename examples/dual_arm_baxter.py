"""Baxter carries a box with both hands: the hands keep their relative pose while their
absolute pose (halfway between them, ``cgadyn.cooperative_space``) follows a circle.

Two cooperative tasks (``cgadyn.CooperativeTask``), solved by ``cgadyn.solve_tasks`` at each
of ``--waypoints`` points of the circle, each from the previous answer:

1. ``relative``: the right gripper seen from the left one stays what it was at the start;
2. ``absolute``: the pose halfway between the grippers moves along a circle of radius 0.1 m
   in the vertical plane in front of the robot, its orientation unchanged.

    python examples/dual_arm_baxter.py [--plot validation/results/dual_arm_baxter.png]

``run()`` returns, per waypoint, whether it converged and two errors measured from the
grippers' placements ``T_L, T_R`` (independently of the tasks): how far the relative pose
``T_L⁻¹ T_R`` drifted from the start, and how far the target ``T_a`` is from being the
absolute pose, whose square seen from the left gripper is the relative pose:
``(T_L⁻¹ T_a)² = T_L⁻¹ T_R``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import cgadyn
from cgadyn.tasks.ik import middle_configuration

LEFT, RIGHT = "left_gripper", "right_gripper"
RADIUS = 0.1


def _log6(T: np.ndarray) -> np.ndarray:
    """``(v, ω)`` of a rigid transform's logarithm, from its matrix (numpy only)."""
    R, p = T[:3, :3], T[:3, 3]
    theta = np.arccos(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0))
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    w = w * (0.5 if theta < 1e-8 else theta / (2.0 * np.sin(theta)))
    W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    k = 1.0 / 12.0 if theta < 1e-8 else (
        1.0 - theta * np.sin(theta) / (2.0 * (1.0 - np.cos(theta)))) / theta ** 2
    return np.concatenate([(np.eye(3) - 0.5 * W + k * W @ W) @ p, w])


def run(waypoints: int = 24) -> list[dict]:
    model = cgadyn.load("baxter")
    q = middle_configuration(model)
    Ma, _, Mr, _ = cgadyn.cooperative_space(model, q, LEFT, RIGHT)
    start = Ma.matrix()
    relative = cgadyn.CooperativeTask(model, LEFT, RIGHT, "relative", Mr)
    out = []
    for s in np.linspace(0.0, 2.0 * np.pi, waypoints + 1)[1:]:
        offset = RADIUS * np.array([0.0, np.sin(s), 1.0 - np.cos(s)])  # y-z circle
        target = start.copy()
        target[:3, 3] += offset
        res = cgadyn.solve_tasks(model, [relative, cgadyn.CooperativeTask(
            model, LEFT, RIGHT, "absolute", target)], q)
        q = res.q
        T = cgadyn.link_placements(model, q)
        TL, TR = T[model.link_index(LEFT)], T[model.link_index(RIGHT)]
        drift = np.linalg.norm(_log6(np.linalg.inv(Mr.matrix()) @ np.linalg.inv(TL) @ TR))
        H = np.linalg.inv(TL) @ target
        absolute = np.linalg.norm(_log6(np.linalg.inv(H @ H) @ np.linalg.inv(TL) @ TR))
        out.append({"converged": res.converged, "iterations": res.iterations,
                    "relative_drift": float(drift), "absolute_error": float(absolute),
                    "left": TL[:3, 3], "right": TR[:3, 3], "target": target[:3, 3]})
    return out


def _plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True)
    for ax, (i, name) in zip(axes, [(0, "x"), (2, "z")], strict=True):
        for key, style, label in [("left", "o-", LEFT), ("right", "s-", RIGHT),
                                  ("target", "k+-", "absolute pose target")]:
            P = np.array([r[key] for r in rows])
            ax.plot(P[:, 1], P[:, i], style, ms=3, lw=1, label=label)
        for r in rows[::3]:  # the box between the hands
            ax.plot([r["left"][1], r["right"][1]], [r["left"][i], r["right"][i]],
                    color="0.75", lw=0.8)
        ax.set_ylabel(f"{name} (m)")
        ax.set_aspect("equal")
    axes[1].set_xlabel("y (m)")
    axes[0].set_title("baxter: relative pose held, absolute pose on a circle\n"
                      "(top: seen from above; bottom: from the front)", fontsize=10)
    axes[1].legend(loc="upper center", bbox_to_anchor=(0.5, -0.6), ncol=3, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--waypoints", type=int, default=24)
    ap.add_argument("--plot", type=Path)
    args = ap.parse_args()
    rows = run(args.waypoints)
    print(f"{sum(r['converged'] for r in rows)}/{len(rows)} waypoints converged; worst "
          f"relative drift {max(r['relative_drift'] for r in rows):.1e}, worst absolute "
          f"pose error {max(r['absolute_error'] for r in rows):.1e}; mean iterations "
          f"{np.mean([r['iterations'] for r in rows]):.1f}")
    if args.plot:
        _plot(rows, args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
