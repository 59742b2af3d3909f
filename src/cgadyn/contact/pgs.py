"""Projected Gauss-Seidel on the blocks of ``ncp.py``, the Coulomb cones contact by contact,
then the one-row intervals (two collinear ones together), its iterate polished on its active
set (``docs/contact.md``, K18, K18a, K19, K29, K29a), with ``admm_solve``'s interface and
scratch."""

from __future__ import annotations

import math

from .._jit import core, inline
from ..algorithms.status import NONFINITE_INPUT, NONFINITE_RESULT, OK, fault
from .admm import RHS, SIGMA, TMP, XOLD, ZOLD, X, Y, Z
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
    input_scale,
    passes,
    project_blocks,
    residuals,
    velocity,
)
from .polish import active_set, newton_step, unsettled
from .sets import interval_step, pair_step

GATE = 1e3
"""A sweep is followed by the stopping rule (K19) only where no row's velocity changed by more
than ``GATE`` times the rule's dual tolerance (``_move``): far from the solution the rule's
residuals are not worth computing."""
POLISH = 1e-3
"""The sweeps' iterate is polished (``_polish``, K18a) once no row's velocity changed by more
than ``POLISH`` (m/s, rad/s) in a sweep; where the polish does not pass the stopping rule,
again each time the change has fallen ``POLISH_STEP`` times further, at most ``POLISHES``
times in a solve."""
POLISH_STEP = 1e-2
POLISHES = 3
STALL = 100
"""Sweeps that still change a velocity by more than ``POLISH`` after ``STALL``, ``2 STALL``,
``4 STALL``, ... sweeps are polished there too: on a stiff problem (a joint at its stop
behind a contact near its cone's edge) they crawl for thousands of sweeps towards a guess
that one Newton step settles."""
NEWTON = 6
"""The most Newton steps of one polish with a sliding contact (K18a)."""
COLLINEAR = 1e-9
"""Two interval rows ``r``, ``s`` are one direction (K29a) where ``A_rs² >= (1 -
COLLINEAR) A_rr A_ss``: a joint's limit row and its friction loss row, ``±e_k`` and ``e_k``,
whose ``A`` rows agree but for rounding."""
SETTLED = 1e-12
"""A polish with a sliding contact ends where its equations' largest residual (``unsettled``,
a velocity) is at most ``SETTLED`` times the stopping rule's dual scale, ``max(‖g‖∞, ‖(G +
R) λ‖∞)``."""


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
def _contact_step(G, R, sigma, lam, mu, o, inv):
    """Contact ``o // 3``'s forces by K18: the normal one ``λ_N ← max(0, λ_N - σ_N /
    A_NN)``, then the tangential one ``λ_T ← λ_T - σ'_T / L_T`` at the velocity ``σ'_T``
    after the normal step, cut to the disc ``‖λ_T‖ <= μ λ_N`` (``L_T`` the largest
    eigenvalue of the contact's tangential 2 x 2 block; ``inv[o]`` holds ``1 / L_T`` and
    ``inv[o + 2]`` ``1 / A_NN``, 0 where not positive: ``_inverses``); then ``σ`` kept by
    the three changes at once, one pass over the block's columns of ``G`` (``_move``'s,
    fused). Returns the largest ``|Δλ_r| A_rr`` of the three rows."""
    n = lam[o + 2]
    if inv[o + 2] > 0.0:  # the normal force
        n = max(0.0, n - sigma[o + 2] * inv[o + 2])
    dn = n - lam[o + 2]
    x0, x1 = lam[o], lam[o + 1]
    if inv[o] > 0.0:  # the tangential force, cut to the disc
        t0 = x0 - (sigma[o] + G[o, o + 2] * dn) * inv[o]
        t1 = x1 - (sigma[o + 1] + G[o + 1, o + 2] * dn) * inv[o]
        cap = mu * n
        tt = t0 * t0 + t1 * t1
        x0, x1 = t0, t1
        if tt > cap * cap:  # outside the disc: its root only then (a sticking contact has none)
            scale = cap / math.sqrt(tt)
            x0, x1 = scale * t0, scale * t1
    d0, d1 = x0 - lam[o], x1 - lam[o + 1]
    if dn != 0.0 or d0 != 0.0 or d1 != 0.0:
        lam[o], lam[o + 1], lam[o + 2] = x0, x1, n
        for c in range(lam.shape[0]):
            sigma[c] += G[o, c] * d0 + G[o + 1, c] * d1 + G[o + 2, c] * dn
        sigma[o] += R[o] * d0
        sigma[o + 1] += R[o + 1] * d1
        sigma[o + 2] += R[o + 2] * dn
    return max(abs(d0) * (G[o, o] + R[o]), abs(d1) * (G[o + 1, o + 1] + R[o + 1]),
               abs(dn) * (G[o + 2, o + 2] + R[o + 2]))


