"""The physical criteria of a contact step (``docs/contact.md``, "The physical criteria of a
step", K31-K34), after Le Lidec et al. (T-RO 2024): how far the forces of a step and the
contact velocities after it are from the Signorini condition, from Coulomb's cone and from
the maximum-dissipation principle, and how deep the contacts were.

They read what a step gives, contact by contact, in each contact's frame ``(t₁, t₂, n)``:
the force ``f`` (the impulse over ``dt``, N), the velocity after the step ``σ = J v⁺`` with
the gap's term on the normal (K23, m/s) and the signed distance ``d`` at its start. A step
solved exactly has every criterion zero but the penetration, which only the linearisation of
a turning body and the stabilization leave.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["CRITERIA", "SLIP", "ContactCriteria", "contact_frame_forces", "step_criteria"]

SLIP = 1e-6
"""The tangential speed (m/s) above which a contact slides (K33): ``ContactSettings.accept``'s
default, far above what a converged solver leaves on a sticking contact."""

CRITERIA = ("signorini", "approach", "cone", "dissipation", "friction_direction",
            "penetration")
"""The criteria of ``ContactCriteria``, in the order they are reported."""


@dataclass(frozen=True)
class ContactCriteria:
    """The criteria of one step, one entry per contact (K31-K34):

    ``signorini`` (W): ``|f_N σ_N|``, the normal complementarity (K31); ``approach`` (m/s):
    ``max(0, -σ_N)``, the speed at which a contact still closes after the step (the other
    half of Signorini's condition, K31); ``cone`` (N): ``max(0, ‖f_T‖ - μ f_N, -f_N)``, how
    far the force lies outside Coulomb's cone (K32); ``dissipation`` (W): ``max(0, μ f_N ‖σ_T‖
    + f_T · σ_T)``, the power by which friction falls short of the most the cone allows it
    to dissipate (K33); ``friction_direction`` (N): for a sliding contact (``‖σ_T‖ > slip``)
    ``‖f_T + μ f_N σ_T / ‖σ_T‖‖``, how far friction is from that most dissipating force,
    zero for a sticking one (K33); ``penetration`` (m): ``max(0, -d)`` (K34); ``sliding``:
    which contacts slide. ``maxima()`` gives the largest of each (0 without contacts)."""

    signorini: np.ndarray = field(repr=False)
    approach: np.ndarray = field(repr=False)
    cone: np.ndarray = field(repr=False)
    dissipation: np.ndarray = field(repr=False)
    friction_direction: np.ndarray = field(repr=False)
    penetration: np.ndarray = field(repr=False)
    sliding: np.ndarray = field(repr=False)

    def __len__(self) -> int:
        return int(self.signorini.size)

    def maxima(self) -> dict[str, float]:
        """The largest value of each criterion over the contacts (``CRITERIA``' order)."""
        return {name: float(np.max(getattr(self, name), initial=0.0)) for name in CRITERIA}

    def __repr__(self) -> str:
        worst = ", ".join(f"{k} {v:.3g}" for k, v in self.maxima().items())
        return f"ContactCriteria({len(self)} contacts; maxima: {worst})"


def contact_frame_forces(forces, frames) -> np.ndarray:
    """(nc, 3): world-frame forces (nc, 3) turned into their contacts' frames ``(t₁, t₂,
    n)`` (``frames`` (nc, 3, 3), those rows each: ``step.ground_frame`` of its normal), as
    the solvers order them (K11)."""
    f = np.asarray(forces, dtype=float).reshape(-1, 3)
    return np.einsum("cij,cj->ci", np.asarray(frames, dtype=float).reshape(-1, 3, 3), f)


def step_criteria(forces, velocities, distance, friction, slip: float = SLIP
                  ) -> ContactCriteria:
    """The criteria (K31-K34) of one step's ``nc`` contacts from their ``forces`` (nc, 3)
    and post-step ``velocities`` (nc, 3), both in the contact frames ``(t₁, t₂, n)`` (N and
    m/s; ``velocities`` with the gap's term of K23 on the normal), their signed
    ``distance`` (nc,) at the start of the step and ``friction`` coefficients (nc,);
    ``slip``: the tangential speed above which a contact counts as sliding (K33)."""
    f = np.asarray(forces, dtype=float)
    s = np.asarray(velocities, dtype=float)
    d = np.asarray(distance, dtype=float).reshape(-1)
    mu = np.asarray(friction, dtype=float).reshape(-1)
    nc = d.size
    for name, x in (("forces", f), ("velocities", s)):
        if x.shape != (nc, 3):
            raise ValueError(f"step_criteria: {name} must have shape ({nc}, 3) for {nc} "
                             f"contacts (t₁, t₂, n each), got {x.shape}")
    if mu.shape != (nc,):
        raise ValueError(f"step_criteria: friction must have shape ({nc},), got {mu.shape}")
    if not (np.isfinite(slip) and slip >= 0):
        raise ValueError(f"step_criteria: slip must be a finite speed >= 0, got {slip!r}")
    fT, fN = f[:, :2], f[:, 2]
    sT, sN = s[:, :2], s[:, 2]
    signorini = np.abs(fN * sN)  # K31
    approach = np.maximum(0.0, -sN)
    cone = np.maximum(0.0, np.maximum(np.linalg.norm(fT, axis=1) - mu * fN, -fN)) + 0.0  # K32
    speed = np.linalg.norm(sT, axis=1)
    dissipation = np.maximum(0.0, mu * fN * speed + np.sum(fT * sT, axis=1))  # K33
    sliding = speed > slip
    direction = sT / np.where(sliding, speed, 1.0)[:, None]
    off = np.linalg.norm(fT + (mu * fN)[:, None] * direction, axis=1)  # K33
    penetration = np.maximum(0.0, -d)  # K34
    return ContactCriteria(signorini, approach, cone, dissipation,
                           np.where(sliding, off, 0.0), penetration, sliding)
