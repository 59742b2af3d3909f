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

__all__ = ["clamp", "interval_residuals", "interval_step", "pair_step"]


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


@inline
def _allows(state, sigma, tol):
    """Whether a row held at its lower bound (``state`` 0), its upper one (1) or inside
    them (2) allows the velocity ``σ`` (K26): ``σ >= 0``, ``σ <= 0``, any (to ``tol``)."""
    if state == 0:
        return sigma >= -tol
    if state == 1:
        return sigma <= tol
    return True


@inline
def pair_step(lo_r, hi_r, lo_s, hi_s, lam_r, lam_s, sig_r, sig_s, a, c):
    """PGS's update of two interval rows ``r`` and ``s`` whose Jacobian rows are collinear,
    ``J_s = c J_r`` (K29a: a joint's limit row and its friction loss row, both on one
    coordinate), solved together: their impulses move the one velocity ``w = σ_r`` by
    ``a (Λ' - Λ)``, ``Λ = λ_r + c λ_s``, ``a = A_rr``, and ``σ_s = σ_s + c (w' - σ_r)``.
    Each row is at its lower bound (then its ``σ >= 0``), at its upper one (``σ <= 0``) or
    inside (``σ = 0``); the laws are monotone in ``w``, so exactly one ``w'`` meets both,
    found by trying each pair of states. Returns ``(λ_r', λ_s')``; where no state fits (by
    rounding), each row's own step (K29) in turn, as for unpaired rows."""
    big = 1.0 + abs(lam_r) + abs(c * lam_s)
    tol_l, tol_v = 1e-12 * big, 1e-12 * (abs(sig_r) + abs(sig_s) + a * big)
    L = lam_r + c * lam_s
    for kr in range(3):
        for ks in range(3):
            if kr == 2 and ks == 2:
                continue  # both inside: only where σ_s = c σ_r, below
            yr = lo_r if kr == 0 else hi_r
            ys = lo_s if ks == 0 else hi_s
            if kr == 2:  # r inside: w' = 0
                w = 0.0
                yr = L - sig_r / a - c * ys
                if not (lo_r - tol_l <= yr <= hi_r + tol_l):
                    continue
                yr = clamp(lo_r, hi_r, yr)
            elif ks == 2:  # s inside: σ_s' = 0
                w = sig_r - sig_s / c
                ys = (L + (w - sig_r) / a - yr) / c
                if not (lo_s - tol_l <= ys <= hi_s + tol_l):
                    continue
                ys = clamp(lo_s, hi_s, ys)
            else:
                w = sig_r + a * (yr + c * ys - L)
            if not (math.isfinite(yr) and math.isfinite(ys)):
                continue
            if _allows(kr, w, tol_v) and _allows(ks, sig_s + c * (w - sig_r), tol_v):
                return yr, ys
    if abs(sig_s - c * sig_r) <= tol_v:  # both inside: Λ' fixed, its split kept near λ
        target = L - sig_r / a
        ys = clamp(lo_s, hi_s, lam_s)
        yr = clamp(lo_r, hi_r, target - c * ys)
        return yr, clamp(lo_s, hi_s, (target - yr) / c)
    yr = interval_step(lo_r, hi_r, lam_r, sig_r, 1.0 / a)
    return yr, interval_step(lo_s, hi_s, lam_s, sig_s + c * a * (yr - lam_r), 1.0 / (c * c * a))
