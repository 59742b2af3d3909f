"""Inverse kinematics: reach a pose, or put a carried object onto a target primitive.

``inverse_kinematics(model, link, target, q0=None, ...)`` builds one ``Task`` (a 4x4 pose or
a motor: the full pose, ``log6`` of the error; a primitive: the carried object onto it) and
``solve(model, tasks, q0)`` minimises a weighted stack of tasks, both by the compiled
Levenberg-Marquardt of ``_solve`` within the joint limits. A batch of targets ((B, 4, 4)
poses, a batch Motor, or a list) is solved in one compiled call, in parallel over numba's
threads. A target out of reach is no error: ``converged`` is False and ``q`` the best
configuration found, with its residual.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from .._threads import PARALLEL_LOCK
from ..algorithms import _inputs
from ..cga.objects import Geometric, Motor
from ..cga.poses import motors_from_matrices
from . import _rows as R
from ._solve import (
    CONVERGED,
    ITERATIONS,
    LAMBDA0,
    MAX_ITER,
    RESIDUAL,
    RESTARTS,
    RESTARTS_USED,
    SEED,
    TOL,
    solve_batch,
    solve_single,
)
from .task import Task, stack_for

__all__ = ["IKResult", "inverse_kinematics", "middle_configuration", "solve"]


@dataclass(frozen=True)
class IKResult:
    """The solution of inverse kinematics; batch results hold one entry per target.

    q: (nq,) or (B, nq) the best configuration found, within the joint limits.
    converged: whether ``|r| ≤ tol``. residual: the stacked weighted residual at q, (nr,)
    or (B, nr). error: ``|r|``. iterations: Levenberg-Marquardt iterations over all runs.
    restarts: random restarts used."""

    q: np.ndarray
    converged: bool | np.ndarray
    residual: np.ndarray
    error: float | np.ndarray
    iterations: int | np.ndarray
    restarts: int | np.ndarray


DAMPING = 0.1
"""The first λ of Levenberg-Marquardt. On 2048 random panda poses from the middle of the
joint ranges it takes a tenth fewer iterations than λ = 1 (18.7 against 21.0 a target),
with 3 targets unsolved against 2."""


def middle_configuration(model) -> np.ndarray:
    """The middle of every joint's range (0 for unbounded joints; joints that are not
    additive, free flyers, neutral: ``multibody.joints.table.middle``)."""
    from ..multibody.joints.table import middle

    return middle(model)


def _options(max_iter, tol, restarts, seed, damping) -> np.ndarray:
    o = np.zeros(5)
    for name, value, low in [("max_iter", max_iter, 1), ("restarts", restarts, 0),
                             ("seed", seed, 0)]:
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < low:
            raise ValueError(f"{name} must be an integer ≥ {low}, got {value!r}")
    for name, value in [("tol", tol), ("damping", damping)]:
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and positive, got {value!r}")
    o[MAX_ITER], o[TOL], o[RESTARTS], o[SEED], o[LAMBDA0] = max_iter, tol, restarts, seed, \
        damping
    return o


def _start(model, q0, batch: int | None) -> np.ndarray:
    if q0 is None:
        q0 = middle_configuration(model)
    q0 = _inputs.state(model, q0, "q0", model.nq)
    if not np.all(np.isfinite(q0)):
        raise ValueError("q0 holds NaN or inf")
    if batch is None:
        if q0.ndim != 1:
            raise ValueError(f"q0 must be one configuration ({model.nq},) for one target, got "
                             f"{q0.shape}")
        return q0
    if q0.ndim == 1:
        return np.ascontiguousarray(np.broadcast_to(q0, (batch, model.nq)))
    if q0.shape[0] != batch:
        raise ValueError(f"q0 has {q0.shape[0]} configurations for {batch} targets")
    return q0


def _limits(model) -> tuple[np.ndarray, np.ndarray]:
    return np.ascontiguousarray(model.lower), np.ascontiguousarray(model.upper)


def solve(model, tasks: Task | Sequence[Task], q0=None, *, tol: float = 1e-10,
          max_iter: int = 30, restarts: int = 20, damping: float = DAMPING,
          seed: int = 0) -> IKResult:
    """Minimise the weighted stack of ``tasks`` from ``q0`` (default: the middle of the
    joint ranges) within the joint limits: the task-stack form of inverse kinematics."""
    rows = stack_for(model, tasks)
    q0 = _start(model, q0, None)
    options = _options(max_iter, tol, restarts, seed, damping)
    nr = sum(R.DIMS[int(r[R.KIND])] for r in rows)
    q, res, info = np.empty(model.nq), np.empty(nr), np.empty(4)
    lower, upper = _limits(model)
    if solve_single(model.packed, q0, lower, upper, rows, options, q, res, info) != 0:
        raise ValueError("inverse kinematics: the residual is not finite at any configuration "
                         "tried (check the target and q0)")
    return IKResult(q, bool(info[CONVERGED]), res, float(info[RESIDUAL]),
                    int(info[ITERATIONS]), int(info[RESTARTS_USED]))


def _batch_rows(model, link, target, carried, tool, kind) -> np.ndarray | None:
    """The (B, 1, TASK_SIZE) task rows of a batch of targets, or None for one target."""
    if isinstance(target, Geometric):
        return None
    if isinstance(target, Motor):
        if not target.batch_shape:
            return None
        motors = target.normalized().values.reshape(-1, 8)
    elif isinstance(target, (list, tuple)):
        if not target:
            raise ValueError("the batch of targets is empty")
        rows = np.stack([Task(model, link, t, carried=carried, tool=tool, kind=kind).row
                         for t in target])
        if len({int(k) for k in rows[:, R.KIND]}) != 1:
            raise ValueError("every target of a batch must be of the same kind (all poses, "
                             "all planes, ...)")
        return np.ascontiguousarray(rows[:, None])
    else:
        a = np.asarray(target, dtype=float)
        if a.ndim == 3 and a.shape[1:] == (4, 4):
            if a.shape[0] == 0:
                raise ValueError("the batch of targets is empty")
            motors = motors_from_matrices(a)
        elif a.ndim == 2 and a.shape[1] == 8 and a.shape[0] > 0:
            motors = Motor(a).normalized().values
        else:
            return None
    template = Task(model, link, Motor.identity(), carried=carried, tool=tool, kind=kind).row
    rows = np.repeat(template[None, None], len(motors), axis=0)
    rows[:, 0, R.TARGET:R.TARGET + 8] = motors
    return rows


def inverse_kinematics(model, link: str | int, target, q0=None, *, carried=None, tool=None,
                       kind: str | None = None, tol: float = 1e-10, max_iter: int = 30,
                       restarts: int = 20, damping: float = DAMPING, seed: int = 0,
                       threads: int | None = None) -> IKResult:
    """A configuration that brings ``link`` (or its ``tool`` frame, or the object it
    ``carried``) onto ``target``: a 4x4 pose or a Motor (the full pose; ``kind=
    'orientation'`` for the rotation alone), or a Point, Plane, Line, Sphere or Circle (see
    ``Task``). A batch of targets ((B, 4, 4), a batch Motor or a list) is solved in one
    parallel compiled call on ``threads`` threads (default: numba's).

    Levenberg-Marquardt within the joint limits from ``q0`` (default: the middle of the
    joint ranges), at most ``max_iter`` iterations a run and up to ``restarts`` random
    restarts; ``tol`` bounds ``|r|``; ``damping`` is the first λ."""
    rows = _batch_rows(model, link, target, carried, tool, kind)
    if rows is None:
        task = Task(model, link, target, carried=carried, tool=tool, kind=kind)
        return solve(model, task, q0, tol=tol, max_iter=max_iter, restarts=restarts,
                     damping=damping, seed=seed)
    B = rows.shape[0]
    q0 = _start(model, q0, B)
    options = _options(max_iter, tol, restarts, seed, damping)
    threads = numba.get_num_threads() if threads is None else int(threads)
    if threads < 1:
        raise ValueError(f"threads must be at least 1, got {threads}")
    dim = R.DIMS[int(rows[0, 0, R.KIND])]
    q, res, info = np.empty((B, model.nq)), np.empty((B, dim)), np.empty((B, 4))
    lower, upper = _limits(model)
    with PARALLEL_LOCK:
        status = solve_batch(model.packed, q0, lower, upper, rows, options, q, res, info,
                             threads)
    bad = np.flatnonzero(status)
    if bad.size:
        raise ValueError(f"inverse kinematics: the residual is not finite for target "
                         f"{int(bad[0])} at any configuration tried")
    return IKResult(q, info[:, CONVERGED] > 0.5, res, info[:, RESIDUAL].copy(),
                    info[:, ITERATIONS].astype(int), info[:, RESTARTS_USED].astype(int))
