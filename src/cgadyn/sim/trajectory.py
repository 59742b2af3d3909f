"""The result of ``simulate``: states, accelerations and energies at every step."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Trajectory:
    """Rollouts of ``steps`` steps of ``dt`` from ``t = 0``.

    One rollout: ``q`` (steps+1, nq), ``v``, ``a`` (steps+1, nv), ``kinetic``,
    ``potential``, ``energy = kinetic + potential`` (steps+1,); B rollouts: the same with a
    leading B. ``a[i]`` is the acceleration at state i (at the last state with the last
    open-loop torque). ``completed``: the steps each rollout completed (an int, or (B,));
    ``diverged``: whether it stopped early because its state stopped being finite or ABA
    failed (bool, or (B,)); ``message`` says why ("" when every rollout completed).

    A rollout that stopped holds its states up to the last one reached: one rollout's
    arrays (and ``t``) are cut there, B rollouts keep their common length with NaN after
    each stop (``simulate`` also warns, ``SimulationDiverged``).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    completed: int | np.ndarray
    diverged: bool | np.ndarray
    dt: float
    integrator: str
    message: str = ""

    @property
    def energy(self) -> np.ndarray:
        """The total energy ``kinetic + potential`` at every state."""
        return self.kinetic + self.potential

    @property
    def batch(self) -> bool:
        """True for B rollouts."""
        return self.q.ndim == 3

    def energy_drift(self) -> float | np.ndarray:
        """``max_i |E_i - E_0| / |E_0|`` over the states reached (per rollout for B), the
        relative drift of the total energy (meaningful for passive runs); the absolute
        drift where ``E_0 = 0``."""
        e = self.energy
        drift = np.nanmax(np.abs(e - e[..., :1]), axis=-1)
        scale = np.abs(e[..., 0])
        out = np.where(scale > 0, drift / np.where(scale > 0, scale, 1.0), drift)
        return float(out) if out.ndim == 0 else out
