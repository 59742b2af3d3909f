"""The configuration manifold: ``q ⊕ v`` and ``q1 ⊖ q0``, joint by joint (``multibody.joints``).

One-dof joints add and subtract their coordinates; a free flyer moves its motor by the
exponential of its body twist and takes the logarithm of the relative motor, as Pinocchio's
``integrate`` and ``difference`` do on SE(3). An Euler step across it takes a free flyer's
(or planar joint's) linear velocity in the frame it starts from and moves the result into
the frame it ends in (``free_velocity``, ``transport``; docs/contact.md, K24).
"""

from __future__ import annotations

import numpy as np

from .._jit import core, inline, serial
from ..multibody.joints import (
    joint_difference,
    joint_frame_rate,
    joint_integrate,
    joint_step,
    joint_transport,
)
from ..multibody.packed import unpack
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


@inline
def free_velocity(m, v, a, h, out):
    """``out = v + h q̈`` (``a``) with, on a joint whose velocity holds a linear part in a
    frame the joint turns (a free flyer, a planar joint), that part's rate in the frame the
    step starts from, ``h ω × v`` (``joint_frame_rate``): an Euler step's velocity, in the
    frames of ``q`` (K24)."""
    for k in range(m.nv):
        out[k] = v[k] + h * a[k]
    if not m.flat:
        for j in range(m.n):
            joint_frame_rate(m, j, v, h, out)


@inline
def transport(m, w, h, x):
    """``x``, a velocity in the frames of ``q``, moved into those of ``q ⊕ h w``
    (``joint_transport``: ``exp(-h ω̂)`` on a free flyer's or planar joint's linear part;
    nothing where every joint adds, K24)."""
    if not m.flat:
        for j in range(m.n):
            joint_transport(m, j, w, h, x)


@serial
def euler_velocity(packed, v, a, h, out):
    """``free_velocity`` of the model packed in ``packed``, for Python (``contact_step``)."""
    free_velocity(unpack(packed), v, a, h, out)


@serial
def euler_transport(packed, w, h, x):
    """``transport`` of the model packed in ``packed``, for Python (``contact_step``)."""
    transport(unpack(packed), w, h, x)


def step_free_velocity(model, v, a, dt: float) -> np.ndarray:
    """``free_velocity`` from Python, a new array: an Euler step's velocity from ``(v, q̈ =
    a)`` in the frames of ``q`` (``contact_step``, the criteria of a trajectory, K24)."""
    out = np.empty(model.nv)
    euler_velocity(model.packed, np.asarray(v, dtype=float), np.asarray(a, dtype=float),
                   float(dt), out)
    return out


@core
def integrate_joints(m, q, v, h, tmp, dq, out):
    """``out = q ⊕ h v`` joint by joint (``joint_integrate``; ``dq`` receives ``h v``),
    compiled once and called: the rollouts' sites and every rollout's specialisation share
    it instead of each carrying every joint type's exponential."""
    for k in range(m.nv):
        dq[k] = h * v[k]
    for j in range(m.n):
        joint_integrate(m, j, q, dq, tmp, out)


@core
def step_joints(m, q, v, h, tmp, dq, out):
    """``integrate_joints`` for an Euler step (``joint_step``: a free flyer's or planar
    joint's origin straight along the world vector of its linear velocity, K24a)."""
    for k in range(m.nv):
        dq[k] = h * v[k]
    for j in range(m.n):
        joint_step(m, j, q, dq, tmp, out)


@serial
def euler_position(packed, q, dq, out):
    """``step_joints`` for Python (``contact_step``): ``out = q`` moved by ``dq``."""
    step_joints(unpack(packed), q, dq, 1.0, np.empty((3, 8)), np.empty(dq.shape[0]), out)


def step_moved_configuration(model, q, dq) -> np.ndarray:
    """``q`` moved by an Euler step's displacement ``dq`` (its velocity times dt), as the
    rollouts move it (``joint_step``, K24a): ``integrate`` but for a free flyer's or planar
    joint's origin, which goes straight along the world vector of its linear part. A new
    array."""
    q = np.asarray(q, dtype=float)
    out = q.copy()
    euler_position(model.packed, q, np.asarray(dq, dtype=float), out)
    return out


def step_moved_velocity(model, v, dt: float) -> np.ndarray:
    """``transport`` from Python, a new array: ``v`` (in the frames of ``q``) moved into
    those of ``q ⊕ dt v``; ``-dt`` moves a velocity of the step's end back into the frames
    of its start (ω, about which the step turned, is unchanged by it, K24)."""
    v = np.asarray(v, dtype=float)
    out = v.copy()
    euler_transport(model.packed, v, float(dt), out)
    return out
