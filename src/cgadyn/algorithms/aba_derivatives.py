"""Analytic derivatives of forward dynamics: ∂q̈/∂q, ∂q̈/∂v and ∂q̈/∂τ = M(q)⁻¹.

Forward dynamics inverts inverse dynamics: ``τ = ID(q, v, q̈(q, v, τ))`` for all q, v, τ, so
differentiating at ``q̈ = aba(q, v, τ)`` gives (``docs/derivatives.md``, D12)

    ∂q̈/∂q = -M⁻¹ ∂τ/∂q,   ∂q̈/∂v = -M⁻¹ ∂τ/∂v,   ∂q̈/∂τ = M⁻¹

with ∂τ/∂q and ∂τ/∂v of ``rnea_derivatives`` at that q̈, which also gives M (its ∂τ/∂a),
and M⁻¹ from that M by ``minverse``'s factorisation along the tree (M1-M4). ∂τ/∂q is
sparse: its entry (k, l) is zero unless k and l lie on one branch, so the products run over
the coordinates related to each column only.
"""

from __future__ import annotations

from .._jit import core, inline
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .aba import aba_core
from .aba import workspace_size as aba_workspace
from .minverse import minverse_from_mass
from .rnea_derivatives import _workspace as rnea_derivatives_workspace
from .rnea_derivatives import rnea_derivatives_backward, rnea_derivatives_forward
from .rnea_derivatives import workspace_size as rnea_derivatives_size
from .status import OK


@inline
def times_minus_minv(m, Minv, Dq, Dv, outq, outv):
    """``outq = -M⁻¹ Dq`` and ``outv = -M⁻¹ Dv`` for the ∂τ matrices Dq, Dv (D12). Row l of
    the transposes ``-Dᵀ M⁻¹`` (M⁻¹ symmetric) sums the rows of M⁻¹ over the coordinates k
    related to l only (D[k, l] is zero unless k and l lie on one branch: those of l's
    joint's subtree and of the joints above it), each a contiguous row read once for both
    products; the outputs hold the transposes, then are transposed in place."""
    nv = m.nv
    for l in range(nv):
        tq = outq[l]
        tv = outv[l]
        for i in range(nv):
            tq[i] = 0.0
            tv[i] = 0.0
        j = m.dof_joint[l]
        for k in range(m.iv[j], m.subtree_end[j]):  # l's joint and below
            x = Dq[k, l]
            y = Dv[k, l]
            r = Minv[k]
            for i in range(nv):
                tq[i] -= x * r[i]
                tv[i] -= y * r[i]
        k = m.dof_parent[m.iv[j]]
        while k >= 0:  # the joints above
            x = Dq[k, l]
            y = Dv[k, l]
            r = Minv[k]
            for i in range(nv):
                tq[i] -= x * r[i]
                tv[i] -= y * r[i]
            k = m.dof_parent[k]
    for i in range(nv):
        for l in range(i):
            outq[i, l], outq[l, i] = outq[l, i], outq[i, l]
            outv[i, l], outv[l, i] = outv[l, i], outv[i, l]


@core
def aba_derivatives_core(m, q, v, tau, f, dq, dv, dtau, option, work):
    """``dq = ∂q̈/∂q``, ``dv = ∂q̈/∂v``, ``dtau = ∂q̈/∂τ = M⁻¹`` (nv, nv) of one sample."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    qdd, D, rest = _workspace(ws.data_pointer(work), m)
    status = aba_core(m, q, v, tau, f, qdd, option, rest)  # q̈
    if status != OK:
        return status
    k_ = rnea_derivatives_workspace(ws.data_pointer(rest), m)
    rnea_derivatives_forward(m, q, v, qdd, f, k_)
    rnea_derivatives_backward(m, k_, D[0], D[1], dtau)  # ∂τ/∂q, ∂τ/∂v at q̈, and M
    status = minverse_from_mass(m, dtau, qdd)  # M⁻¹ (M1-M4); q̈ is no longer needed
    if status != OK:
        return status
    times_minus_minv(m, dtau, D[0], D[1], dq, dv)  # -M⁻¹ ∂τ/∂q, -M⁻¹ ∂τ/∂v (D12)
    status = check_result(dq)
    if status == OK:
        status = check_result(dv)
    return status


@inline
def workspace_size(n, nq, nv, nl):
    return nv + 2 * nv * nv + max(aba_workspace(n, nq, nv, nl),
                                  rnea_derivatives_size(n, nq, nv, nl))


@inline
def _workspace(buf, m):
    """q̈ (nv) (then the scratch row of ``minverse_from_mass``), ∂τ/∂q, ∂τ/∂v (2, nv, nv),
    then the space aba and the rnea derivatives share."""
    qdd, o = ws.carve(buf, 0, (m.nv,))
    D, o = ws.carve(buf, o, (2, m.nv, m.nv))
    size = max(aba_workspace(m.n, m.nq, m.nv, m.nl), rnea_derivatives_size(m.n, m.nq, m.nv, m.nl))
    rest, o = ws.carve(buf, o, (size,))
    return qdd, D, rest
