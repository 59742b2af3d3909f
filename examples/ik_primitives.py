"""Put the panda's tool on a plane, then on a sphere, then through a line: tasks on CGA
primitives solved by ``cgadyn.inverse_kinematics``.

The tool frame is the hand's centre point, 0.1034 m along the hand's z axis. Each task moves
an object the tool carries onto a target primitive (``cgadyn.Task`` says which residual):

1. the tool's xy-plane onto a tilted table (plane onto plane): the tool touches the table
   and points into it, anywhere on it;
2. the tool's centre on a sphere of radius 0.15 m around an object (point on sphere);
3. the tool's z axis along a line through the workspace (line onto line): the tool points
   along the line, its centre anywhere on it.

    python examples/ik_primitives.py [--plot validation/results/ik_primitives.png]

``run()`` solves the three and returns, per task, the configuration, whether it converged,
the residual and the geometric check measured independently from the link placement.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import cgadyn
from cgadyn.cga.objects import Line, Plane, Point, Sphere

LINK = "panda_hand"
TOOL = np.eye(4)
TOOL[2, 3] = 0.1034
TABLE = (Point([0.5, -0.2, 0.1]), Point([0.5, 0.2, 0.15]), Point([0.3, 0.0, 0.1]))
CENTRE, RADIUS = np.array([0.45, 0.25, 0.35]), 0.15
LINE = (Point([0.3, -0.3, 0.4]), Point([0.5, -0.1, 0.2]))


def _tool_pose(model, q) -> np.ndarray:
    return cgadyn.link_placements(model, q)[model.link_index(LINK)] @ TOOL


def run() -> dict:
    """The three tasks: q, converged, |residual| and the independent geometric error."""
    model = cgadyn.load("panda")
    out = {}
    table = Plane.through(*TABLE)
    # the tool's xy plane, normal -z (pointing back out of the tool), onto the table
    tool_plane = Plane.through(Point([0, 0, 0]), Point([0, 1, 0]), Point([1, 0, 0]))
    res = cgadyn.inverse_kinematics(model, LINK, table, carried=tool_plane, tool=TOOL)
    a, b, c = (p.down() for p in TABLE)
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n)
    T = _tool_pose(model, res.q)
    out["plane"] = (res, max(abs(n @ (T[:3, 3] - a)), 1 - abs(n @ T[:3, 2])))
    res = cgadyn.inverse_kinematics(model, LINK, Sphere.from_center_radius(CENTRE, RADIUS),
                                    tool=TOOL)
    T = _tool_pose(model, res.q)
    out["sphere"] = (res, abs(np.linalg.norm(T[:3, 3] - CENTRE) - RADIUS))
    tool_axis = Line.through(Point([0, 0, 0]), Point([0, 0, 1]))
    res = cgadyn.inverse_kinematics(model, LINK, Line.through(*LINE), carried=tool_axis,
                                    tool=TOOL)
    T = _tool_pose(model, res.q)
    p0, p1 = (p.down() for p in LINE)
    u = (p1 - p0) / np.linalg.norm(p1 - p0)
    e = T[:3, 3] - p0
    out["line"] = (res, max(np.linalg.norm(e - u * (u @ e)), np.linalg.norm(T[:3, 2] - u)))
    return out


def plot(results: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = cgadyn.load("panda")
    chain = [model.link_index(f"panda_link{i}") for i in range(8)] + [model.link_index(LINK)]
    fig = plt.figure(figsize=(15, 5.2))
    titles = {"plane": "tool plane onto a tilted table", "sphere": "tool centre on a sphere",
              "line": "tool axis along a line"}
    for k, (name, (res, err)) in enumerate(results.items()):
        ax = fig.add_subplot(1, 3, k + 1, projection="3d")
        P = cgadyn.link_placements(model, res.q)
        pts = np.array([P[i][:3, 3] for i in chain] + [(P[chain[-1]] @ TOOL)[:3, 3]])
        ax.plot(*pts.T, "-o", color="0.25", lw=3, ms=4, label="panda")
        T = P[chain[-1]] @ TOOL
        ax.quiver(*T[:3, 3], *(0.12 * T[:3, 2]), color="crimson", lw=2, label="tool z axis")
        if name == "plane":
            a, b, c = (p.down() for p in TABLE)
            s, t = np.meshgrid(np.linspace(-0.6, 0.6, 2), np.linspace(-0.8, 0.8, 2))
            o = T[:3, 3]  # the patch of the (infinite) table around the contact
            X = o[:, None, None] + (b - a)[:, None, None] * s + (c - a)[:, None, None] * t
            ax.plot_surface(*X, alpha=0.3, color="tab:blue")
        elif name == "sphere":
            u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
            ax.plot_wireframe(CENTRE[0] + RADIUS * np.cos(u) * np.sin(v),
                              CENTRE[1] + RADIUS * np.sin(u) * np.sin(v),
                              CENTRE[2] + RADIUS * np.cos(v), color="tab:blue", lw=0.5)
        else:
            p0, p1 = (p.down() for p in LINE)
            L = np.array([p0 + s * (p1 - p0) for s in (-1.5, 2.5)])
            ax.plot(*L.T, color="tab:blue", lw=2, label="target line")
        ax.scatter(*T[:3, 3], color="crimson", s=30)
        ax.set_title(f"{titles[name]}\n|r| = {res.error:.1e}, geometric error {err:.1e}",
                     fontsize=10)
        ax.set_xlim(-0.2, 0.8)
        ax.set_ylim(-0.5, 0.5)
        ax.set_zlim(0.0, 1.0)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
    fig.suptitle("cgadyn.inverse_kinematics on CGA primitives (panda, tool centre point)",
                 y=0.99)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    fig.savefig(path, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plot", type=Path,
                    default=Path(__file__).resolve().parent.parent / "validation" / "results"
                    / "ik_primitives.png")
    args = ap.parse_args()
    results = run()
    for name, (res, err) in results.items():
        print(f"{name:7s} converged {res.converged}, |r| = {res.error:.2e}, "
              f"{res.iterations} iterations, geometric error {err:.2e}")
    plot(results, args.plot)
    print(f"figure: {args.plot}")


if __name__ == "__main__":
    main()
