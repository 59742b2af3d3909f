"""The constraint forces of a KKT system through its Delassus matrix (C6-C8), by one
factorisation or by proximal iterations, and the errors that name a constraint.

Both dynamics reduce to ``G λ = b`` with ``G = J M⁻¹ Jᵀ`` (C7): forward dynamics with
``b = -γ - J q̈_free`` (C6), an impact with ``b = -(1 + e) J v⁻`` (C9). Without damping the
system is solved once (Cholesky of G), after a check that G is not singular. With damping
``μ > 0`` the proximal iterations of Pinocchio's ``ProximalSettings`` run (C8):
``(G + μ I) λ_{k+1} = b + μ λ_k`` from ``λ_0 = 0``, stopped when ``|G λ - b|∞`` or
``|λ_{k+1} - λ_k|∞`` is at most ``accuracy``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Constraint

SINGULAR = 1e-12
"""G is taken as singular when the smallest eigenvalue of its diagonal-scaled form, over the
rows of the constraints up to one of them, is below this (times their number)."""

CONFLICT = 1e-6
"""A proximal solve that ends with ``|G λ - b|∞ > CONFLICT · max(1, |b|∞)`` has no solution."""


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


def conflict(G: np.ndarray, lam: np.ndarray, b: np.ndarray,
             constraints: tuple[Constraint, ...], iterations: int) -> str:
    """The message of a set with no solution: the constraint with the largest residual."""
    r = np.abs(G @ lam - b)
    starts = row_starts(constraints)
    k = int(np.searchsorted(starts, int(np.argmax(r)), side="right") - 1)
    return (f"the constraints have no solution: after {iterations} proximal iterations "
            f"constraint {k} ({constraints[k].name}) is still violated by {r.max():.3g} "
            f"(|J q̈ + γ| or |J v⁺ + e J v⁻|): its rows conflict with those of the others")


def solve(G: np.ndarray, b: np.ndarray, constraints: tuple[Constraint, ...],
          damping: float, iterations: int, accuracy: float) -> tuple[np.ndarray, SolveInfo]:
    """``λ`` of ``G λ = b`` (C7), directly or by proximal iterations (C8), and how."""
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(b))):
        raise ValueError("the Delassus matrix or the constraint right-hand side is not finite "
                         "(a state too large, or a singular mass matrix)")
    if len(b) == 0:
        return b.copy(), SolveInfo(0, 0.0, 0.0, True)
    if damping == 0.0:
        why = singular_constraint(G, constraints)
        if why is not None:
            raise ValueError(why)
        L = np.linalg.cholesky(G)
        lam = np.linalg.solve(L.T, np.linalg.solve(L, b))
        r = float(np.abs(G @ lam - b).max())
        return lam, SolveInfo(1, r, float(np.abs(lam).max()), True)
    L = np.linalg.cholesky(G + damping * np.eye(len(b)))
    lam = np.zeros_like(b)
    r = change = np.inf
    it = 0
    while it < iterations:
        it += 1
        new = np.linalg.solve(L.T, np.linalg.solve(L, b + damping * lam))  # C8
        r = float(np.abs(G @ new - b).max())
        change = float(np.abs(new - lam).max())
        lam = new
        if r <= accuracy or change <= accuracy:
            break
    converged = r <= accuracy or change <= accuracy
    if not converged and r > CONFLICT * max(1.0, float(np.abs(b).max())):
        raise ValueError(conflict(G, lam, b, constraints, it))
    return lam, SolveInfo(it, r, change, converged)
