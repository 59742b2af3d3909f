"""Geometric tasks: an object carried by a link, a target object, a residual and its Jacobian.

``Task(model, link, target, carried=None, tool=None, weight=1.0, kind=None)`` picks the task
from the types of the target and of the carried object (``_rows`` states each residual's
geometric meaning):

=======================  =========================  ==================
target                   carried (in the tool frame)  task
=======================  =========================  ==================
Point                    Point (default: the origin)  ``point``
Plane                    Point                        ``plane``
Plane                    Plane                        ``plane_plane``
Line                     Point                        ``line``
Line                     Line                         ``line_line``
Sphere                   Point                        ``sphere``
Circle                   Point                        ``circle``
Motor or 4x4 pose        (the tool frame)             ``pose``; ``kind="orientation"``
=======================  =========================  ==================

``tool`` is the tool frame in the link frame (a Motor or 4x4 matrix). ``evaluate(model, q,
tasks)`` stacks the weighted residuals and Jacobians (nv columns, the tangent space of q).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..algorithms import _inputs
from ..cga.objects import Circle, Geometric, Line, Motor, Plane, Point, Sphere
from ..cga.poses import motors_from_matrices
from . import _rows as R
from ._stack import evaluate as _evaluate
from .primitives import (
    circle_parameters,
    line_parameters,
    plane_parameters,
    point_coordinates,
    sphere_parameters,
)

__all__ = ["Task", "as_motor", "evaluate", "stack", "stack_for"]


def as_motor(x, what: str) -> np.ndarray:
    """Motor coefficients (8,) of a Motor, 8 coefficients or a rigid 4x4 matrix."""
    if isinstance(x, Motor):
        if x.batch_shape:
            raise ValueError(f"{what} must be one motor, got a batch {x.batch_shape}")
        return x.normalized().values.copy()
    a = np.asarray(x, dtype=float)
    if a.shape == (4, 4):
        try:
            return motors_from_matrices(a[None])[0]
        except ValueError as exc:
            raise ValueError(f"{what}: {exc}") from None
    if a.shape == (8,):
        return Motor(a).normalized().values.copy()
    raise ValueError(f"{what} must be a Motor, 8 motor coefficients or a rigid 4x4 matrix, "
                     f"got shape {a.shape}")


def _carried_kind(target, carried) -> int:
    pairs = {(Point, Point): R.POINT, (Plane, Point): R.PLANE, (Plane, Plane): R.PLANE_PLANE,
             (Line, Point): R.LINE, (Line, Line): R.LINE_LINE, (Sphere, Point): R.SPHERE,
             (Circle, Point): R.CIRCLE}
    kind = pairs.get((type(target), type(carried)))
    if kind is None:
        ok = sorted({f"{c.__name__} onto {t.__name__}" for t, c in pairs})
        raise ValueError(f"no task puts a {type(carried).__name__} onto a "
                         f"{type(target).__name__}; the tasks are: {', '.join(ok)} (and a "
                         f"pose: a Motor or a 4x4 matrix)")
    return kind


class Task:
    """One weighted task on a link of a model (module docstring); ``row`` its compiled form."""

    def __init__(self, model, link, target, carried: Geometric | None = None, tool=None,
                 weight: float = 1.0, kind: str | None = None):
        self.link = _inputs.link_index(model, link)
        self.link_name = model.link_names[self.link]
        if not (np.isfinite(weight) and weight > 0.0):
            raise ValueError(f"weight must be finite and positive, got {weight}")
        row = np.zeros(R.TASK_SIZE)
        row[R.TOOL:R.TOOL + 8] = (np.array([1.0, 0, 0, 0, 0, 0, 0, 0]) if tool is None
                                  else as_motor(tool, "tool"))
        a = row[R.CARRIED:R.CARRIED + 8]
        g = row[R.TARGET:R.TARGET + 16]
        if isinstance(target, Geometric):
            if kind is not None:
                raise ValueError(f"kind={kind!r} applies to a pose target, not a "
                                 f"{type(target).__name__}")
            carried = Point([0.0, 0.0, 0.0]) if carried is None else carried
            k = _carried_kind(target, carried)
            if k == R.LINE_LINE:
                b, w = line_parameters(carried)
                a[0:3], a[3:6] = b, w
            elif k == R.PLANE_PLANE:
                a[0:3], a[3] = plane_parameters(carried)
            else:
                a[0:3] = point_coordinates(carried)
            if k == R.POINT:
                g[0:3] = point_coordinates(target)
            elif k in (R.PLANE, R.PLANE_PLANE):
                g[0:3], g[3] = plane_parameters(target)
            elif k in (R.LINE, R.LINE_LINE):
                g[0:3], g[3:6] = line_parameters(target)
            elif k == R.SPHERE:
                g[0:3], g[3] = sphere_parameters(target)
            else:
                g[0:3], g[3:6], g[6] = circle_parameters(target)
        else:
            if carried is not None:
                raise ValueError("a pose target moves the tool frame itself: give no carried "
                                 "object (use tool= to offset the frame)")
            if kind not in (None, "pose", "orientation"):
                raise ValueError(f"kind must be 'pose' or 'orientation' for a pose target, "
                                 f"got {kind!r}")
            k = R.ORIENTATION if kind == "orientation" else R.POSE
            g[0:8] = as_motor(target, "target")
        row[R.KIND], row[R.LINK], row[R.WEIGHT] = k, self.link, weight
        self.kind = R.KIND_NAMES[k]
        self.dim = R.DIMS[k]
        self.row = row
        self.nv = model.nv

    def __repr__(self) -> str:
        return f"Task({self.kind} on {self.link_name!r}, weight {self.row[R.WEIGHT]:g})"


def stack(tasks: Task | Sequence[Task]) -> np.ndarray:
    """The (T, TASK_SIZE) rows of one task or a sequence of them."""
    tasks = [tasks] if isinstance(tasks, Task) else list(tasks)
    if not tasks or not all(isinstance(t, Task) for t in tasks):
        raise ValueError(f"expected a Task or a non-empty sequence of Tasks, got {tasks!r}")
    return np.ascontiguousarray(np.array([t.row for t in tasks]))


def stack_for(model, tasks: Task | Sequence[Task]) -> np.ndarray:
    """``stack(tasks)``, checked against the model the rows will be evaluated on: tasks
    built for another model (other links, other coordinates) are refused."""
    rows = stack(tasks)
    for t in [tasks] if isinstance(tasks, Task) else tasks:
        links = [t.link, t.second] if hasattr(t, "second") else [t.link]
        if t.nv != model.nv or max(links) >= model.nlinks:
            raise ValueError(f"{t!r} was built for another model (this one has "
                             f"{model.nlinks} links and nv = {model.nv})")
    return rows


def evaluate(model, q, tasks) -> tuple[np.ndarray, np.ndarray]:
    """The stacked weighted residual (nr,) and its Jacobian (nr, nv) at one configuration."""
    rows = stack_for(model, tasks)
    q = _inputs.state(model, q, "q", model.nq)
    if q.ndim != 1:
        raise ValueError(f"evaluate takes one configuration (nq,), got shape {q.shape}")
    nr = sum(R.DIMS[int(r[R.KIND])] for r in rows)
    r, J = np.empty(nr), np.empty((nr, model.nv))
    _evaluate(model.packed, np.ascontiguousarray(q), rows, r, J)
    return r, J
