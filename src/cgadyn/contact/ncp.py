"""What both contact solvers share (``docs/contact.md``, K11, K19, K26-K28): the layout of
their settings and report, the velocity ``σ = (G + R) λ + g`` (K11), the projection on and
the residuals of every block, and the stopping rule (K19).

A problem has blocks of two kinds: ``nc`` contacts first, 3 rows each (``(t₁, t₂, n)``, the
Coulomb cone of ``mu[i]``, ``cone.py``), then ``nb`` one-row blocks, each an interval
``bounds[b] = [lo, hi]`` (``[0, ∞)`` for a joint limit, ``[-f, f]`` for a friction loss,
``sets.py``): ``m = 3 nc + nb`` rows. ``R`` is the diagonal of the compliance (zero for rigid
contacts).
"""

from __future__ import annotations

import math

from .._jit import inline
from .cone import ncp_residuals, project
from .sets import clamp, interval_residuals

ABS_TOL, REL_TOL, MAX_ITER, WARM, PROX, POWER_INIT, POWER_STEP, RATIO = range(8)
"""Offsets in ``settings``: the absolute and relative tolerances, the iteration limit,
whether ``λ`` holds a warm start (1) or not (0), then ADMM's proximal weight ``η``, the
spectral rule's initial power ``p₀``, its step and the primal/dual ratio that triggers it
(K17)."""
SETTINGS = 8

ITERATIONS, PRIMAL, DUAL, COMPLEMENTARITY, CONVERGED, RHO = range(6)
"""Offsets in ``info``: iterations done, the three residuals (K19) at the returned ``λ``,
1.0 where they passed the stopping rule, ADMM's last penalty ``ρ`` (0 for PGS)."""
INFO = 6


@inline
def input_scale(G, g, R):
    """``‖g‖∞``, the stopping rule's scale of the free velocity (K19), or -1 where ``g``,
    ``R`` or ``G`` holds NaN or inf: the check each solver begins with."""
    m = g.shape[0]
    gmax = 0.0
    for r in range(m):
        gmax = max(gmax, abs(g[r]))
        if not (math.isfinite(g[r]) and math.isfinite(R[r])):
            return -1.0
        for c in range(m):
            if not math.isfinite(G[r, c]):
                return -1.0
    return gmax


@inline
def velocity(G, R, g, lam, sigma):
    """``σ = (G + R) λ + g`` (K11); returns ``(‖σ‖∞, ‖(G + R) λ‖∞, ‖λ‖∞)``, the scales of
    the stopping rule (K19)."""
    m = g.shape[0]
    smax = gl = lmax = 0.0
    for r in range(m):
        acc = R[r] * lam[r]
        for c in range(m):
            acc += G[r, c] * lam[c]
        sigma[r] = acc + g[r]
        smax = max(smax, abs(sigma[r]))
        gl = max(gl, abs(acc))
        lmax = max(lmax, abs(lam[r]))
    return smax, gl, lmax


@inline
def passes(settings, primal, dual, comp, gmax, gl, lmax):
    """The stopping rule (K19): each residual below the absolute tolerance, or below the
    relative one times its scale: ``‖λ‖∞`` for the primal residual, ``max(‖g‖∞, ‖(G + R)
    λ‖∞)`` for the dual one, their product for the complementarity."""
    a, r = settings[ABS_TOL], settings[REL_TOL]
    sd = max(gmax, gl)
    return (primal <= a or primal <= r * lmax) and (dual <= a or dual <= r * sd) and \
        (comp <= a or comp <= r * lmax * sd)


@inline
def project_blocks(mu, bounds, x, out):
    """``out = P(x)`` block by block: each cone's K14, each interval's K27. ``out`` may be
    ``x``."""
    nc = mu.shape[0]
    for i in range(nc):
        project(mu[i], x, 3 * i, out, 3 * i)
    for b in range(bounds.shape[0]):
        r = 3 * nc + b
        out[r] = clamp(bounds[b, 0], bounds[b, 1], x[r])


@inline
def residuals(mu, bounds, lam, sigma, tmp):
    """The residuals (K19) of every block at ``λ``: the cones' (K13, ``cone.ncp_residuals``)
    and the intervals' (K28), as ``(primal, dual, complementarity)``, each the largest."""
    primal, dual, comp = ncp_residuals(mu, lam, sigma, tmp)
    o = 3 * mu.shape[0]
    for b in range(bounds.shape[0]):
        p, d, c = interval_residuals(bounds[b, 0], bounds[b, 1], lam[o + b], sigma[o + b])
        primal, dual, comp = max(primal, p), max(dual, d), max(comp, c)
    return primal, dual, comp
