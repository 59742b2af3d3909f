"""Kinetic energy and power (section 2.7): T = ½ B ∨ I[B] (2.35), Π = B ∨ F (2.37)."""

from __future__ import annotations

import numpy as np

from .inertia import Inertia
from .model import PGA

__all__ = ["kinetic_energy", "power", "potential_energy", "total_energy"]


def kinetic_energy(inertia: Inertia, b) -> np.ndarray:
    """T = ½ B ∨ I[B] (eq. 2.35), a scalar (per batch entry); frame-invariant."""
    return 0.5 * inertia.model.vee(b, inertia.apply(b))[..., 0]


def power(model: PGA, b, f) -> np.ndarray:
    """Π = B ∨ F (eq. 2.37): the rate of work of forque F on the motion with rate B."""
    return model.vee(b, f)[..., 0]


def potential_energy(forque, m) -> float:
    """Potential energy of a forque (or a sum of them) that has one; 0 for the others."""
    fn = getattr(forque, "potential", None)
    return 0.0 if fn is None else float(fn(m))


def total_energy(inertia: Inertia, forque, m, b) -> float:
    """T + V: conserved when every forque is conservative (gravity, springs)."""
    return float(kinetic_energy(inertia, b)) + potential_energy(forque, m)
