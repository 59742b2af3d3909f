"""Centroidal quantities: the centre of mass, its velocity and acceleration, and the
centroidal momentum matrix (Pinocchio's ``centerOfMass`` and ``ccrba``).

A body's first moment in the world is ``m_j c_j = m_j p_j + R_j h_j`` (h_j its first
moment in its own frame, ``M^w_j = T(p_j) R_j``), and the force part of its momentum
wrench ``I_j[V_j]`` (eq. 15) is its linear momentum ``m_j ċ_j``; the force part of
``I_j[V̇_j] + V_j × I_j[V_j]`` (the RNEA body wrench without gravity) is its rate
``m_j c̈_j``. Summed in the world and divided by the total mass: c, ċ, c̈.

The centroidal momentum matrix ``A_g`` maps v to the momentum of the whole robot, linear and
angular about its centre of mass. In world coordinates (as in ``crba``), velocity coordinate
k of joint j moves the composite body ``I^c_j`` (j and its descendants) with the twist
``S^w_k``, whose momentum wrench ``F_k = I^c_j[S^w_k]`` (eq. 15) is at the world's origin;
moved to the centre of mass, its moment is ``n - c × f``: ``A_g[:, k] = (f, n - c × f)``.
A robot that is one tree on a free-flyer root is computed in its root body's frame instead
(``kinematics.frame_motors`` with ``free_roots_at_rest``, as ``crba``), where nothing
carries the base's distance from the origin, and its rows and c are then turned to the
world: ``A_g = diag(R, R) A'_g`` and ``c = R c' + p`` with ``M^w_root = T(p) R``.
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels import (
    adjoint_apply_transpose,
    inertia_apply,
    twist_cross,
    twist_cross_wrench,
    wrench_adjoint,
)
from ..kernels.layout import physical
from ..kernels.rigid import (
    rigid_apply,
    rigid_frame,
    rigid_move_inertia,
    rigid_move_twist,
    rigid_parameters,
    rigid_rotate,
)
from ..multibody.joints import joint_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import frame_motors, free_root, world_motors
from .status import OK
from .work.centroidal import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Mw": ("n", 8),  # both cores': the world and joint motors
    "M": ("n", 8),
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
    "Ad": (6, 6),  # ``com_core``'s
    "V": ("n", 6),
    "A": ("n", 6),
    "W": (6,),
    "tmp": (6,),
    "VJ": (6,),
    "Ic": ("n", 10),  # ``centroidal_core``'s
    "Sw": ("nv", 6),
    "F": ("nv", 6),
}


@core
def com_core(m, q, v, a, out, work):
    """``out = (c, ċ, c̈)`` (3, 3), world frame: the centre of mass, its velocity and its
    (classical) acceleration."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    Mw, M, tmp8, c, s, Ad, V, A, W, tmp, VJ = (k_.Mw, k_.M, k_.tmp8, k_.c, k_.s, k_.Ad, k_.V, k_.A,
                                               k_.W, k_.tmp, k_.VJ)
    world_motors(m, q, c, s, tmp8, M, Mw)
    for i in range(3):
        for k in range(3):
            out[i, k] = 0.0
    mass = 0.0
    for j in range(m.n):
        p = m.parents[j]
        wrench_adjoint(M[j], Ad)
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
                A[j, k] = 0.0  # no gravity: the accelerations of the bodies themselves
        else:
            adjoint_apply_transpose(Ad, V[p], V[j])  # ~M_j V_λ M_j
            adjoint_apply_transpose(Ad, A[p], A[j])
        joint_twist(m, j, v, VJ)
        for k in range(6):
            V[j, k] += VJ[k]  # V_j
        twist_cross(V[j], VJ, tmp)
        joint_twist(m, j, a, VJ)
        for k in range(6):
            A[j, k] += tmp[k] + VJ[k]  # V̇_j, eqs. (10-11)
        inertia_apply(m.inertias[j], V[j], tmp)  # I_j[V_j]: (angular, linear) momentum
        inertia_apply(m.inertias[j], A[j], W)
        twist_cross_wrench(V[j], tmp, VJ)
        for k in range(6):
            W[k] += VJ[k]  # I_j[V̇_j] + V_j × I_j[V_j]: its rate
        r, pw = rigid_frame(Mw[j])
        par = rigid_parameters(m.inertias[j])
        mj = par[0]
        mass += mj
        h = rigid_rotate(r, par[1], par[2], par[3])
        _, _, _, f1, f2, f3 = physical(tmp)  # linear momentum m_j ċ_j, body frame
        _, _, _, g1, g2, g3 = physical(W)  # its rate m_j c̈_j, body frame
        f = rigid_rotate(r, f1, f2, f3)
        g = rigid_rotate(r, g1, g2, g3)
        for i in range(3):
            out[0, i] += mj * pw[i] + h[i]  # m_j c_j = m_j p_j + R_j h_j
            out[1, i] += f[i]
            out[2, i] += g[i]
    for i in range(3):
        for k in range(3):
            out[i, k] /= mass
    return check_result(out)


