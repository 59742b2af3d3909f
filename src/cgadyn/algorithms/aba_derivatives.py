"""Analytic derivatives of forward dynamics: ∂q̈/∂q, ∂q̈/∂v and ∂q̈/∂τ = M(q)⁻¹.

Forward dynamics inverts inverse dynamics: ``τ = ID(q, v, q̈(q, v, τ))`` for all q, v, τ, so
differentiating at ``q̈ = aba(q, v, τ)`` gives (``docs/derivatives.md``, D12)

    ∂q̈/∂q = -M⁻¹ ∂τ/∂q,   ∂q̈/∂v = -M⁻¹ ∂τ/∂v,   ∂q̈/∂τ = M⁻¹

with ∂τ/∂q and ∂τ/∂v of ``rnea_derivatives`` at that q̈. q̈ itself comes without ABA
(D13): the forward pass of the rnea derivatives at q̈ = 0 gives M and the bias, q̈ solves
``M q̈ = τ - τ(q, v, 0)`` by M's factorisation along the tree (L1, L2), which then gives
M⁻¹ (L3, L4), and the acceleration's part is added to that forward pass.
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import dot, twist_cross
from ..kernels.lanes import W
from ..kernels.rigid import rigid_apply
from . import _workspace as ws
from ._checks import check_configuration, check_result
from ._dense import minus_product, rows_subtract1, rows_subtract4
from .ltdl import ltdl, ltdl_inverse, ltdl_solve, ltdl_solve_rows, supports
from .rnea_derivatives import rnea_derivatives_backward, rnea_derivatives_forward
from .status import OK, SINGULAR, fault
from .work.aba_derivatives import workspace
from .work.rnea_derivatives import workspace as rnea_derivatives_workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "x": ("nv",),  # q̈ (zero for the forward pass)
    "b": ("nv",),  # the bias τ(q, v, 0)
    "X": ("nv", "2 * nv"),  # [∂τ/∂q  ∂τ/∂v]
    "acc": ("2 * nv",),  # a row of its product with M⁻¹
    "Ic": ("n", 10),  # the composites' copies (D7)
    "Fc": ("n", 6),
    "Aq": ("n", 6),  # q̈'s part of the accelerations
    "rest": ("size(rnea_derivatives)",),  # the rnea derivatives' workspace
}


@inline
def times_minus_minv(m, Minv, X, outq, outv, acc):
    """``outq = -M⁻¹ ∂τ/∂q`` and ``outv = -M⁻¹ ∂τ/∂v`` (D12), from ``X = [∂τ/∂q  ∂τ/∂v]``
    (nv, 2nv), the two side by side so that one sweep over a row of X serves both. Row i
    of the result is ``-Σ_k M⁻¹[i, k] X[k]``, accumulated in ``acc`` (2nv) four rows of X
    at a time: each pass over ``acc`` then does four multiply-adds per load and store, in
    loops of 2nv that the compiler vectorises; from ``W`` coordinates on, each product in
    blocks held in vector registers (``minus_product``). The product is dense: X's zeros
    (entries of coordinates on different branches) cost less than the branches that would
    skip them."""
    nv = m.nv
    if nv >= W:
        minus_product(Minv, X, 0, outq)
        minus_product(Minv, X, nv, outv)
        return
    w = 2 * nv
    for i in range(nv):
        r = Minv[i]
        for c in range(w):
            acc[c] = 0.0
        k = 0
        while k + 4 <= nv:
            rows_subtract4(acc, r[k], X[k], r[k + 1], X[k + 1], r[k + 2], X[k + 2], r[k + 3],
                           X[k + 3])
            k += 4
        while k < nv:
            rows_subtract1(acc, r[k], X[k])
            k += 1
        for c in range(nv):
            outq[i, c] = acc[c]
            outv[i, c] = acc[nv + c]


@inline
def solve_by_factors(m):
    """D15's choice of route to ``-M⁻¹ X``: the product with M⁻¹ from ``W`` coordinates on
    (in blocks held in vector registers, it is the faster route even on a humanoid);
    below that, L5-L6 when their row operations, ``2 (Σ_k d_k + nv)`` with the copy of the
    result, are fewer than 0.6 nv² (a branched tree)."""
    return m.nv < W and 10 * (supports(m) + m.nv) < 3 * m.nv * m.nv


@inline
def mass_and_bias(m, k_, Ic, Fc, H, b):
    """From the forward pass at q̈ = 0: the lower triangle of M into ``H`` (D10) and the
    torques of that pass ``b = τ(q, v, 0)`` (the bias, ``⟨S_k, F^c⟩``), with the
    composites accumulated in the copies ``Ic`` (n, 10) and ``Fc`` (n, 6) (D7), so that
    the body inertias and wrenches stay for the passes at q̈."""
    Iw, Sw = k_.Iw, k_.Sw
    for j in range(m.n):
        for i in range(10):
            Ic[j, i] = Iw[j, i]
    for k in range(m.nv - 1, -1, -1):  # children come after their parents
        j = m.dof_joint[k]
        w = rigid_apply(Ic[j], Sw[k])  # I^c[S_k], I^c complete
        i = k
        while i >= 0:  # k and the coordinates supporting it
            H[k, i] = -dot(Sw[i], w)  # M[k, i] = ⟨S_i, I^c[S_k]⟩ (D10)
            i = m.dof_parent[i]
        H[k, k] += m.armature[k]  # the rotor's inertia on the diagonal
        p = m.parents[j]
        if k == m.iv[j] and p >= 0:  # joint j done: its composite into the parent's
            for i in range(10):
                Ic[p, i] += Ic[j, i]
    bias(m, k_, Fc, b)


@inline
def bias(m, k_, Fc, b):
    """The torques of the forward pass at q̈ = 0, ``b = τ(q, v, 0) = ⟨S_k, F^c⟩`` (D13),
    with the composite wrenches accumulated in the copy ``Fc`` (n, 6)."""
    F, Sw = k_.F, k_.Sw
    for j in range(m.n):
        for i in range(6):
            Fc[j, i] = F[j, i]
    for k in range(m.nv - 1, -1, -1):  # children come after their parents
        j = m.dof_joint[k]
        b[k] = -dot(Sw[k], Fc[j])  # τ_k = ⟨S_k, F^c⟩
        p = m.parents[j]
        if k == m.iv[j] and p >= 0:  # joint j done: its composite into the parent's
            for i in range(6):
                Fc[p, i] += Fc[j, i]


@inline
def accelerate(m, k_, qdd, Aq):
    """Add q̈'s part to the forward pass run at q̈ = 0: ``A_j += Aq_j`` with ``Aq_j = Aq_λ +
    S_j q̈_j`` (D2; the velocity products do not involve q̈), ``ψ_k += Aq_λ × S_k`` (D4)
    and ``F_j += I_j[Aq_j]`` (eq. 15); every one is linear in the acceleration."""
    A, F, Iw, Sw, Psi, t1 = k_.A, k_.F, k_.Iw, k_.Sw, k_.Psi, k_.t1
    for j in range(m.n):
        p = m.parents[j]
        k0, k1 = m.iv[j], m.iv[j + 1]
        for i in range(6):
            x = Aq[p, i] if p >= 0 else 0.0
            for k in range(k0, k1):
                x += qdd[k] * Sw[k, i]
            Aq[j, i] = x
            A[j, i] += x
        w = rigid_apply(Iw[j], Aq[j])
        for i in range(6):
            F[j, i] += w[i]
        if p >= 0:
            for k in range(k0, k1):
                twist_cross(Aq[p], Sw[k], t1)
                for i in range(6):
                    Psi[k, i] += t1[i]


@core
def aba_derivatives_core(m, q, v, tau, f, dq, dv, dtau, work):
    """``dq = ∂q̈/∂q``, ``dv = ∂q̈/∂v``, ``dtau = ∂q̈/∂τ = M⁻¹`` (nv, nv) of one sample.

    q̈ without ABA: the forward pass of the rnea derivatives at q̈ = 0 gives M and the bias
    ``τ(q, v, 0)``, so ``q̈ = M⁻¹ (τ - τ(q, v, 0))`` (D13) from M's factorisation (L1, L2), which
    then gives M⁻¹ as well (L3, L4); the forward quantities that involve the acceleration
    are completed with q̈'s part, and the backward pass runs at q̈."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    w = workspace(ws.data_pointer(work), m)
    x, rest = w.x, w.rest
    for k in range(m.nv):
        x[k] = 0.0
    rnea_derivatives_forward(m, q, v, x, f, rest)  # at q̈ = 0
    return from_forward(m, tau, dq, dv, dtau, work)


