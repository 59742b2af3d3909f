"""Kinetic and potential energy of a robot.

Kinetic: ``T = ½ Σ_j p(V_j, I_j[V_j]) = -½ Σ_j V_j · I_j[V_j]`` (eqs. 9 and 15), with the
body twists ``V_j = ~M_j V_λ M_j + S_j q̇_j`` of the forward pass of Algorithm 2. Potential:
``U = -Σ_j m_j g · c_j``, with ``m_j c_j = m_j p_j + R_j h_j`` the body's first moment in
the world (h_j its first moment in its own frame, ``M^w_j = T(p_j) R_j``), as in Pinocchio.
Gravity is read from the model's base acceleration ``V̇_0 = -g``.
"""

from __future__ import annotations

from .._jit import core
from ..kernels import dot, inertia_apply, twist_sandwich_rev
from ..kernels.layout import physical
from ..kernels.rigid import rigid_frame, rigid_parameters, rigid_rotate
from ..multibody.joints import joint_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import world_motors
from .status import OK
from .work.energy import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Mw": ("n", 8),  # the world motors
    "V": ("n", 6),  # the bodies' twists
    "tmp": (6,),
    "VJ": (6,),
    "M": ("n", 8),  # the joint motors
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


@core
def energy_core(m, q, v, out, work):
    """``out = (T, U)`` of one sample."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    Mw, V, tmp, VJ, M, tmp8, c, s = k_.Mw, k_.V, k_.tmp, k_.VJ, k_.M, k_.tmp8, k_.c, k_.s
    _, _, _, g1, g2, g3 = physical(m.gravity)  # -g, the base acceleration's linear part
    kinetic = 0.0
    potential = 0.0
    world_motors(m, q, c, s, tmp8, M, Mw)  # M_j and M^w_j = M^w_λ M_j
    for j in range(m.n):
        p = m.parents[j]
        if p < 0:
            for k in range(6):
                V[j, k] = 0.0
        else:
            twist_sandwich_rev(M[j], V[p], V[j])  # ~M_j V_λ M_j
        joint_twist(m, j, v, VJ)
        for k in range(6):
            V[j, k] += VJ[k]  # V_j = ~M_j V_λ M_j + S_j q̇_j
        inertia_apply(m.inertias[j], V[j], tmp)
        kinetic -= 0.5 * dot(V[j], tmp)  # ½ p(V_j, I_j[V_j]) = -½ V_j · I_j[V_j]
        r, pw = rigid_frame(Mw[j])
        par = rigid_parameters(m.inertias[j])  # (m_j, h_j, ...)
        mass, h0, h1, h2 = par[0], par[1], par[2], par[3]
        h0, h1, h2 = rigid_rotate(r, h0, h1, h2)
        c0, c1, c2 = mass * pw[0] + h0, mass * pw[1] + h1, mass * pw[2] + h2  # m_j p_j + R_j h_j
        potential += g1 * c0 + g2 * c1 + g3 * c2  # -m_j g · c_j
    out[0] = kinetic
    out[1] = potential
    return check_result(out)
