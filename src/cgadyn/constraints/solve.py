"""What the solve of the constraint forces reports, and the errors that name a constraint.

Both dynamics reduce to ``G λ = b`` with ``G = J M⁻¹ Jᵀ`` (C7): forward dynamics with
``b = -γ - J q̈_free`` (C6), an impact with ``b = -(1 + e) J v⁻`` (C9). The solve itself,
once by Cholesky or by the proximal iterations of Pinocchio's ``ProximalSettings`` (C8), is
compiled (``constraints/core.py``, ``solve_forces``); here are its ``SolveInfo`` and the
words of its faults: a singular G (which constraint makes it so) and a set with no
solution.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Constraint

SINGULAR = 1e-12
"""G is taken as singular when the smallest eigenvalue of its diagonal-scaled form, over the
rows of the constraints up to one of them, is below this (times their number)."""


@dataclass(frozen=True)
class SolveInfo:
    """How the forces were found: ``iterations`` (1 for a direct solve), ``residual``
    ``|G λ - b|∞`` (for forward dynamics ``|J q̈ + γ|∞``, Pinocchio's ``absolute_residual``),
    ``change`` ``|λ_k - λ_{k-1}|∞`` of the last iteration (its ``relative_residual``) and
    ``converged``."""

    iterations: int
    residual: float
    change: float
    converged: bool


def row_starts(constraints: tuple[Constraint, ...]) -> np.ndarray:
    """The first row of each constraint, and the total as the last entry."""
    return np.cumsum([0] + [c.size for c in constraints])


def singular_constraint(G: np.ndarray, constraints: tuple[Constraint, ...]) -> str | None:
    """Why G is singular, naming the first constraint whose rows are zero or depend on those
    of itself and the constraints before it; None where G is regular."""
    starts = row_starts(constraints)
    d = np.sqrt(np.maximum(np.diag(G), 0.0))
    scale = max(float(d.max(initial=0.0)), 1e-300)
    for k, c in enumerate(constraints):
        if np.any(d[starts[k]:starts[k + 1]] <= 1e-12 * scale):
            return (f"constraint {k} ({c.name}) moves with no joint: a row of its Jacobian is "
                    f"zero, so no force can act along it")
    Gs = G / np.outer(d, d)
    for k, c in enumerate(constraints):
        e = starts[k + 1]
        if np.linalg.eigvalsh(Gs[:e, :e])[0] < SINGULAR * e:
            before = "" if k == 0 else " and on those of the constraints before it"
            return (f"constraint {k} ({c.name}) has rows that depend on each other{before}: "
                    f"the Delassus matrix G = J M⁻¹ Jᵀ is singular, the set is redundant or "
                    f"conflicting; pass damping > 0 (e.g. 1e-8) to solve it by proximal "
                    f"iterations, which give the least-norm forces of a redundant set")
    return None


def conflict(constraints: tuple[Constraint, ...], starts: np.ndarray, row: int,
             residual: float, iterations: int) -> str:
    """The message of a set with no solution: the constraint with the largest residual
    (its ``row``)."""
    k = int(np.searchsorted(starts, row, side="right") - 1)
    return (f"the constraints have no solution: after {iterations} proximal iterations "
            f"constraint {k} ({constraints[k].name}) is still violated by {residual:.3g} "
            f"(|J q̈ + γ| or |J v⁺ + e J v⁻|): its rows conflict with those of the others")


def solve_info(constraints: tuple[Constraint, ...], starts: np.ndarray,
               info: np.ndarray) -> SolveInfo:
    """The ``SolveInfo`` of the compiled solve's ``info`` (``constraints/core.py``); a set
    with no solution is an error."""
    iterations, residual, change, converged, row = info.tolist()
    if row >= 0:
        raise ValueError(conflict(constraints, starts, int(row), residual, int(iterations)))
    return SolveInfo(int(iterations), residual, change, bool(converged))