@core
def from_forward(m, tau, dq, dv, dtau, work):
    """``aba_derivatives_core`` after the forward pass at q̈ = 0, whose results are in the
    rnea derivatives' part of ``work``; a status."""
    w = workspace(ws.data_pointer(work), m)
    x, b, X, acc, Ic, Fc, Aq = w.x, w.b, w.X, w.acc, w.Ic, w.Fc, w.Aq
    k_ = rnea_derivatives_workspace(ws.data_pointer(w.rest), m)
    mass_and_bias(m, k_, Ic, Fc, dtau, b)  # M, τ(q, v, 0)
    k = ltdl(m, dtau)  # M = Lᵀ D L (L1, L2)
    if k >= 0:
        return fault(SINGULAR, m.dof_joint[k])
    for k in range(m.nv):
        x[k] = tau[k] - b[k]
    ltdl_solve(m, dtau, x)  # q̈ = M⁻¹ (τ - τ(q, v, 0)) (D13)
    accelerate(m, k_, x, Aq)  # the forward pass at q̈
    nv = m.nv
    rnea_derivatives_backward(m, w.rest, X[:, :nv], X[:, nv:], X[:0])  # ∂τ/∂q, ∂τ/∂v at q̈ (M known)
    if solve_by_factors(m):  # a small branched tree: solve by M's factors (D15)
        ltdl_solve_rows(m, dtau, X, -1.0)  # -M⁻¹ ∂τ/∂q, -M⁻¹ ∂τ/∂v (D12, L5, L6)
        for i in range(nv):
            for c in range(nv):
                dq[i, c], dv[i, c] = X[i, c], X[i, nv + c]
        ltdl_inverse(m, dtau, x)  # M⁻¹ (L3, L4); q̈ is no longer needed
    else:  # eight coordinates or more, or a chain: the product with M⁻¹ (D15)
        ltdl_inverse(m, dtau, x)  # M⁻¹ (L3, L4); q̈ is no longer needed
        times_minus_minv(m, dtau, X, dq, dv, acc)  # -M⁻¹ ∂τ/∂q, -M⁻¹ ∂τ/∂v (D12)
    status = check_result(dtau)
    if status == OK:
        status = check_result(dq)
    if status == OK:
        status = check_result(dv)
    return status