@inline
def _inverses(G, R, nc, inv):
    """``inv``: for each contact ``1 / L_T`` (``L_T`` the largest eigenvalue of its
    tangential 2 x 2 block of ``A = G + R``) at its first row and ``1 / A_NN`` at its normal
    row; ``1 / A_rr`` at each interval row; 0 where the pivot is not positive (the row is
    then left as it is, K18, K29). Once per solve: a sweep then multiplies."""
    for r in range(inv.shape[0]):
        a = G[r, r] + R[r]
        inv[r] = 1.0 / a if a > 0.0 else 0.0
    for i in range(nc):
        o = 3 * i
        a, b, d = G[o, o] + R[o], G[o, o + 1], G[o + 1, o + 1] + R[o + 1]
        big = 0.5 * (a + d) + math.sqrt(0.25 * (a - d) ** 2 + b * b)
        inv[o] = 1.0 / big if big > 0.0 else 0.0
        inv[o + 1] = 0.0


@inline
def _partners(G, R, nc, nb, pair):
    """``pair[b]``: the interval row after ``b`` whose Jacobian row is collinear with ``b``'s
    (``COLLINEAR``), -1 for none, -2 for a row that its partner's step moves (K29a). Once per
    solve."""
    for b in range(nb):
        pair[b] = -1.0
    for b in range(nb):
        r = 3 * nc + b
        if pair[b] != -1.0 or R[r] != 0.0 or not G[r, r] > 0.0:
            continue
        for e in range(b + 1, nb):
            s = 3 * nc + e
            if pair[e] == -1.0 and R[s] == 0.0 and G[s, s] > 0.0 and \
                    G[r, s] * G[r, s] >= (1.0 - COLLINEAR) * G[r, r] * G[s, s]:
                pair[b], pair[e] = float(e), -2.0
                break


@inline
def _interval_sweep(G, R, sigma, lam, bounds, nc, inv, pair):
    """One sweep over the interval rows (K29), a collinear pair's two rows in one step
    (K29a, ``sets.pair_step``). Returns the largest ``|Δλ_r| A_rr``."""
    change = 0.0
    for b in range(bounds.shape[0]):
        e = int(pair[b])
        if e == -2:
            continue
        r = 3 * nc + b
        if e < 0:
            change = max(change, _move(G, R, sigma, lam, r, interval_step(
                bounds[b, 0], bounds[b, 1], lam[r], sigma[r], inv[r])))
            continue
        s = 3 * nc + e
        yr, ys = pair_step(bounds[b, 0], bounds[b, 1], bounds[e, 0], bounds[e, 1], lam[r],
                           lam[s], sigma[r], sigma[s], G[r, r], G[r, s] / G[r, r])
        change = max(change, _move(G, R, sigma, lam, r, yr), _move(G, R, sigma, lam, s, ys))
    return change


@inline
def _scales(g, sigma, lam):
    """``(‖(G + R) λ‖∞, ‖λ‖∞)`` from ``σ - g``: the stopping rule's scales (K19)."""
    gl = lmax = 0.0
    for r in range(g.shape[0]):
        gl = max(gl, abs(sigma[r] - g[r]))
        lmax = max(lmax, abs(lam[r]))
    return gl, lmax


@inline
def _newton(G, g, mu, bounds, R, settings, lam, sigma, tmp, C, x, rows, slides, k, sliding,
            gmax):
    """Newton's steps on the guess ``rows``/``slides`` (K18a): one where no contact slides,
    else until the equations' residual is below ``SETTLED`` times the dual scale (at most
    ``NEWTON``), then the stopping rule (K19) on ``σ`` formed anew. Returns ``(passed,
    primal, dual, complementarity)``; ``λ`` and ``σ`` are left where the steps ended."""
    gl = lmax = 0.0  # σ is the sweeps' kept one until the first step
    for n in range(NEWTON + 1 if sliding else 2):
        if n > 0 and (not sliding or unsettled(mu, lam, sigma, rows, slides, k)
                      <= SETTLED * max(gmax, gl)):
            primal, dual, comp = residuals(mu, bounds, lam, sigma, tmp)
            return passes(settings, primal, dual, comp, gmax, gl, lmax), primal, dual, comp
        if n == NEWTON or not newton_step(G, R, mu, lam, sigma, rows, slides, k, C, x) >= 0.0:
            break
        _, gl, lmax = velocity(G, R, g, lam, sigma)
    return False, 0.0, 0.0, 0.0


