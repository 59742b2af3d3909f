"""The configuration manifold: ``q ⊕ v`` and ``q1 ⊖ q0``, joint by joint (``multibody.joints``).

One-dof joints add and subtract their coordinates; a free flyer moves its motor by the
exponential of its body twist and takes the logarithm of the relative motor, as Pinocchio's
``integrate`` and ``difference`` do on SE(3).
"""

from __future__ import annotations

from .._jit import core
from ..multibody.joints import joint_difference, joint_integrate
from . import _workspace as ws
from ._checks import check_configuration, check_result
from .status import OK
from .work.manifold import workspace

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py)
    "tmp": (3, 8),
}


@core
def integrate_core(m, q, v, out, work):
    """``out = q ⊕ v`` (nq)."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    tmp = k_.tmp
    for j in range(m.n):
        joint_integrate(m, j, q, v, tmp, out)
    return check_result(out)


@core
def difference_core(m, q0, q1, out, work):
    """``out = q1 ⊖ q0`` (nv): the velocity that takes q0 to q1 in unit time."""
    status = check_configuration(m, q0)
    if status == OK:
        status = check_configuration(m, q1)
    if status != OK:
        return status
    k_ = workspace(ws.data_pointer(work), m)
    tmp = k_.tmp
    for j in range(m.n):
        joint_difference(m, j, q0, q1, tmp, out)
    return check_result(out)
