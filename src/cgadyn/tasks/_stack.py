"""A weighted stack of tasks in compiled code: all residual rows and Jacobian rows at q.

Forward kinematics once (eq. 5, ``algorithms.kinematics.world_motors``), then every task's
rows (``_rows.task_rows``) one under the other: the residual ``r`` (nr) and its Jacobian
``J`` (nr, nv) in the tangent space of q. Nothing is allocated: the arrays are carved out of
the caller's ``work`` (``stack_workspace_size`` floats).
"""

from __future__ import annotations

import numpy as np

from .._jit import inline, serial
from .._views import carve, data_pointer
from ..algorithms.kinematics import world_motors
from ..multibody.packed import unpack
from ._cooperative import RELATIVE, cooperative, cooperative_rows
from ._rows import DIMS, KIND, task_dim, task_rows

__all__ = ["DIMS", "evaluate", "stack_dim", "stack_rows", "stack_workspace_size"]


@inline
def stack_workspace_size(n, nq, nv):
    return 16 * n + 2 * nq + 8 * 4 + 12 + 6 * nv + 36 + 54 + coop_workspace_size(nv)


@inline
def coop_workspace_size(nv):
    return 8 * 4 + 2 * 6 * nv + 2 * 36


@inline
def stack_workspace(buf, m, o):
    """The scratch of ``stack_rows`` from offset ``o``: the joint motors M, Mw (n, 8), their
    scalars c, s (nq), tmp8, and the rows' work (L, F, E (8), tw, xi (6), Jf (6, nv),
    J6 (6, 6), t (6, 3, 3)), the cooperative rows' (``coop_workspace``); and the next
    offset."""
    M, o = carve(buf, o, (m.n, 8))
    Mw, o = carve(buf, o, (m.n, 8))
    c, o = carve(buf, o, (m.nq,))
    s, o = carve(buf, o, (m.nq,))
    tmp8, o = carve(buf, o, (8,))
    L, o = carve(buf, o, (8,))
    F, o = carve(buf, o, (8,))
    E, o = carve(buf, o, (8,))
    tw, o = carve(buf, o, (6,))
    xi, o = carve(buf, o, (6,))
    Jf, o = carve(buf, o, (6, m.nv))
    J6, o = carve(buf, o, (6, 6))
    t, o = carve(buf, o, (6, 3, 3))
    wk = (L, F, E, tw, xi, Jf, J6, t)
    cw, o = coop_workspace(buf, m, o, wk)
    return (M, Mw, c, s, tmp8, wk, cw), o


@inline
def coop_workspace(buf, m, o, wk):
    """The scratch of the cooperative rows, ``CoopWork`` (L, F1, F2, H, E (8), tw, xi (6),
    J1 (6, nv), K, K2, K3 (6, 6), t (6, 3, 3)), and the outputs Ma, Mr (8), Ja, Jr (6, nv):
    what a one-link task's rows use (``wk``, never at the same time) and F2, H, K2, K3 and
    the outputs carved from offset ``o``."""
    L, F, E, tw, xi, Jf, J6, t = wk
    F2, o = carve(buf, o, (8,))
    H, o = carve(buf, o, (8,))
    K2, o = carve(buf, o, (6, 6))
    K3, o = carve(buf, o, (6, 6))
    Ma, o = carve(buf, o, (8,))
    Mr, o = carve(buf, o, (8,))
    Ja, o = carve(buf, o, (6, m.nv))
    Jr, o = carve(buf, o, (6, m.nv))
    return ((L, F, F2, H, E, tw, xi, Jf, J6, K2, K3, t), Ma, Ja, Mr, Jr), o


@inline
def stack_dim(tasks):
    """The residual rows of a stack of task rows (T, TASK_SIZE)."""
    nr = 0
    for i in range(tasks.shape[0]):
        nr += task_dim(int(tasks[i, KIND]))
    return nr


@inline
def stack_rows(m, q, tasks, r, J, sw):
    """``r`` (nr) and ``J`` (nr, nv) of the stack at q; ``sw`` from ``stack_workspace``."""
    M, Mw, c, s, tmp8, wk, (cw, Ma, Ja, Mr, Jr) = sw
    world_motors(m, q, c, s, tmp8, M, Mw)
    o = 0
    for i in range(tasks.shape[0]):
        kind = int(tasks[i, KIND])
        if kind >= RELATIVE:
            cooperative_rows(m, Mw, tasks[i], kind, r, J, o, cw, Ma, Ja, Mr, Jr)
        else:
            task_rows(m, Mw, tasks[i], r, J, o, wk)
        o += task_dim(kind)


@serial
def cooperative_space(packed, q, task, Ma, Ja, Mr, Jr):
    """The absolute and relative motors and their Jacobians of a cooperative task row's two
    links at q (``_cooperative``, C1-C4), for Python."""
    m = unpack(packed)
    work = np.empty(stack_workspace_size(m.n, m.nq, m.nv))
    sw, _ = stack_workspace(data_pointer(work), m, 0)
    M, Mw, c, s, tmp8, _, (cw, _, _, _, _) = sw
    world_motors(m, q, c, s, tmp8, M, Mw)
    cooperative(m, Mw, task, Ma, Ja, Mr, Jr, cw)


@serial
def evaluate(packed, q, tasks, r, J):
    """``r, J`` of a stack at one configuration (for Python: tests, the task objects)."""
    m = unpack(packed)
    work = np.empty(stack_workspace_size(m.n, m.nq, m.nv))
    sw, _ = stack_workspace(data_pointer(work), m, 0)
    stack_rows(m, q, tasks, r, J, sw)

