"""The result of ``simulate``: states, accelerations and energies at every step."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class Deferred:
    """Energies computed when first read: ``compute()`` returns ``(kinetic, potential)``,
    called at most once (``simulate`` passes one, shared by both fields, so that a rollout
    whose energy is never read does not pay for it)."""

    def __init__(self, compute):
        self._compute = compute
        self._value = None

    def value(self) -> tuple[np.ndarray, np.ndarray]:
        if self._value is None:
            self._value = self._compute()
            self._compute = None
        return self._value


class _Energy:
    """A field of ``Trajectory`` (``kinetic``, column 0, or ``potential``, column 1) given
    either as an array or as a ``Deferred`` evaluated on first access (a dataclass field
    whose default is a descriptor: ``__init__`` stores through ``__set__``)."""

    def __init__(self, column: int):
        self.column = column

    def __set_name__(self, owner, name):
        self.slot = "_" + name

    def __get__(self, obj, owner=None):
        if obj is None:
            raise AttributeError(self.slot[1:])  # a required field: no default
        value = obj.__dict__[self.slot]
        if isinstance(value, Deferred):
            value = value.value()[self.column]
            obj.__dict__[self.slot] = value
        return value

    def __set__(self, obj, value):
        obj.__dict__[self.slot] = value


@dataclass(frozen=True)
class Trajectory:
    """Rollouts of ``steps`` steps of ``dt`` from ``t = 0``.

    One rollout: ``q`` (rows, nq), ``v``, ``a`` (rows, nv), ``kinetic``, ``potential``,
    ``energy = kinetic + potential`` (rows,) at the times ``t`` (rows,); B rollouts: the same
    with a leading B. The rows are the states kept: all steps+1 by default, every k-th and
    the last with ``record_every=k``, the last alone with ``final_only=True``. ``a[i]`` is
    the acceleration at the state of row i (at the last state with the last open-loop
    torque). ``completed``: the steps each rollout completed (an int, or (B,));
    ``diverged``: whether it stopped early because its state stopped being finite or ABA
    failed (bool, or (B,)); ``message`` says why ("" when every rollout completed).

    A rollout that stopped holds its states up to the last one reached: one rollout's
    arrays (and ``t``) are cut there, B rollouts keep their common length with NaN after
    each stop (``simulate`` also warns, ``SimulationDiverged``). Where states are kept every
    k steps, the last state a stopped rollout reached fills the row after the last one it
    filled on the grid (at ``completed * dt``, which ``t`` of one rollout says).

    With constraints (``simulate(..., constraints=...)``): ``constraint_violation``
    (rows, nc, 2), or (B, rows, nc, 2), at each state kept and for each constraint, the norm
    of its position error (column 0: ``|p₁ - p₂|`` in metres for a point; for a frame
    ``|log(~M₁ M₂)|``, its rotation (rad) and translation (m) together) and of its velocity
    error ``|J v|`` (column 1; m/s, or rad/s and m/s); ``forces`` (rows, nr), or
    (B, rows, nr), the forces λ of that state, in ``constrained_dynamics``' layout (each
    constraint's rows in its frame), so that ``M a + h = τ + Jᵀ λ``. Without constraints
    they have nc = nr = 0 columns (None for dask rollouts).

    With a world (``simulate(..., world=..., collisions=...)``): ``contact_count`` (rows,)
    or (B, rows), the contacts of the step taken from each state kept (the last state's:
    those one more step would take; -1 in a row no state reached), and ``contact_forces``
    (rows, K, 3) or (B, rows, K, 3), the world-frame force of each contact slot (K = 4 per
    shape, slot ``4 s + i`` the ``i``-th patch point of shape ``s``; 0 in a slot without
    a contact, NaN in a row no state reached); ``contact_iterations`` (rows,) or (B, rows),
    the solvers' iterations in that step (both solvers' where the first stopped short; -1 in
    a row no state reached), and ``contact_residual``, the largest residual (K19) of the
    forces it kept: at most ``ContactSettings.tolerance`` where the solver converged, up to
    ``accept`` where it stopped short (0 for a step without a contact problem);
    ``limit_torques``, ``friction_torques`` and ``coupling_torques`` (rows, nv) or (B, rows,
    nv), the generalised forces of the joint limits (a rope's among them: a limit of its
    tendon's length), of the friction losses and of the couplings in that step (their
    impulses over dt, K26, K46, K30, K45: zero where none acts, NaN in a row no state
    reached): in a semi-implicit Euler step without springs or dampers, ``M (v⁺ - v) / dt
    = τ - h + Jᵀ f + limit_torques + friction_torques + coupling_torques``, f the contact
    forces. None without a world.
    ``scene`` (a ``sim.criteria.ContactScene``: the model, collisions, world and contact
    settings of the run) lets ``contacts(k)`` find the contacts of a kept
    state again, with their forces, and ``contact_criteria()`` compute the physical
    criteria of every step (docs/contact.md, K31-K34).

    With controls of actuators that have activation dynamics (``simulate(ctrl=...)``,
    ``Model.actuator_dynamics``): ``activation`` (rows, na) or (B, rows, na), the
    actuators' activations at each state kept (A2; 0 for an actuator without dynamics,
    NaN in a row no state reached), what a next run starts from (``simulate(..., act=)``).
    None otherwise.

    ``kinetic`` and ``potential`` from ``simulate`` are computed when one of them (or
    ``energy``) is first read, from the states ``q``, ``v`` then held, in one parallel
    compiled call over all states; the rollout itself computes no energy.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    kinetic: np.ndarray = _Energy(0)
    potential: np.ndarray = _Energy(1)
    completed: int | np.ndarray
    diverged: bool | np.ndarray
    dt: float
    integrator: str
    message: str = ""
    constraint_violation: np.ndarray | None = None
    forces: np.ndarray | None = None
    contact_count: np.ndarray | None = None
    contact_forces: np.ndarray | None = None
    contact_iterations: np.ndarray | None = None
    contact_residual: np.ndarray | None = None
    limit_torques: np.ndarray | None = None
    friction_torques: np.ndarray | None = None
    coupling_torques: np.ndarray | None = None
    scene: object = None
    activation: np.ndarray | None = None

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

    def contacts(self, k: int, rollout: int | None = None) -> list:
        """The contacts of kept state ``k`` (``rollout``: which one of a batch), each a
        ``ContactPoint``: link and shape names, point, normal, signed distance and the
        world-frame force of the step taken from that state
        (``sim.criteria.trajectory_contacts``). Needs a rollout with a world."""
        from .criteria import trajectory_contacts

        return trajectory_contacts(self, k, rollout)

    def contact_criteria(self, rollout: int | None = None, slip: float | None = None):
        """The physical criteria of every step (Signorini, Coulomb's cone, maximum
        dissipation, penetration; docs/contact.md, K31-K34) as a ``CriteriaHistory``
        (``sim.criteria.trajectory_criteria``). Needs a rollout with a world and every
        state kept (``record_every=1``)."""
        from ..contact.criteria import SLIP
        from .criteria import trajectory_criteria

        return trajectory_criteria(self, rollout, SLIP if slip is None else slip)
