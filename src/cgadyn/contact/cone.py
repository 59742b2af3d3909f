"""The Coulomb cone of one contact, written once for every solver: its projection (K14), the
projection on its dual cone (K15), De Saxcé's correction (K13) and the three residuals of the
NCP at a point (K19) (``docs/contact.md``).

A contact's three numbers are ``(t₁, t₂, n)``: two tangential components, then the normal,
as Pinocchio orders a ``CoulombFrictionCone``. ``K_μ = {‖λ_T‖ <= μ λ_N}`` (K12).
"""

from __future__ import annotations

import math

from .._jit import inline

__all__ = ["desaxce", "dual_project", "ncp_residuals", "project"]


@inline
def project(mu, x, o, out, p):
    """``out[p:p+3] = P_Kμ(x[o:o+3])``, the Euclidean projection on the cone (K14): ``x``
    itself inside, zero in the polar cone ``μ ‖x_T‖ <= -x_N``, else the nearest point of the
    cone's surface, ``n' = (μ ‖x_T‖ + x_N) / (1 + μ²)``, ``x_T' = μ n' x_T / ‖x_T‖``. ``out``
    may be ``x``."""
    t1, t2, n = x[o], x[o + 1], x[o + 2]
    t = math.sqrt(t1 * t1 + t2 * t2)
    if t <= mu * n:
        out[p], out[p + 1], out[p + 2] = t1, t2, n
    elif mu * t <= -n:
        out[p], out[p + 1], out[p + 2] = 0.0, 0.0, 0.0
    else:
        nn = (mu * t + n) / (1.0 + mu * mu)
        s = mu * nn / t
        out[p], out[p + 1], out[p + 2] = s * t1, s * t2, nn


@inline
def dual_project(mu, x, o, tmp, out, p):
    """``out[p:p+3] = P_Kμ*(x[o:o+3])``, the projection on the dual cone
    ``K_μ* = {μ ‖σ_T‖ <= σ_N}`` by Moreau's decomposition, ``P_K*(x) = x + P_K(-x)`` (K15);
    ``tmp`` holds three floats."""
    for i in range(3):
        tmp[i] = -x[o + i]
    project(mu, tmp, 0, tmp, 0)
    for i in range(3):
        out[p + i] = x[o + i] + tmp[i]


@inline
def desaxce(mu, sigma, o):
    """The normal component of De Saxcé's correction ``Γ(σ) = (0, 0, μ ‖σ_T‖)`` (K13)."""
    return mu * math.sqrt(sigma[o] * sigma[o] + sigma[o + 1] * sigma[o + 1])


@inline
def ncp_residuals(mu, lam, sigma, tmp):
    """The NCP's residuals at ``λ`` with ``σ = (G + R) λ + g`` (K19), as ``(primal, dual,
    complementarity)``: ``max_i ‖λ_i - P_K(λ_i)‖∞``, ``max_i ‖σ̃_i - P_K*(σ̃_i)‖∞`` and
    ``max_i |λ_i · σ̃_i|`` with ``σ̃ = σ + Γ(σ)`` (K13); ``tmp`` holds six floats."""
    primal = dual = comp = 0.0
    for i in range(mu.shape[0]):
        o = 3 * i
        project(mu[i], lam, o, tmp, 3)  # tmp[3:6] = P_K(λ_i)
        for k in range(3):
            primal = max(primal, abs(lam[o + k] - tmp[3 + k]))
        tmp[3], tmp[4], tmp[5] = sigma[o], sigma[o + 1], sigma[o + 2] + desaxce(mu[i], sigma, o)
        comp = max(comp, abs(lam[o] * tmp[3] + lam[o + 1] * tmp[4] + lam[o + 2] * tmp[5]))
        a0, a1, a2 = tmp[3], tmp[4], tmp[5]
        dual_project(mu[i], tmp, 3, tmp, tmp, 3)  # tmp[3:6] = P_K*(σ̃_i)
        dual = max(dual, abs(a0 - tmp[3]), abs(a1 - tmp[4]), abs(a2 - tmp[5]))
    return primal, dual, comp
