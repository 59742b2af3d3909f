"""The position correction of a step's contacts (docs/contact.md, K43): a penetration is
taken back by the configuration alone, with no velocity left behind.

A rigid contact's normal row closes an open gap within the step and holds a penetration
where it is (K23's term ``max(d, 0) / dt``); the step's position update then moves the
configuration by the smallest displacement δ, in the metric of the mass matrix, that takes
each contact's penetration at the end of the step back by the fraction β and takes no
other inside:

```
min ½ δᵀ M δ   subject to   J_N δ >= b,    b_c = -β e_c (e_c < 0),   b_c = -e_c (e_c >= 0)
e_c = min(d_c, 0) + dt σ_N,c        (the gap at the end of the step, σ = G λ + g)
δ = M⁻¹ J_Nᵀ μ,   0 <= μ ⊥ G_NN μ - b >= 0,   q⁺ ← q⁺ ⊕ δ                          (K43)
```

where ``J_N`` are the rigid contacts' normal rows and ``G_NN = J_N M⁻¹ J_Nᵀ`` their block of
the step's Delassus matrix. It is the post-stabilization of Cline and Pai (2003), the
position half of a split impulse: K23's velocity ``β d / dt`` stayed in ``v⁺``, and a ball
of 1 kg started 1 cm inside the ground left it at 2 m/s and rose 19 cm (0.88 J, then 2.90 J);
K43 leaves ``v⁺`` as the contact problem made it, and the ball rises to the ground's surface
by ``1 - (1 - β)^k`` of its depth in k steps. In M's metric the correction moves a floating
base, not only the link that touches: the displacement an impulse ``J_Nᵀ μ`` would give.
"""

from __future__ import annotations

import math

from .._jit import inline

SWEEPS = 100
"""Projected Gauss-Seidel sweeps at most for μ (K43): a sweep that changes no row's velocity
by more than ``TOLERANCE`` of the deepest target ends them. Each sweep lowers the problem's
objective, so a correction stopped short is still a correction, never a push."""
TOLERANCE = 1e-6
"""The change of ``G_NN μ`` (m), relative to the deepest target, below which the sweeps
stop (K43): a correction to a millionth of itself, which the next step's corrects further."""


@inline
def correction_targets(G, g, lam, depth, nc, beta, dt, b):
    """``b`` (nc,) of K43 from each contact's signed distance at the start of the step
    (``depth``: NaN for a compliant contact, which its spring holds and K43 leaves alone),
    its normal row ``3c + 2`` of the step's ``G`` and ``g`` and the impulses ``λ``; the
    deepest target, ``<= 0`` where no contact ends the step inside (no correction), 0
    where none begins it inside."""
    inside = False
    for c in range(nc):
        inside = inside or depth[c] < 0.0  # NaN: False
    if not inside:
        return 0.0
    deepest = 0.0
    for c in range(nc):
        d = depth[c]
        if math.isnan(d):
            b[c] = -math.inf
            continue
        r = 3 * c + 2
        sigma = g[r]
        for k in range(lam.shape[0]):
            sigma += G[r, k] * lam[k]
        e = min(d, 0.0) + dt * sigma  # the gap at the end of the step
        b[c] = -beta * e if e < 0.0 else -e
        deepest = max(deepest, b[c])
    return deepest


@inline
def correction_impulses(G, nc, b, deepest, mu):
    """``0 <= μ ⊥ G_NN μ - b >= 0`` (K43) by projected Gauss-Seidel from zero on the normal
    rows ``3c + 2`` of ``G``; a contact whose ``b`` is ``-inf`` takes no part."""
    for c in range(nc):
        mu[c] = 0.0
    for _ in range(SWEEPS):
        change = 0.0
        for c in range(nc):
            r = 3 * c + 2
            if b[c] == -math.inf or G[r, r] <= 0.0:
                continue
            w = -b[c]
            for k in range(nc):
                w += G[r, 3 * k + 2] * mu[k]
            new = max(0.0, mu[c] - w / G[r, r])
            change = max(change, abs(new - mu[c]) * G[r, r])
            mu[c] = new
        if change <= TOLERANCE * deepest:
            break
