"""The cooperative dual-task space of two end-effectors (Adorno's, in motors): the relative
motor ``M_r = ~F_1 F_2`` and the absolute motor ``M_a = F_1 M_r^½`` of two tool frames and
their body Jacobians (``_cooperative``, C1-C4, compiled).

``CooperativeTask`` asks ``log6(~M_target M)`` of either motor to vanish; it stacks with the
other tasks and ``solve`` minimises the stack in compiled code, within the joint limits and
with restarts (keep the relative pose of the hands while the absolute pose moves).
"""

from __future__ import annotations

import numpy as np

from ..algorithms import _inputs
from ..algorithms.errors import _nonfinite_input
from ..cga.objects import Motor
from . import _rows as R
from ._cooperative import ABSOLUTE, RELATIVE
from ._stack import cooperative_space as _cooperative_space
from .task import Task, as_motor

__all__ = ["CooperativeTask", "cooperative_space"]

_IDENTITY = np.array([1.0, 0, 0, 0, 0, 0, 0, 0])


def _row(model, first, second, which: str, target, weight: float, tools) -> np.ndarray:
    kinds = {"relative": RELATIVE, "absolute": ABSOLUTE}
    if which not in kinds:
        raise ValueError(f"which must be 'absolute' or 'relative', got {which!r}")
    if not (np.isfinite(weight) and weight > 0.0):
        raise ValueError(f"weight must be finite and positive, got {weight}")
    i, j = _inputs.link_index(model, first), _inputs.link_index(model, second)
    if i == j:
        raise ValueError(f"the two links of a cooperative task must differ, got "
                         f"{model.link_names[i]!r} twice")
    if tools is None:
        tools = (None, None)
    if len(tools) != 2:
        raise ValueError(f"tools must be a pair (first, second), got {len(tools)} items")
    row = np.zeros(R.TASK_SIZE)
    row[R.KIND], row[R.LINK], row[R.WEIGHT], row[R.SECOND] = kinds[which], i, weight, j
    for slot, tool, name in [(R.TOOL, tools[0], "first tool"),
                             (R.CARRIED, tools[1], "second tool")]:
        row[slot:slot + 8] = _IDENTITY if tool is None else as_motor(tool, name)
    row[R.TARGET:R.TARGET + 8] = as_motor(target, "target")
    return row


class CooperativeTask(Task):
    """The absolute (``which='absolute'``) or relative motor of two links (or of ``tools``,
    their tool frames in the link frames) onto ``target`` (a Motor or a rigid 4x4 matrix),
    weighted: a task of two links, stacked and solved like any ``Task``."""

    def __init__(self, model, first, second, which: str, target, weight: float = 1.0,
                 tools=None):
        self.row = _row(model, first, second, which, target, weight, tools)
        self.link = int(self.row[R.LINK])
        self.second = int(self.row[R.SECOND])
        self.link_name = model.link_names[self.link]
        self.second_name = model.link_names[self.second]
        self.kind = which
        self.dim = 6
        self.nv = model.nv

    def __repr__(self) -> str:
        return (f"CooperativeTask({self.kind} of {self.link_name!r} and "
                f"{self.second_name!r}, weight {self.row[R.WEIGHT]:g})")


def cooperative_space(model, q, first, second, tools=None
                      ) -> tuple[Motor, np.ndarray, Motor, np.ndarray]:
    """``(M_a, J_a, M_r, J_r)``: the absolute and relative motors of two links (or of their
    ``tools``) at q and their body Jacobians (6, nv), rows ``[v, ω]`` (C1-C4)."""
    row = _row(model, first, second, "relative", Motor.identity(), 1.0, tools)
    q = _inputs.state(model, q, "q", model.nq)
    if q.ndim != 1:
        raise ValueError(f"expected one configuration ({model.nq},), got {q.shape}")
    if not np.all(np.isfinite(q)):  # else the motors' own check blames "Motor"
        raise _nonfinite_input(model, {"q": q})
    Ma, Mr = np.empty(8), np.empty(8)
    Ja, Jr = np.empty((6, model.nv)), np.empty((6, model.nv))
    _cooperative_space(model.packed, np.ascontiguousarray(q), row, Ma, Ja, Mr, Jr)
    return Motor(Ma), Ja, Motor(Mr), Jr
