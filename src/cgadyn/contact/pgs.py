"""Projected Gauss-Seidel on the blocks of ``ncp.py``, the Coulomb cones contact by contact,
then the one-row intervals (``docs/contact.md``, K18, K19, K29): the second solver, for
comparison, with ``admm_solve``'s interface and scratch."""

from __future__ import annotations

import math

from .._jit import inline, serial
from ..algorithms.status import NONFINITE_INPUT, NONFINITE_RESULT, OK, fault
from .admm import SIGMA, TMP
from .ncp import (
    ABS_TOL,
    COMPLEMENTARITY,
    CONVERGED,
    DUAL,
    ITERATIONS,
    MAX_ITER,
    PRIMAL,
    REL_TOL,
    RHO,
    WARM,
    passes,
    project_blocks,
    residuals,
    velocity,
)
from .sets import interval_step

GATE = 1e3
"""A sweep is followed by the stopping rule (K19) only where no row's velocity changed by more
than ``GATE`` times the rule's dual tolerance (``_move``): far from the solution the rule's
residuals are not worth computing."""


@inline
def _move(G, R, sigma, lam, r, value):
    """``λ_r ← value``, and ``σ = (G + R) λ + g`` (K11) kept by its change: column ``r`` of
    ``G`` (its row: ``G`` is symmetric) times the step, plus ``R_r`` times it on row ``r``.
    ``sigma`` may be longer than the problem (scratch): its first ``len(lam)`` rows.
    Returns ``|Δλ_r| A_rr``, the change of the row's own velocity."""
    step = value - lam[r]
    if step != 0.0:
        lam[r] = value
        for c in range(lam.shape[0]):
            sigma[c] += G[r, c] * step
        sigma[r] += R[r] * step
    return abs(step) * (G[r, r] + R[r])


@inline
def _contact_step(G, R, sigma, lam, mu, o):
    """Contact ``o // 3``'s forces by K18: the normal one ``λ_N ← max(0, λ_N - σ_N /
    A_NN)``, then the tangential one ``λ_T ← λ_T - σ'_T / L_T`` at the velocity ``σ'_T``
    after the normal step, cut to the disc ``‖λ_T‖ <= μ λ_N`` (``L_T`` the largest
    eigenvalue of the contact's tangential 2 x 2 block); then ``σ`` kept by the three
    changes at once, one pass over the block's columns of ``G`` (``_move``'s, fused).
    Returns the largest ``|Δλ_r| A_rr`` of the three rows."""
    ann = G[o + 2, o + 2] + R[o + 2]
    n = lam[o + 2]
    if ann > 0.0:  # the normal force
        n = max(0.0, n - sigma[o + 2] / ann)
    dn = n - lam[o + 2]
    s0, s1 = sigma[o] + G[o, o + 2] * dn, sigma[o + 1] + G[o + 1, o + 2] * dn
    a, b, d = G[o, o] + R[o], G[o, o + 1], G[o + 1, o + 1] + R[o + 1]
    big = 0.5 * (a + d) + math.sqrt(0.25 * (a - d) ** 2 + b * b)
    x0, x1 = lam[o], lam[o + 1]
    if big > 0.0:  # the tangential force, cut to the disc
        t0, t1 = x0 - s0 / big, x1 - s1 / big
        t = math.sqrt(t0 * t0 + t1 * t1)
        cap = mu * n
        scale = cap / t if t > cap else 1.0
        x0, x1 = scale * t0, scale * t1
    d0, d1 = x0 - lam[o], x1 - lam[o + 1]
    if dn != 0.0 or d0 != 0.0 or d1 != 0.0:
        lam[o], lam[o + 1], lam[o + 2] = x0, x1, n
        for c in range(lam.shape[0]):
            sigma[c] += G[o, c] * d0 + G[o + 1, c] * d1 + G[o + 2, c] * dn
        sigma[o] += R[o] * d0
        sigma[o + 1] += R[o + 1] * d1
        sigma[o + 2] += R[o + 2] * dn
    return max(abs(d0) * a, abs(d1) * d, abs(dn) * ann)


@inline
def _scales(g, sigma, lam):
    """``(‖(G + R) λ‖∞, ‖λ‖∞)`` from ``σ - g``: the stopping rule's scales (K19)."""
    gl = lmax = 0.0
    for r in range(g.shape[0]):
        gl = max(gl, abs(sigma[r] - g[r]))
        lmax = max(lmax, abs(lam[r]))
    return gl, lmax


@serial
def pgs_solve(G, g, mu, bounds, R, settings, lam, info, C, w):
    """Solve the NCP (K13, K26) by sweeps over the blocks (K18): for contact ``i`` the normal
    force ``λ_N ← max(0, λ_N - σ_N / A_NN)``, then the tangential one ``λ_T ← λ_T - σ_T /
    L_T`` cut to the disc ``‖λ_T‖ <= μ λ_N`` (``A = G + R``, ``L_T`` the largest eigenvalue of
    the contact's tangential 2 x 2 block); then each interval row of ``bounds`` (K29);
    ``C`` is unused. ``σ`` is formed once and then kept by each block's change
    (``_contact_step``, ``_move``), one pass over its columns of ``G``, and formed anew
    where the stopping rule passes; the rule follows a sweep only where it changed no row's
    velocity by more than ``GATE`` times its tolerance. A status."""
    m = g.shape[0]
    nc = mu.shape[0]
    nb = bounds.shape[0]
    sigma, tmp = w[SIGMA], w[TMP]
    gmax = 0.0
    for r in range(m):
        gmax = max(gmax, abs(g[r]))
        if not (math.isfinite(g[r]) and math.isfinite(R[r])):
            return fault(NONFINITE_INPUT, -1)
        for c in range(m):
            if not math.isfinite(G[r, c]):
                return fault(NONFINITE_INPUT, -1)
    if settings[WARM] == 0.0:
        for r in range(m):
            lam[r] = 0.0
    project_blocks(mu, bounds, lam, lam)
    _, gl, lmax = velocity(G, R, g, lam, sigma)
    primal, dual, comp = residuals(mu, bounds, lam, sigma, tmp)
    ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
    it = 0
    limit = int(settings[MAX_ITER])
    while not ok and it < limit:
        it += 1
        change = 0.0
        for i in range(nc):
            change = max(change, _contact_step(G, R, sigma, lam, mu[i], 3 * i))
        for b in range(nb):  # each interval row (K29)
            r = 3 * nc + b
            change = max(change, _move(G, R, sigma, lam, r, interval_step(
                bounds[b, 0], bounds[b, 1], lam[r], sigma[r], G[r, r] + R[r])))
        if change > GATE * max(settings[ABS_TOL], settings[REL_TOL] * max(gmax, gl)) \
                and it < limit:
            continue  # far from the solution (GATE; NaN falls through to the rule)
        gl, lmax = _scales(g, sigma, lam)
        primal, dual, comp = residuals(mu, bounds, lam, sigma, tmp)
        if not math.isfinite(dual):
            return fault(NONFINITE_RESULT, -1)
        ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
        if ok:  # the kept σ drifts by rounding: the rule again on σ formed anew
            _, gl, lmax = velocity(G, R, g, lam, sigma)
            primal, dual, comp = residuals(mu, bounds, lam, sigma, tmp)
            ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
    info[ITERATIONS], info[PRIMAL], info[DUAL], info[COMPLEMENTARITY] = it, primal, dual, comp
    info[CONVERGED] = 1.0 if ok else 0.0
    info[RHO] = 0.0
    return OK
