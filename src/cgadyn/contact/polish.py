"""Polishing a PGS iterate by its active set (``docs/contact.md``, K18a): once the sweeps
(K18) have found which contacts stick, slide or separate and which interval rows sit at a
bound, the NCP (K13, K26) on that guess is a square system of equations, which a few Newton
steps end.

With ``A = G + R`` and ``σ = A λ + g`` (K11), each block's conditions on its guessed set are
equations in its unknowns:

- a contact that sticks (``‖λ_T‖ < μ λ_N``): ``σ_i = 0``, three unknowns ``λ_i``;
- a contact that slides (``‖λ_T‖ = μ λ_N > 0``): ``σ_N = 0`` and ``λ_T ‖σ_T‖ + μ λ_N σ_T =
  0`` (its friction on the cone's edge, opposite its sliding velocity: maximum
  dissipation), three unknowns ``λ_i``;
- a contact apart (``λ_N = 0``): ``λ_i = 0``;
- an interval row strictly inside its bounds: ``σ_r = 0``, one unknown; at a bound: fixed.

Newton's step on them, ``F'(λ) δ = -F(λ)`` (K18a), over the unknowns' rows, with a sliding
contact's tangential rows ``∂F_T/∂λ = ‖σ_T‖ E_T + λ_T σ_Tᵀ A_T / ‖σ_T‖ + μ σ_T e_Nᵀ + μ
λ_N A_T``, solved by Gaussian elimination with partial pivoting. The equations of sticking
contacts and interval rows are linear, so without a sliding contact one step is exact;
with one, the steps converge quadratically from the sweeps' iterate, and a direction is
settled to rounding, where K19's complementarity residual fixes it only to the square root
of its tolerance. The result is kept only where K19's stopping rule passes on it, every
residual recomputed from ``σ`` formed anew (``ncp.velocity``, ``ncp.residuals``): a wrong
guess or a singular system (redundant contacts) leaves the sweeps' iterate as it was, and
they go on. It is the polishing step of OSQP (Stellato et al., 2020) on the contact NCP.
"""

from __future__ import annotations

import math

from .._jit import inline

INSIDE = 1.0 - 1e-9
"""A contact whose ``‖λ_T‖`` is below ``INSIDE · μ λ_N`` sticks; at or above it slides."""
PIVOT = 1e-9
"""A pivot below ``PIVOT`` times the largest diagonal of ``F'``: the guessed system is
singular (redundant contacts: a box's four corners, whose G holds its null directions only
to rounding) or nearly so, and the polish gives up. A lower bound let such a system through
with forces along its null directions that no velocity checks and rounding then carries
into the velocities after the step."""


@inline
def active_set(mu, bounds, lam, rows, slides):
    """The unknowns' rows of the guess at ``λ`` (module docstring) into ``rows``, and for
    each 1.0 where it is a sliding contact's (``slides``). Returns ``(unknowns, sliding
    contacts)``."""
    k = sliding = 0
    nc = mu.shape[0]
    for i in range(nc):
        o = 3 * i
        n = lam[o + 2]
        if n <= 0.0:
            continue
        slide = math.sqrt(lam[o] * lam[o] + lam[o + 1] * lam[o + 1]) >= INSIDE * mu[i] * n
        sliding += int(slide)
        for r in range(3):
            rows[k], slides[k] = o + r, 1.0 if slide else 0.0
            k += 1
    for b in range(bounds.shape[0]):
        r = 3 * nc + b
        if bounds[b, 0] < lam[r] < bounds[b, 1]:
            rows[k], slides[k] = r, 0.0
            k += 1
    return k, sliding


@inline
def _entry(G, R, r, c):
    """``A[r, c] = (G + R)[r, c]``, ``R`` the diagonal."""
    return G[r, c] + (R[r] if r == c else 0.0)


