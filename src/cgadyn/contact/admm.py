"""The ADMM contact solver with a proximal term and the spectral penalty update of
Carpentier, Le Lidec and Montaut (RSS 2024) (``docs/contact.md``, K16-K17, K19), on the
blocks of ``ncp.py``: Coulomb cones, then one-row intervals (joint limits, friction loss).

One call solves one problem in place, with its scratch given (``SCRATCH_ROWS`` rows of
``max(m, 6)`` floats and an ``m x m`` matrix for the factor), allocates nothing and returns a
status, so that a rollout can call it every step.
"""

from __future__ import annotations

import math

from .._jit import core, inline
from ..algorithms._dense import cholesky, cholesky_substitute
from ..algorithms.status import DELASSUS_SINGULAR, NONFINITE_INPUT, NONFINITE_RESULT, OK, fault
from .cone import desaxce
from .ncp import (
    COMPLEMENTARITY,
    CONVERGED,
    DUAL,
    ITERATIONS,
    MAX_ITER,
    POWER_INIT,
    POWER_STEP,
    PRIMAL,
    PROX,
    RATIO,
    RHO,
    WARM,
    input_scale,
    passes,
    project_blocks,
    residuals,
    velocity,
)

X, Z, Y, SIGMA, RHS, ZOLD, XOLD, TMP = range(8)
SCRATCH_ROWS = 8
"""Rows of the scratch: ``x`` (the linear step), ``z`` (its projection, the forces), ``y``
(the multiplier), ``σ``, a right-hand side, the previous ``z`` and ``x``, six floats."""
POWER_ITERATIONS = 50


@inline
def largest_eigenvalue(G, R, u, w):
    """The largest eigenvalue ``L`` of ``G + R`` by power iteration (K17), to 1e-6, from the
    uniform vector, or, where that lies in the null space of ``G + R`` (two rows of
    opposite sign on one direction: a joint's upper stop, ``-e_k``, and its friction loss,
    ``e_k``), from the unit vector of the largest diagonal entry; ``u``, ``w`` hold ``m``
    floats."""
    m = G.shape[0]
    top = 0
    for r in range(m):
        u[r] = 1.0 / math.sqrt(m)
        if G[r, r] + R[r] > G[top, top] + R[top]:
            top = r
    L = 0.0
    restarted = False
    for _ in range(POWER_ITERATIONS):
        norm = 0.0
        for r in range(m):
            acc = R[r] * u[r]
            for c in range(m):
                acc += G[r, c] * u[c]
            w[r] = acc
            norm += acc * acc
        norm = math.sqrt(norm)
        if not norm > 0.0:
            if restarted or L > 0.0:
                return 0.0
            restarted = True
            for r in range(m):
                u[r] = 1.0 if r == top else 0.0
            continue
        for r in range(m):
            u[r] = w[r] / norm
        done = abs(norm - L) <= 1e-6 * norm
        L = norm
        if done:
            break
    return L


@inline
def _factor_shifted(G, R, shift, C):
    """``C`` the Cholesky factor of ``G + R + shift I`` (K16); False where it fails (G not
    positive semi-definite)."""
    m = G.shape[0]
    for r in range(m):
        for c in range(m):
            C[r, c] = G[r, c]
        C[r, r] += R[r] + shift
    return cholesky(C, m, 0.0) < 0


@core
def admm_solve(G, g, mu, bounds, R, settings, lam, info, C, w):
    """Solve the NCP (K13, K26) of ``σ = (G + R) λ + g`` by ADMM (K16) from ``λ`` (a warm
    start where ``settings[WARM]``, else zero), the cones of ``mu`` then the intervals of
    ``bounds`` (``ncp.py``): the forces into ``lam``, the report into ``info``; a status.
    An interval row is K16 with its projection (K27) and no correction (``s = 0``)."""
    m = g.shape[0]
    nc = mu.shape[0]
    x, z, y, sigma, rhs, zold, xold, tmp = w[X], w[Z], w[Y], w[SIGMA], w[RHS], w[ZOLD], \
        w[XOLD], w[TMP]
    gmax = input_scale(G, g, R)
    if gmax < 0.0:
        return fault(NONFINITE_INPUT, -1)
    warm = settings[WARM] != 0.0
    for r in range(m):  # z₀ = P_K(λ₀), x₀ = z₀
        z[r] = lam[r] if warm else 0.0
    project_blocks(mu, bounds, z, z)
    for r in range(m):
        x[r] = z[r]
    _, gl, lmax = velocity(G, R, g, z, sigma)
    for r in range(m):  # y₀ = -σ̃(z₀): a solution given is a fixed point
        y[r] = -sigma[r]
    for i in range(nc):
        y[3 * i + 2] -= desaxce(mu[i], sigma, 3 * i)
    eta = settings[PROX]
    big = largest_eigenvalue(G, R, rhs, xold) + eta
    power = settings[POWER_INIT]
    rho = math.sqrt(eta * big) * (big / eta) ** power  # K17
    if not _factor_shifted(G, R, rho + eta, C):
        return fault(DELASSUS_SINGULAR, -1)
    primal, dual, comp = residuals(mu, bounds, z, sigma, tmp)
    ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
    it = 0
    limit = int(settings[MAX_ITER])
    while not ok and it < limit:
        it += 1
        for r in range(m):  # (G + R + (ρ + η) I) x = -(g + s) - y + ρ z + η x (K16)
            xold[r] = x[r]
            zold[r] = z[r]
            rhs[r] = -g[r] - y[r] + rho * z[r] + eta * x[r]
        for i in range(nc):
            rhs[3 * i + 2] -= desaxce(mu[i], y, 3 * i)  # s = Γ(-y_k) (K13)
        for r in range(m):
            x[r] = rhs[r]
        cholesky_substitute(C, m, x)
        for r in range(m):
            rhs[r] = x[r] + y[r] / rho
        project_blocks(mu, bounds, rhs, z)  # z = P_K(x + y / ρ) (K16, K27)
        rp = rd = 0.0
        for r in range(m):  # y += ρ (x - z) (K16)
            y[r] += rho * (x[r] - z[r])
            rp = max(rp, abs(x[r] - z[r]))
            rd = max(rd, abs(rho * (z[r] - zold[r]) + eta * (x[r] - xold[r])))
        _, gl, lmax = velocity(G, R, g, z, sigma)
        _, dual, comp = residuals(mu, bounds, z, sigma, tmp)
        primal = rp
        if not (math.isfinite(dual) and math.isfinite(primal)):
            return fault(NONFINITE_RESULT, -1)
        ok = passes(settings, primal, dual, comp, gmax, gl, lmax)
        if ok:
            break
        step = 0.0  # the spectral update of ρ (K17)
        if rp > settings[RATIO] * rd:
            step = settings[POWER_STEP]
        elif rd > settings[RATIO] * rp:
            step = -settings[POWER_STEP]
        if step != 0.0 and -1.0 <= power + step <= 1.0:
            power += step
            rho = math.sqrt(eta * big) * (big / eta) ** power
            if not _factor_shifted(G, R, rho + eta, C):
                return fault(DELASSUS_SINGULAR, -1)
    for r in range(m):
        lam[r] = z[r]
    info[ITERATIONS], info[PRIMAL], info[DUAL], info[COMPLEMENTARITY] = it, primal, dual, comp
    info[CONVERGED] = 1.0 if ok else 0.0
    info[RHO] = rho
    return OK