@inline
def _polish(G, g, mu, bounds, R, settings, lam, sigma, tmp, w, C, gmax):
    """The iterate polished on its active set (K18a, ``polish.py``): Newton's steps on the
    guess read off it (``_newton``); where that guess has a sliding contact and does not
    pass, once more with every contact in contact sticking (the sweeps' iterate may slide
    on the cone's edge, on its way to forces just inside it). Returns ``(passed, primal,
    dual, complementarity)``; where neither passed, ``λ`` and ``σ`` are the iterate's
    again."""
    m = g.shape[0]
    save, rows, slides, x = w[ZOLD], w[Y], w[XOLD], w[Z]
    k, sliding = active_set(mu, bounds, lam, rows, slides)
    for r in range(m):
        save[r] = lam[r]
    for attempt in range(2 if sliding else 1):
        if attempt == 1:  # the same rows, every contact sticking
            for r in range(m):
                lam[r] = save[r]
            velocity(G, R, g, lam, sigma)
            for a in range(k):
                slides[a] = 0.0
            sliding = 0
        ok, primal, dual, comp = _newton(G, g, mu, bounds, R, settings, lam, sigma, tmp, C, x,
                                         rows, slides, k, sliding, gmax)
        if ok:
            return True, primal, dual, comp
    for r in range(m):
        lam[r] = save[r]
    velocity(G, R, g, lam, sigma)
    return False, 0.0, 0.0, 0.0


@core
def pgs_solve(G, g, mu, bounds, R, settings, lam, info, C, w):
    """Solve the NCP (K13, K26) by sweeps over the blocks (K18): for contact ``i`` the normal
    force ``λ_N ← max(0, λ_N - σ_N / A_NN)``, then the tangential one ``λ_T ← λ_T - σ_T /
    L_T`` cut to the disc ``‖λ_T‖ <= μ λ_N`` (``A = G + R``, ``L_T`` the largest eigenvalue of
    the contact's tangential 2 x 2 block); then each interval row of ``bounds`` (K29), two
    collinear ones in one step (K29a).
    ``σ`` is formed once and then kept by each block's change (``_contact_step``,
    ``_move``), one pass over its columns of ``G``, and formed anew where the stopping rule
    passes; the rule follows a sweep only where it changed no row's velocity by more than
    ``GATE`` times its tolerance. Once the sweeps change little (``POLISH``), or at sweeps
    ``STALL``, ``2 STALL``, ... where they do not, the iterate is polished on its active set
    (K18a, ``_polish``; ``C`` its scratch), which ends the solve where the rule passes on
    the result. A status."""
    m = g.shape[0]
    nc = mu.shape[0]
    nb = bounds.shape[0]
    sigma, tmp, inv, pair = w[SIGMA], w[TMP], w[X][:m], w[RHS]
    gmax = input_scale(G, g, R)
    if gmax < 0.0:
        return fault(NONFINITE_INPUT, -1)
    if settings[WARM] == 0.0:
        for r in range(m):
            lam[r] = 0.0
    project_blocks(mu, bounds, lam, lam)
    _inverses(G, R, nc, inv)
    _partners(G, R, nc, nb, pair)
    _, gl, lmax = velocity(G, R, g, lam, sigma)
    primal, dual, comp = residuals(mu, bounds, lam, sigma, tmp)
    ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
    it = 0
    limit = int(settings[MAX_ITER])
    polish, polishes, stall = POLISH, 0, STALL
    while not ok and it < limit:
        it += 1
        change = 0.0
        for i in range(nc):
            change = max(change, _contact_step(G, R, sigma, lam, mu[i], 3 * i, inv))
        change = max(change, _interval_sweep(G, R, sigma, lam, bounds, nc, inv, pair))
        if (change <= polish and polishes < POLISHES) or it == stall:
            if it == stall:
                stall *= 2
            else:
                polishes += 1
                polish *= POLISH_STEP
            ok, primal, dual, comp = _polish(G, g, mu, bounds, R, settings, lam, sigma, tmp, w,
                                             C, gmax)
            if ok:
                break
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