@inline
def _equation(G, R, mu, lam, sigma, rows, slides, k, a, M, x):
    """Row ``a`` of Newton's system: ``M[a, :k] = ∂F_a/∂λ_rows`` and ``x[a] = -F_a`` at ``λ``
    with its ``σ``, for unknown ``a``'s row ``r``: ``F = σ_r`` (a sticking contact's row,
    a sliding contact's normal, an interval's), ``F = λ_r ‖σ_T‖ + μ λ_N σ_r`` (a sliding
    contact's tangential row)."""
    r = int(rows[a])
    if slides[a] == 0.0 or r % 3 == 2:
        x[a] = -sigma[r]
        for b in range(k):
            M[a, b] = _entry(G, R, r, int(rows[b]))
        return
    o = r - r % 3
    i = o // 3
    s = math.sqrt(sigma[o] * sigma[o] + sigma[o + 1] * sigma[o + 1])
    n = lam[o + 2]
    x[a] = -(lam[r] * s + mu[i] * n * sigma[r])
    ls = lam[r] / s if s > 0.0 else 0.0  # λ_r / ‖σ_T‖, once for the row
    for b in range(k):
        c = int(rows[b])
        v = mu[i] * n * _entry(G, R, r, c)
        if s > 0.0:
            v += ls * (sigma[o] * _entry(G, R, o, c) + sigma[o + 1] * _entry(G, R, o + 1, c))
        if c == r:
            v += s
        if c == o + 2:
            v += mu[i] * sigma[r]
        M[a, b] = v


@inline
def unsettled(mu, lam, sigma, rows, slides, k):
    """The largest ``|F_a|`` over the unknowns (module docstring) at ``λ`` with its ``σ``, in
    velocity units: ``|σ_r|``, and for a sliding contact's tangential row ``|λ_r ‖σ_T‖ + μ
    λ_N σ_r| / (μ λ_N)`` (the sliding velocity's part across its friction)."""
    out = 0.0
    for a in range(k):
        r = int(rows[a])
        if slides[a] == 0.0 or r % 3 == 2:
            out = max(out, abs(sigma[r]))
            continue
        o = r - r % 3
        mn = mu[o // 3] * lam[o + 2]
        s = math.sqrt(sigma[o] * sigma[o] + sigma[o + 1] * sigma[o + 1])
        out = max(out, abs(lam[r] * s + mn * sigma[r]) / mn if mn > 0.0 else math.inf)
    return out


@inline
def newton_step(G, R, mu, lam, sigma, rows, slides, k, M, x):
    """``λ`` moved by Newton's step on the ``k`` unknowns (module docstring) at ``λ`` with
    its ``σ = A λ + g``; ``M`` (at least k x k) and ``x`` (at least k) scratch. Returns the
    step's largest ``|δ|``, or -1.0, ``λ`` unchanged, where a pivot is below ``PIVOT``
    (the guess is singular)."""
    scale = 0.0
    for a in range(k):
        _equation(G, R, mu, lam, sigma, rows, slides, k, a, M, x)
        scale = max(scale, abs(M[a, a]))
    for c in range(k):  # elimination with partial pivoting
        p = c
        for a in range(c + 1, k):
            if abs(M[a, c]) > abs(M[p, c]):
                p = a
        if not abs(M[p, c]) > PIVOT * scale:
            return -1.0
        if p != c:
            for b in range(k):
                M[c, b], M[p, b] = M[p, b], M[c, b]
            x[c], x[p] = x[p], x[c]
        inv = 1.0 / M[c, c]
        for a in range(c + 1, k):
            f = M[a, c] * inv
            if f != 0.0:
                for b in range(c, k):
                    M[a, b] -= f * M[c, b]
                x[a] -= f * x[c]
    step = 0.0
    for c in range(k - 1, -1, -1):
        acc = x[c]
        for b in range(c + 1, k):
            acc -= M[c, b] * x[b]
        x[c] = acc * (1.0 / M[c, c])
        step = max(step, abs(x[c]))
    for j in range(k):
        lam[int(rows[j])] += x[j]
    return step