@inline
def from_inverse(m, tau, dq, dv, Minv, work):
    """``from_forward`` with M⁻¹ already in ``Minv`` (a batch has it from the
    articulated-body recursion on a group of samples, ``minverse_lanes``): q̈ = M⁻¹ (τ -
    τ(q, v, 0)) as the product (D13) instead of by M's factors, which are not formed; a
    status. Inlined into its one caller, the batch's loop over a group's samples
    (``aba_derivatives_lanes._group``): there ``Minv``, ``dq`` and ``dv`` are rows of the
    results whose shapes the loop knows, where a called pass reads them at every index."""
    w = workspace(ws.data_pointer(work), m)
    x, b, X, acc, Fc, Aq = w.x, w.b, w.X, w.acc, w.Fc, w.Aq
    k_ = rnea_derivatives_workspace(ws.data_pointer(w.rest), m)
    nv = m.nv
    bias(m, k_, Fc, b)  # τ(q, v, 0)
    for k in range(nv):
        acc[k] = tau[k] - b[k]
    for i in range(nv):  # q̈ = M⁻¹ (τ - τ(q, v, 0)) (D13)
        y = 0.0
        for k in range(nv):
            y += Minv[i, k] * acc[k]
        x[i] = y
    accelerate(m, k_, x, Aq)  # the forward pass at q̈
    rnea_derivatives_backward(m, w.rest, X[:, :nv], X[:, nv:], X[:0])  # ∂τ/∂q, ∂τ/∂v at q̈
    times_minus_minv(m, Minv, X, dq, dv, acc)  # -M⁻¹ ∂τ/∂q, -M⁻¹ ∂τ/∂v (D12)
    status = check_result(dq)
    if status == OK:
        status = check_result(dv)
    return status

