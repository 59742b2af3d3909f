"""A trajectory as a figure: joint positions, joint velocities and the energy over time."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .._paths import check_plot_path

__all__ = ["plot_trajectory", "trajectory_figure"]


def _coordinate_labels(model, velocity: bool = False) -> list[str]:
    """One label per configuration (or velocity) coordinate: the joint's name, with the
    coordinate's for a joint of several (a free flyer's x, y, z, qx, ... or vx, vy, ...)."""
    return model.coordinate_names(velocity)


def _styles(count: int) -> list[dict]:
    """A colour and line style per curve, distinct up to 40 curves: tab10 for a few,
    tab20 beyond, then tab20 again dashed (the default cycle repeats after ten, which
    makes a legend of solo12's 19 coordinates ambiguous)."""
    import matplotlib

    cmap = matplotlib.colormaps["tab10" if count <= 10 else "tab20"]
    n = cmap.N
    dashes = ("-", "--", ":", "-.")
    return [{"color": cmap(i % n), "linestyle": dashes[(i // n) % len(dashes)]}
            for i in range(count)]


def _curves(ax, t: np.ndarray, x: np.ndarray, labels: list[str], ylabel: str) -> None:
    """One curve per coordinate, each labelled, with a legend beside the panel in as many
    columns as it takes to stay the panel's height (every coordinate named, however many)."""
    for i, (label, style) in enumerate(zip(labels, _styles(len(labels)), strict=True)):
        ax.plot(t, x[:, i], lw=1, label=label, **style)
    ax.set_ylabel(ylabel)
    ncol = 1 if len(labels) <= 12 else 2 if len(labels) <= 30 else 3
    ax.legend(fontsize=7 if len(labels) <= 12 else 6, ncol=ncol, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, handlelength=1.6,
              columnspacing=1.0, frameon=False)


def plot_trajectory(model, traj, path: str | os.PathLike, title: str | None = None) -> Path:
    """Write a figure of one trajectory (``cgadyn.simulate``'s result) to ``path``: joint
    positions q(t), velocities v(t), and kinetic, potential and total energy (and the
    contact forces of a rollout with a world). Every
    coordinate is named in a legend beside its panel, in columns when there are many.

    The format follows the extension (any that matplotlib writes); the path is checked
    first by ``cgadyn._paths.check_plot_path`` (a ``UsageError`` naming the
    problem)."""
    out = check_plot_path(str(path))
    import matplotlib.pyplot as plt

    fig = trajectory_figure(model, traj, title)
    try:
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return out


def _contact_panel(ax, model, t: np.ndarray, traj) -> None:
    """The total contact force on the robot (world x, y, z) next to its weight ``m g``, and
    the number of contacts on a second axis."""
    total = np.nansum(np.asarray(traj.contact_forces), axis=-2)
    for i, axis in enumerate("xyz"):
        ax.plot(t, total[:, i], lw=1.5 if axis == "z" else 1, label=f"contact force {axis}")
    weight = float(np.sum(model.body_mass)) * 9.81
    ax.axhline(weight, color="k", lw=0.8, ls="--", label="weight m g")
    ax.set_yscale("symlog", linthresh=weight)  # an impact's peak beside the weight held
    ax.set_ylabel("force (N)")
    count = ax.twinx()
    count.step(t, np.asarray(traj.contact_count), where="post", color="0.6", lw=0.8)
    count.set_ylabel("contacts", color="0.5")


def trajectory_figure(model, traj, title: str | None = None):
    """The matplotlib figure of :func:`plot_trajectory` (three panels: q, v, energy; a
    fourth, the contact forces, for a rollout with a world), drawn on the Agg backend; the
    caller closes it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.asarray(traj.t)
    if np.asarray(traj.q).ndim != 2:
        raise ValueError(f"plot_trajectory draws one rollout; got q of shape "
                         f"{np.shape(traj.q)}")
    wide = max(model.nq, model.nv) > 12
    contact = traj.contact_forces is not None
    fig, axes = plt.subplots(4 if contact else 3, 1,
                             figsize=(11 if wide else 9.5, 11.5 if contact else 9),
                             sharex=True, constrained_layout=True)
    ax_q, ax_v, ax_e = axes[:3]
    _curves(ax_q, t, np.asarray(traj.q), _coordinate_labels(model), "q (rad, m)")
    _curves(ax_v, t, np.asarray(traj.v), _coordinate_labels(model, velocity=True),
            "v (rad/s, m/s)")
    ax_e.plot(t, traj.kinetic, lw=1, label="kinetic T")
    ax_e.plot(t, traj.potential, lw=1, label="potential U")
    ax_e.plot(t, traj.energy, lw=1.5, color="k", label="total T + U")
    ax_e.set_ylabel("energy (J)")
    ax_e.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                frameon=False)
    if contact:
        _contact_panel(axes[3], model, t, traj)
        axes[3].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.07, 1.0),
                       borderaxespad=0.0, frameon=False)
    axes[-1].set_xlabel("t (s)")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(title or f"{model.name}: {traj.integrator}, dt = {traj.dt:g} s")
    return fig
