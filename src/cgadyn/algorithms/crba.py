"""Joint-space mass matrix by composite rigid bodies (CRBA), in CGA, in one frame per tree.

The frame is the world's for a fixed base and the root body's own for a free-flyer root
(``kinematics.frame_motors`` with ``free_roots_at_rest``): with the base twist in the base
frame, M does not depend on where the base is, and computed in the world every product
would carry the base's distance from the origin, losing digits as its square (a drone in
UTM coordinates, a robot a kilometre away). Below, "world" means that frame.

Forward pass: the world motor of each body ``M^w_j = M^w_λ M_j`` (``kinematics``); from its
rotation and translation, built once (``rigid_frame``), the columns of the joint's motion
subspace in world coordinates ``S^w_j = M^w_j S_j ~M^w_j`` (eq. 4) and the body's inertia
moved to the world with eq. (16)'s closed form for rigid bodies, kept as its ten
parameters (mass, first moment, rotational inertia). Backward pass (j = n..1): in one
frame the composite inertias are plain sums, ``I^c_λ += I^c_j``, ten numbers each. Once
``I^c_j`` is complete (all its descendants are added), the wrench ``F = I^c_j[S^w_j]``
(eq. 15) of each of the joint's columns is already in the frame of every supporting joint
coordinate i, which reads its entries by the power pairing ``H_ik = H_ki = -S^w_i · F``
(eq. 9): 6 multiplications per pair, where moving F down the path takes 27 more. The
coordinates supporting k are found by walking ``dof_parent`` (Featherstone's expanded
tree, ``multibody.packed``). The pairing is
invariant under motors, so the entries equal those of local frames. The full symmetric
matrix is returned.
"""

from __future__ import annotations

from .._jit import core
from ..kernels import dot
from ..kernels.rigid import rigid_apply, rigid_frame, rigid_move_inertia, rigid_move_twist
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .kinematics import frame_motors
from .status import OK
from .work.crba import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "Ic": ("n", 10),  # ten parameters of the composite rigid inertias
    "Sw": ("nv", 6),  # S_k in the world
    "Mw": ("n", 8),  # the world motors
    "M": ("n", 8),  # the joint motors
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
}


@core
def crba_core(m, q, H, work):
    """One sample into ``H`` (nv, nv); ``work`` ``workspace_size`` floats. Returns a
    status."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    n, iv, parents = m.n, m.iv, m.parents
    k_ = workspace(ws.data_pointer(work), m)
    Ic, Sw, Mw, M, tmp8, c, s = k_.Ic, k_.Sw, k_.Mw, k_.M, k_.tmp8, k_.c, k_.s
    frame_motors(m, q, c, s, tmp8, M, Mw, True)  # M^w_j = M^w_λ X_j M_J(q_j), free roots at rest
    for j in range(n):
        r, p = rigid_frame(Mw[j])  # R and p of M^w_j
        for k in range(iv[j], iv[j + 1]):
            rigid_move_twist(r, p, m.S[k], Sw[k])  # S^w_j = M^w_j S_j ~M^w_j
        rigid_move_inertia(r, p, m.inertias[j], Ic[j])  # M^w_j * I_j, eq. (16)
    for i in range(m.nv):  # entries of joints on different branches stay zero
        for k in range(m.nv):
            H[i, k] = 0.0
    for k in range(m.nv - 1, -1, -1):  # children come after their parents
        j = m.dof_joint[k]
        F = rigid_apply(Ic[j], Sw[k])  # F = I^c_j[S^w_k], I^c_j complete
        i = k
        while i >= 0:  # k itself, then every coordinate supporting it
            H[i, k] = H[k, i] = -dot(Sw[i], F)  # power of F along the axis S^w_i
            i = m.dof_parent[i]
        H[k, k] += m.armature[k]  # the rotor's inertia on the diagonal
        p = parents[j]
        if k == iv[j] and p >= 0:  # joint j done
            for l in range(10):
                Ic[p, l] += Ic[j, l]  # I^c_λ += I^c_j, ten parameters in world coordinates
    return check_result(H)
