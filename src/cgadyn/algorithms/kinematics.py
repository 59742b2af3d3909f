"""Forward kinematics: the motor of every joint frame and link frame in the world, eq. (5).

``M^w_j = M^w_λ(j) M_j`` with ``M_j = X_j M_J(q_j)`` (eqs. 5-6): the product of eq. (5)
taken along the path from the root. A link rigidly attached to body j is at
``M^w_link = M^w_j P_link`` (P: the link frame in the joint frame, the world for links
fixed to it).
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import motor_mul
from ..kernels.rigid import motor_matrix
from ..multibody.joints import free_root, joint_motors, joint_scalars
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .status import OK
from .work.kinematics import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "M": ("n", 8),  # the joint motors
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
    "Mw": ("n", 8),  # the world motors (``motors_core`` writes them into its output)
}


@inline
def world_motors(m, q, c, s, tmp8, M, Mw):
    """``Mw[j] = M^w_j`` (n, 8) for every joint frame, ``M[j] = M_j`` (n, 8) on the way;
    ``c, s`` (nq) and ``tmp8`` (8) scratch."""
    frame_motors(m, q, c, s, tmp8, M, Mw, False)


@inline
def frame_motors(m, q, c, s, tmp8, M, Mw, free_roots_at_rest):
    """``world_motors``; with ``free_roots_at_rest`` a free-flyer root takes the identity
    instead of its motor, so that its tree is in the root body's own frame (a quantity that
    a common rigid motion of the whole tree leaves alone, as M(q)⁻¹, may be computed
    there)."""
    joint_scalars(q, c, s)  # the scalars of every revolute joint motor (eq. 6)
    chain_motors(m, q, c, s, tmp8, M, Mw, free_roots_at_rest)


@inline
def chain_motors(m, q, c, s, tmp8, M, Mw, free_roots_at_rest):
    """``frame_motors`` from the joints' scalars ``c, s`` on: the joint motors and their
    products down the tree. Only arithmetic, so that it runs on ``W`` samples at once as
    well (``kernels.lane_arrays``)."""
    joint_motors(m, q, c, s, tmp8, M)  # M_j = X_j M_J(q_j)
    for j in range(m.n):
        p = m.parents[j]
        if p < 0:
            rest = free_roots_at_rest and free_root(p, m.types[j])
            for k in range(8):
                Mw[j, k] = (1.0 if k == 0 else 0.0) if rest else M[j, k]  # M^w_j = M_j
        else:
            motor_mul(Mw[p], M[j], Mw[j])  # M^w_j = M^w_λ M_j


@inline
def unit_coefficient(S):
    """``(i, S[i])`` of a unit twist's one nonzero coefficient: a free-flyer root's S_k in
    its own frame (``frame_motors`` with ``free_roots_at_rest``), whose pairing with a
    wrench W is then ``⟨S_k, W⟩ = S[i] W[i]``."""
    i = 0
    for k in range(1, 6):
        if abs(S[k]) > abs(S[i]):
            i = k
    return i, S[i]


@inline
def link_motor(m, Mw, i, out):
    """``out = M^w_link`` of link frame ``i`` from the joints' world motors."""
    j = m.link_joint[i]
    if j < 0:
        for k in range(8):
            out[k] = m.link_placements[i, k]
    else:
        motor_mul(Mw[j], m.link_placements[i], out)


@core
def motors_core(m, q, joints, links, work):
    """World motors of the joint frames (n, 8) and of the link frames (nl, 8)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    M, tmp8, c, s = k_.M, k_.tmp8, k_.c, k_.s
    world_motors(m, q, c, s, tmp8, M, joints)
    for i in range(m.nl):
        link_motor(m, joints, i, links[i])
    return check_result(links)


@core
def placements_core(m, q, T, work):
    """World 4x4 matrices of the link frames (nl, 4, 4)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    M, tmp8, c, s, Mw = k_.M, k_.tmp8, k_.c, k_.s, k_.Mw
    world_motors(m, q, c, s, tmp8, M, Mw)
    for i in range(m.nl):
        link_motor(m, Mw, i, tmp8)
        motor_matrix(tmp8, T[i])
    return check_result(T)
