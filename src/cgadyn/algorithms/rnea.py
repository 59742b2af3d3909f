"""Recursive inverse dynamics (RNEA) in CGA: Algorithm 2 of the CGA paper, on trees.

Every body j has the frame of its joint; ``λ(j) = parents[j]`` is its parent (-1: the world).
Forward pass (j = 1..n)::

    M_j  = X_j M_J(q_j)                                  pose of j in λ(j) (eqs. 5-6)
    V_j  = ~M_j V_λ M_j + S_j q̇_j                        twist
    V̇_j  = ~M_j V̇_λ M_j + V_j × S_j q̇_j + S_j q̈_j        its derivative, eqs. (10-11)
    W_j  = I_j[V̇_j] + V_j × I_j[V_j] - W_ext,j          eq. (15)

Backward pass (j = n..1)::

    τ_j  = -S_jᵀ · W_j                                   power pairing, eq. (9)
    W_λ += M_j W_j ~M_j

``S_j q̇_j`` is the joint's twist: ``q̇_j B_j`` for a one-dof joint with screw B_j, the body
twist itself for a free flyer (``multibody.joints``). Gravity enters as the base
acceleration ``V̇_0 = -g`` (Featherstone's fictitious base acceleration). The paper writes
the bracket as ``B_j × V_j`` and the gyroscopic term with a minus sign: with the sign
conventions of ``cgadyn.cga.conventions`` (where ``×`` is the Lie bracket of twists) these
are the same quantities.

Each joint's sandwich ``M_j (·) ~M_j`` is applied three times, so it is expanded once into
its matrix ``Ad_j`` (``wrench_adjoint``, generated from eq. 4): ``M_j W ~M_j = Ad_j W`` and,
by the invariance of the power pairing, ``~M_j V M_j = Ad_jᵀ V``.
"""

from __future__ import annotations

from .._jit import core
from ..kernels import (
    adjoint_apply,
    adjoint_apply_transpose,
    inertia_apply,
    twist_cross,
    twist_cross_wrench,
    wrench_adjoint,
)
from ..multibody.joints import joint_motors, joint_power, joint_scalars, joint_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .status import OK
from .work.rnea import workspace, workspace_size

__all__ = ["WORKSPACE", "rnea_core", "workspace_size"]

WORKSPACE = {  # one sample's arrays (tools/generate_workspaces.py writes work/rnea.py)
    "Ad": ("n", 6, 6),  # M_j (·) ~M_j as a matrix, per body
    "V": ("n", 6),  # the bodies' twists V_j
    "A": ("n", 6),  # their accelerations V̇_j
    "W": ("n", 6),  # their wrenches W_j
    "VJ": (6,),  # S_j q̇_j, then S_j q̈_j
    "tmp": (6,),
    "M": ("n", 8),  # the joint motors M_j
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


@core
def rnea_core(m, q, v, a, f, tau, work):
    """One sample of Algorithm 2 into ``tau`` (nv); ``f`` the external wrenches (n, 6), or
    (0, 6) for none; ``work`` ``workspace_size`` floats. Returns a status."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    n = m.n
    k_ = workspace(ws.data_pointer(work), m)
    Ad, V, A, W, VJ, tmp, M, tmp8, c, s = (k_.Ad, k_.V, k_.A, k_.W, k_.VJ, k_.tmp, k_.M,
                                           k_.tmp8, k_.c, k_.s)
    joint_scalars(q, c, s)  # the scalars of every revolute joint motor (eq. 6)
    joint_motors(m, q, c, s, tmp8, M)  # M_j = X_j M_J(q_j)
    for j in range(n):
        p = m.parents[j]
        wrench_adjoint(M[j], Ad[j])  # M_j (·) ~M_j as a matrix
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
            adjoint_apply_transpose(Ad[j], m.gravity, A[j])  # V̇_0 = -g
        else:
            adjoint_apply_transpose(Ad[j], V[p], V[j])  # ~M_j V_λ M_j
            adjoint_apply_transpose(Ad[j], A[p], A[j])  # ~M_j V̇_λ M_j
        joint_twist(m, j, v, VJ)  # S_j q̇_j
        for k in range(6):
            V[j, k] += VJ[k]  # V_j = ~M_j V_λ M_j + S_j q̇_j
        twist_cross(V[j], VJ, tmp)  # V_j × S_j q̇_j
        joint_twist(m, j, a, VJ)  # S_j q̈_j
        for k in range(6):  # V̇_j = ~M_j V̇_λ M_j + V_j × S_j q̇_j + S_j q̈_j
            A[j, k] += tmp[k] + VJ[k]
        inertia_apply(m.inertias[j], A[j], W[j])  # I_j[V̇_j]
        inertia_apply(m.inertias[j], V[j], tmp)
        twist_cross_wrench(V[j], tmp, tmp)  # V_j × I_j[V_j]
        for k in range(6):
            W[j, k] += tmp[k]
        if f.shape[0] > 0:
            for k in range(6):
                W[j, k] -= f[j, k]
    for j in range(n - 1, -1, -1):
        joint_power(m, j, W[j], tau)  # τ_j = -S_jᵀ · W_j
        for k in range(m.iv[j], m.iv[j + 1]):
            tau[k] += m.armature[k] * a[k]  # the rotors' inertia, M's diagonal
        p = m.parents[j]
        if p >= 0:
            adjoint_apply(Ad[j], W[j], tmp)  # W_λ += M_j W_j ~M_j
            for k in range(6):
                W[p, k] += tmp[k]
    return check_result(tau)
