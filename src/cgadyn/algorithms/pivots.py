"""A joint's pivot in the articulated-body recursion: the three steps that ABA (Algorithm 1),
M⁻¹ (M1, M2) and the Delassus recursion (C12, C13) share at a joint of several coordinates
``k0 .. k1`` (a one-coordinate joint takes them with a number for D_j, inline in each):

    D_j = -S_jᵀ · U_j + armature,   given U_j = Î_j[S_j]        Algorithm 1; M1
    G_j = U_j D_j⁻¹                                             Algorithm 1; M2
    Ĩ_j = Î_j - U_j G_jᵀ                                        Algorithm 1, second line

``S`` and ``U`` hold one row per coordinate (``S[k]``, ``U[k]``, k in ``k0 .. k1``);
``D`` and ``Dinv`` are (6, 6) of which the leading (k1 - k0) block is used. Only
arithmetic and ``positive``: each runs on one sample's numbers or on ``W`` samples at once
(``kernels.lane_arrays``), as ``minverse``'s batches do.
"""

from __future__ import annotations

from .._jit import inline
from ..kernels import dot
from ._dense import spd_inverse


@inline
def joint_pivot(armature, S, U, k0, k1, D, Dinv):
    """``D`` = D_j = -S_jᵀ · U_j plus the rotors' inertia ``armature[k]`` on its diagonal,
    and ``Dinv`` = D_j⁻¹ (``D`` is overwritten). False when D_j is not positive definite
    (a subtree without inertia along the joint's motion)."""
    for a in range(k0, k1):
        for b in range(k0, k1):
            D[a - k0, b - k0] = -dot(S[a], U[b])  # D_j = -S_jᵀ · U_j
        D[a - k0, a - k0] += armature[a]  # + the rotors' inertia
    return spd_inverse(D, k1 - k0, Dinv)


@inline
def pivot_gain(Dinv, U, k0, k1, G):
    """``G[k]`` for k in ``k0 .. k1``: G_j = U_j D_j⁻¹, one wrench per coordinate."""
    for a in range(k0, k1):
        for i in range(6):
            G[a, i] = 0.0
        for b in range(k0, k1):
            w = Dinv[a - k0, b - k0]
            for i in range(6):
                G[a, i] += w * U[b, i]


@inline
def articulated_inertia(Ih, U, G, k0, k1, It):
    """``It`` = Ĩ_j = Î_j - U_j G_jᵀ from ``Ih`` = Î_j (6, 6), symmetric: the upper half
    formed, the lower mirrored."""
    for k in range(6):
        for l in range(k, 6):
            It[k, l] = Ih[k, l]
    for a in range(k0, k1):
        for k in range(6):
            w = U[a, k]
            for l in range(k, 6):
                It[k, l] -= w * G[a, l]
    for k in range(6):
        for l in range(k + 1, 6):
            It[l, k] = It[k, l]
