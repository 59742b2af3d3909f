"""A trajectory as a figure: joint positions, joint velocities and the energy over time."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["plot_trajectory"]


def _coordinate_labels(model) -> list[str]:
    """One label per configuration coordinate: the joint's name, indexed for multi-dof."""
    labels = []
    for j, name in enumerate(model.joint_names):
        n = int(model.idx_q[j + 1] - model.idx_q[j])
        labels += [name] if n == 1 else [f"{name}[{k}]" for k in range(n)]
    return labels


def plot_trajectory(model, traj, path: str | os.PathLike, title: str | None = None) -> Path:
    """Write a figure of one trajectory (``cgadyn.simulate``'s result) to ``path``: joint
    positions q(t), velocities v(t), and kinetic, potential and total energy.

    The format follows the extension (any that matplotlib writes); the path is checked
    first by ``cgadyn.commands.common.check_plot_path`` (a ``UsageError`` naming the
    problem)."""
    from ..commands.common import check_plot_path

    out = check_plot_path(str(path))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.asarray(traj.t)
    if np.asarray(traj.q).ndim != 2:
        raise ValueError(f"plot_trajectory draws one rollout; got q of shape "
                         f"{np.shape(traj.q)}")
    fig, (ax_q, ax_v, ax_e) = plt.subplots(3, 1, figsize=(8, 9), sharex=True,
                                           constrained_layout=True)
    labels = _coordinate_labels(model)
    for i, label in enumerate(labels):
        ax_q.plot(t, traj.q[:, i], lw=1, label=label)
    for i in range(model.nv):
        ax_v.plot(t, traj.v[:, i], lw=1)
    ax_q.set_ylabel("q (rad, m)")
    ax_v.set_ylabel("v (rad/s, m/s)")
    if len(labels) <= 12:
        ax_q.legend(fontsize=7, ncol=min(4, len(labels)), loc="upper right")
    ax_e.plot(t, traj.kinetic, lw=1, label="kinetic T")
    ax_e.plot(t, traj.potential, lw=1, label="potential U")
    ax_e.plot(t, traj.energy, lw=1.5, color="k", label="total T + U")
    ax_e.set_ylabel("energy (J)")
    ax_e.set_xlabel("t (s)")
    ax_e.legend(fontsize=7, loc="upper right")
    for ax in (ax_q, ax_v, ax_e):
        ax.grid(alpha=0.3)
    fig.suptitle(title or f"{model.name}: {traj.integrator}, dt = {traj.dt:g} s")
    try:
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return out