@core
def centroidal_core(m, q, Ag, com, work):
    """The centroidal momentum matrix ``Ag`` (6, nv), rows linear then angular momentum
    about the centre of mass, world axes; and the centre of mass ``com`` (3)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    Mw, M, tmp8, c, s, Ic, Sw, F = k_.Mw, k_.M, k_.tmp8, k_.c, k_.s, k_.Ic, k_.Sw, k_.F
    local = one_free_tree(m)
    frame_motors(m, q, c, s, tmp8, M, Mw, local)  # the root body's frame, or the world
    for j in range(m.n):
        r, p = rigid_frame(Mw[j])
        for k in range(m.iv[j], m.iv[j + 1]):
            rigid_move_twist(r, p, m.S[k], Sw[k])  # S^w_k = M^w_j S_k ~M^w_j
        rigid_move_inertia(r, p, m.inertias[j], Ic[j])  # M^w_j * I_j, eq. (16)
    mass = h1 = h2 = h3 = 0.0  # mass and first moment of the whole robot
    for k in range(m.nv - 1, -1, -1):  # children come after their parents
        j = m.dof_joint[k]
        f = rigid_apply(Ic[j], Sw[k])  # F_k = I^c_j[S^w_k], I^c_j complete
        for l in range(6):
            F[k, l] = f[l]
        if k == m.iv[j]:  # joint j done
            p = m.parents[j]
            if p >= 0:
                for l in range(10):
                    Ic[p, l] += Ic[j, l]
            else:
                mass, h1, h2, h3 = mass + Ic[j, 0], h1 + Ic[j, 1], h2 + Ic[j, 2], h3 + Ic[j, 3]
    com[0], com[1], com[2] = h1 / mass, h2 / mass, h3 / mass  # c = h / m
    for k in range(m.nv):
        n1, n2, n3, f1, f2, f3 = physical(F[k])
        Ag[0, k], Ag[1, k], Ag[2, k] = f1, f2, f3
        Ag[3, k] = n1 - (com[1] * f3 - com[2] * f2)  # n - c × f
        Ag[4, k] = n2 - (com[2] * f1 - com[0] * f3)
        Ag[5, k] = n3 - (com[0] * f2 - com[1] * f1)
    if local:
        _to_world(M[0], Ag, com)
    status = check_result(com)
    return status if status != OK else check_result(Ag)


@inline
def one_free_tree(m):
    """True when the model is one tree on a free-flyer root (joint 0, the only root): its
    whole momentum can be computed in the root body's frame."""
    for j in range(1, m.n):
        if m.parents[j] < 0:
            return False
    return m.n > 0 and free_root(m.parents[0], m.types[0])


@inline
def _to_world(root, Ag, com):
    """``A_g = diag(R, R) A'_g`` and ``c = R c' + p``, from the root body's frame to the
    world's, ``root = M^w_root = T(p) R``."""
    r, p = rigid_frame(root)
    for k in range(Ag.shape[1]):
        Ag[0, k], Ag[1, k], Ag[2, k] = rigid_rotate(r, Ag[0, k], Ag[1, k], Ag[2, k])
        Ag[3, k], Ag[4, k], Ag[5, k] = rigid_rotate(r, Ag[3, k], Ag[4, k], Ag[5, k])
    x, y, z = rigid_rotate(r, com[0], com[1], com[2])
    com[0], com[1], com[2] = x + p[0], y + p[1], z + p[2]
