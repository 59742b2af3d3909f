"""A weighted stack of tasks in compiled code: all residual rows and Jacobian rows at q.

Forward kinematics once (eq. 5, ``algorithms.kinematics.world_motors``), then every task's
rows (``_rows.task_rows``) one under the other: the residual ``r`` (nr) and its Jacobian
``J`` (nr, nv) in the tangent space of q. Nothing is allocated: the arrays are carved out of
the caller's ``work`` (``workspace_size`` floats, ``WORKSPACE``).
"""

from __future__ import annotations

import numpy as np

from .._jit import inline, serial
from .._views import data_pointer
from ..algorithms.kinematics import world_motors
from ..multibody.packed import unpack
from ._cooperative import RELATIVE, cooperative, cooperative_rows
from ._rows import DIMS, KIND, task_dim, task_rows
from .work._stack import workspace, workspace_size

__all__ = ["DIMS", "evaluate", "stack_dim", "stack_rows", "workspace", "workspace_size"]

WORKSPACE = {  # the scratch of ``stack_rows``, in order (tools/generate_workspaces.py)
    "M": ("n", 8),  # the joint motors
    "Mw": ("n", 8),  # the world motors
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
    "tmp8": (8,),
    "L": (8,),  # the rows' work: a link's motor, the tool frame, an error motor
    "F": (8,),
    "E": (8,),
    "tw": (6,),
    "xi": (6,),
    "Jf": (6, "nv"),  # a frame's Jacobian
    "J6": (6, 6),
    "t": (6, 3, 3),
    "F2": (8,),  # the cooperative rows' own (C1-C4): the second tool frame, its
    "H": (8,),  # half-way motor, two 6 x 6 blocks
    "K2": (6, 6),
    "K3": (6, 6),
    "Ma": (8,),  # the absolute and relative motors and their Jacobians
    "Mr": (8,),
    "Ja": (6, "nv"),
    "Jr": (6, "nv"),
}


@inline
def stack_dim(tasks):
    """The residual rows of a stack of task rows (T, TASK_SIZE)."""
    nr = 0
    for i in range(tasks.shape[0]):
        nr += task_dim(int(tasks[i, KIND]))
    return nr


@inline
def stack_rows(m, q, tasks, r, J, sw):
    """``r`` (nr) and ``J`` (nr, nv) of the stack at q; ``sw`` from ``workspace``."""
    M, Mw, c, s, tmp8 = sw.M, sw.Mw, sw.c, sw.s, sw.tmp8
    world_motors(m, q, c, s, tmp8, M, Mw)
    o = 0
    for i in range(tasks.shape[0]):
        kind = int(tasks[i, KIND])
        if kind >= RELATIVE:
            cooperative_rows(m, Mw, tasks[i], kind, r, J, o, sw, sw.Ma, sw.Ja, sw.Mr, sw.Jr)
        else:
            task_rows(m, Mw, tasks[i], r, J, o, sw)
        o += task_dim(kind)


@serial
def cooperative_space(packed, q, task, Ma, Ja, Mr, Jr):
    """The absolute and relative motors and their Jacobians of a cooperative task row's two
    links at q (``_cooperative``, C1-C4), for Python."""
    m = unpack(packed)
    _cooperative_space(m, q, task, Ma, Ja, Mr, Jr, np.empty(workspace_size(m.n, m.nq, m.nv,
                                                                           m.nl)))


@serial
def _cooperative_space(m, q, task, Ma, Ja, Mr, Jr, work):
    """``cooperative_space`` in ``work``, an argument: the bare views carved from it are
    valid while it lives (``_views.data_pointer``)."""
    sw = workspace(data_pointer(work), m)
    world_motors(m, q, sw.c, sw.s, sw.tmp8, sw.M, sw.Mw)
    cooperative(m, sw.Mw, task, Ma, Ja, Mr, Jr, sw)


@serial
def evaluate(packed, q, tasks, r, J):
    """``r, J`` of a stack at one configuration (for Python: tests, the task objects)."""
    m = unpack(packed)
    _evaluate(m, q, tasks, r, J, np.empty(workspace_size(m.n, m.nq, m.nv, m.nl)))


@serial
def _evaluate(m, q, tasks, r, J, work):
    """``evaluate`` in ``work``, an argument (``_cooperative_space``)."""
    stack_rows(m, q, tasks, r, J, workspace(data_pointer(work), m))

