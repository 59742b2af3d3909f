"""The one-row blocks of the contact problem, written once for every solver: an interval
``[lo, hi]`` that one impulse must lie in, its projection (K27), the residuals of its
complementarity (K28) and PGS's step on it (K29) (``docs/contact.md``, "Joint limits").

A joint limit's row has the set ``ℝ₊ = [0, ∞)`` (K26); a joint's friction loss, the box
``[-f, f]``; a bilateral constraint's in a rollout with contact, the line ``ℝ`` (C14). All
are intervals, so one projection and one residual serve them all: the condition on a row
is ``-σ ∈ N_[lo, hi](λ)``, the interval's normal cone, which for ``ℝ₊`` is the
complementarity ``0 <= λ ⊥ σ >= 0`` of a contact's normal.
"""

from __future__ import annotations

import math

from .._jit import inline

__all__ = ["clamp", "interval_residuals", "interval_step"]


@inline
def clamp(lo, hi, x):
    """``P_[lo, hi](x) = min(max(x, lo), hi)``, the projection on the interval (K27)."""
    return min(max(x, lo), hi)


@inline
def interval_residuals(lo, hi, lam, sigma):
    """The residuals of ``-σ ∈ N_[lo, hi](λ)`` at one row (K28), as ``(primal, dual,
    complementarity)``: ``|λ - P(λ)|``; how far ``σ`` is from the velocities the interval
    allows at ``P(λ)`` (any at a point interval, ``σ >= 0`` at ``lo``, ``σ <= 0`` at ``hi``,
    ``σ = 0`` inside); ``|σ (λ - b)|`` with ``b`` the bound ``σ`` pushes ``λ`` to (``hi``
    where ``σ < 0`` and ``hi`` is finite, else ``lo``), 0 where that bound is infinite (an
    unbounded row, a bilateral constraint's (C14): ``σ = 0`` is then the dual residual's
    ``|σ|`` alone): on ``ℝ₊`` these are K19's ``|λ_N - P(λ_N)|``, ``max(0, -σ_N)`` and
    ``|λ_N σ_N|``."""
    p = clamp(lo, hi, lam)
    if lo == hi:
        dual = 0.0
    elif p <= lo:
        dual = max(0.0, -sigma)
    elif p >= hi:
        dual = max(0.0, sigma)
    else:
        dual = abs(sigma)
    bound = hi if sigma < 0.0 and hi < math.inf else lo
    return abs(lam - p), dual, abs(sigma * (lam - bound)) if bound > -math.inf else 0.0


@inline
def interval_step(lo, hi, lam, sigma, inv):
    """PGS's update of one row (K29): ``P_[lo, hi](λ - σ / A_rr)`` with ``inv = 1 / A_rr``,
    λ unchanged where the row's diagonal ``A_rr`` is not positive (``inv = 0``)."""
    if inv > 0.0:
        return clamp(lo, hi, lam - sigma * inv)
    return lam
