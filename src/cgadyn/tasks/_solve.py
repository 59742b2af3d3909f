"""Inverse kinematics in compiled code: Levenberg-Marquardt on a stack of tasks.

Minimise ``½ |r(q)|²`` (``_stack``: the weighted residuals of the tasks, ``J = ∂r/∂q`` in
the tangent space). Each iteration solves the damped normal equations

    (Jᵀ J + λ 1) δ = -Jᵀ r                                   (Levenberg 1944, Marquardt 1963)

by Cholesky, moves ``q ← clamp(q ⊕ δ)`` (``joints.joint_integrate``, then every coordinate
of an additive joint clamped into its limits) and keeps the step when it lowers the cost: then
``λ ← min(λ / 3, |r|²)``, else ``λ ← 10 λ`` and the step is tried again from the same q.
The cap ``|r|²`` is Yamashita and Fukushima's damping (2001), under which Levenberg-Marquardt
converges quadratically near a zero residual: the last steps are nearly Gauss-Newton ones,
and a run takes fewer iterations than with ``λ / 3`` alone. A run stops
when ``|r| ≤ tol``, after ``max_iter`` iterations, when λ exceeds ``LAMBDA_MAX`` or when it
stalls: its cost, still above ``STALL_FLOOR``, is more than ``STALL_RATIO`` of what it was
``STALL_WINDOW`` accepted steps before (a local minimum or a limit: a stalled run rarely
recovers, and the iterations it would spend there go to a restart instead); it then
restarts from a random configuration within the limits (a
deterministic generator seeded per target; joints that are not additive, a free flyer,
keep their start), at most
``restarts`` times. The best configuration over all runs is returned.

``options = [max_iter, tol, restarts, seed, λ0]``; ``info = [converged, |r|, iterations,
restarts used]``. Nothing is allocated: every array is carved from ``work``
(``workspace_size``, ``WORKSPACE``); the batch entry allocates one ``work`` per chunk of targets.

The rows (``_stack.stack_rows``, ``_rows.task_rows``) and the step are inlined into
``solve_core``: as calls, handing over the model's and the workspace's views cost about as
much as the arithmetic of an iteration. The price is a longer first compile of the solver.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from .._jit import core, inline, parallel, serial
from .._views import data_pointer
from ..algorithms._dense import cholesky, cholesky_substitute
from ..algorithms._workspace import chunks
from ..multibody.joints import is_additive, joint_integrate
from ..multibody.packed import unpack
from ._stack import stack_dim, stack_rows
from .work._solve import workspace, workspace_size
from .work._stack import workspace as stack_workspace

LAMBDA_MAX = 1e10
ACTIVE_PASSES = 4
STALL_WINDOW, STALL_RATIO, STALL_FLOOR = 4, 0.5, 1e-6

WORKSPACE = {  # one target's scratch, in order (tools/generate_workspaces.py); nr: the
    "stack": ("size(_stack)",),  # stack's rows, window: STALL_WINDOW
    "r": ("nr",),  # the residual and its Jacobian at the current q
    "J": ("nr", "nv"),
    "r2": ("nr",),  # and at a trial q
    "J2": ("nr", "nv"),
    "A": ("nv", "nv"),  # the damped normal matrix
    "g": ("nv",),  # the gradient
    "d": ("nv",),  # the step
    "qc": ("nq",),  # the current and trial configurations
    "qt": ("nq",),
    "tmp": (3, 8),
    "free": ("nv",),
    "ring": ("window + 1",),  # the costs of the last accepted steps
}
MAX_ITER, TOL, RESTARTS, SEED, LAMBDA0 = range(5)
CONVERGED, RESIDUAL, ITERATIONS, RESTARTS_USED = range(4)


MINSTD_MODULUS = 2147483647
"""Park and Miller's minimal standard generator ``s ← 48271 s mod (2³¹ - 1)``: products stay
below 2⁴⁷, so the same integers come out compiled and in pure Python."""


@inline
def _first_state(seed, sample):
    """The generator's first state for a target: seed and sample scattered over the whole
    range by a multiplicative hash (Knuth's 2654435761), where ``seed · 1000003 + sample``
    alone started seed 0's first target (every single solve) at state 1, whose first draws
    are near 0: restarts at the lower limits. Every product stays below 2⁶³."""
    x = ((seed % MINSTD_MODULUS) * 1000003 + sample) % (MINSTD_MODULUS - 1) + 1  # never 0
    return x * 2654435761 % MINSTD_MODULUS  # never 0: the modulus is prime, x below it


@inline
def _uniform(state):
    """The next state of the generator and a uniform number in (0, 1)."""
    state = (state * 48271) % MINSTD_MODULUS
    return state, state / MINSTD_MODULUS


@inline
def _clamp(m, lower, upper, q):
    """Every coordinate of an additive joint into its limits."""
    for j in range(m.n):
        if is_additive(m.types[j]):
            for i in range(m.iq[j], m.iq[j + 1]):
                q[i] = min(max(q[i], lower[i]), upper[i])


@inline
def _cost(r):
    acc = 0.0
    for i in range(r.shape[0]):
        acc += r[i] * r[i]
    return acc


@inline
def _cholesky_solve(A, n, b, x):
    """``x = A⁻¹ b`` for the leading n x n block of a symmetric A, by Cholesky in place
    (``algorithms._dense.cholesky``; A's lower triangle overwritten); x may be b. False if
    A is not positive definite."""
    if cholesky(A, n, 0.0) >= 0:
        return False
    for a in range(n):
        x[a] = b[a]
    cholesky_substitute(A, n, x)
    return True


@inline
def _step(m, q, lower, upper, J, r, lam, A, g, d, free):
    """``d = -(Jᵀ J + λ 1)⁻¹ Jᵀ r`` over the free coordinates (the columns of J that
    ``free`` keeps): a coordinate at a limit whose step would leave it is held (an active
    set, ``free[k] = 0``, at most ``ACTIVE_PASSES`` passes). With fewer residual rows than
    coordinates (a redundant arm: 6 rows, 7 or more joints) the same step comes from the
    smaller system ``d = -Jᵀ (J Jᵀ + λ 1)⁻¹ r`` (the push-through identity
    ``(Jᵀ J + λ 1)⁻¹ Jᵀ = Jᵀ (J Jᵀ + λ 1)⁻¹``). ``A`` (nv, nv) and ``g`` (nv)
    are scratch; the smaller system uses their leading part. False if the system is not
    positive definite."""
    nr, nv = J.shape
    for k in range(nv):
        free[k] = 1.0
    for _ in range(ACTIVE_PASSES):
        if nr < nv:
            for a in range(nr):  # J Jᵀ + λ 1 over the free columns
                for b in range(a + 1):
                    acc = 0.0
                    for k in range(nv):
                        acc += J[a, k] * J[b, k] * free[k]
                    A[a, b] = acc
                A[a, a] += lam
                g[a] = -r[a]
            if not _cholesky_solve(A, nr, g, g):  # y = (J Jᵀ + λ 1)⁻¹ (-r), in place
                return False
            for k in range(nv):  # d = Jᵀ y
                acc = 0.0
                for a in range(nr):
                    acc += J[a, k] * g[a]
                d[k] = acc * free[k]
        else:
            for a in range(nv):
                acc = 0.0
                for i in range(nr):
                    acc += J[i, a] * r[i]
                g[a] = -acc * free[a]
                for b in range(a + 1):
                    acc = 0.0
                    for i in range(nr):
                        acc += J[i, a] * J[i, b]
                    A[a, b] = acc * free[a] * free[b]
                A[a, a] += lam if free[a] > 0.0 else 1.0
            if not _cholesky_solve(A, nv, g, d):
                return False
        held = False
        for j in range(m.n):
            if is_additive(m.types[j]):  # q[i] moves by d[k]
                for c in range(m.iv[j + 1] - m.iv[j]):
                    i, k = m.iq[j] + c, m.iv[j] + c
                    if free[k] > 0.0 and ((q[i] <= lower[i] and d[k] < 0.0)
                                          or (q[i] >= upper[i] and d[k] > 0.0)):
                        free[k] = 0.0
                        held = True
        if not held:
            break
    return True


@core
def solve_core(m, q0, lower, upper, tasks, options, sample, q, res, info, work):
    """Levenberg-Marquardt from q0 with restarts (module docstring); the best q into ``q``,
    its residual into ``res``."""
    nr = stack_dim(tasks)
    k_ = workspace(data_pointer(work), m, nr, STALL_WINDOW)
    sw = stack_workspace(data_pointer(k_.stack), m)
    r, J, r2, J2, A, g, d = k_.r, k_.J, k_.r2, k_.J2, k_.A, k_.g, k_.d
    qc, qt, tmp, free, ring = k_.qc, k_.qt, k_.tmp, k_.free, k_.ring
    max_iter, tol, restarts = int(options[MAX_ITER]), options[TOL], int(options[RESTARTS])
    state = _first_state(int(options[SEED]), sample)
    tol2 = tol * tol
    best = np.inf
    for i in range(nr):
        res[i] = np.nan
    iterations = 0
    used = 0
    for attempt in range(restarts + 1):
        used = attempt
        for i in range(m.nq):
            qc[i] = q0[i]
        if attempt > 0:
            for j in range(m.n):
                if is_additive(m.types[j]):
                    for i in range(m.iq[j], m.iq[j + 1]):
                        lo = lower[i] if math.isfinite(lower[i]) else -math.pi
                        hi = upper[i] if math.isfinite(upper[i]) else math.pi
                        state, u = _uniform(state)
                        qc[i] = lo + u * (hi - lo)
        _clamp(m, lower, upper, qc)
        stack_rows(m, qc, tasks, r, J, sw)
        f = _cost(r)
        lam = options[LAMBDA0]
        accepted = 0
        for _ in range(max_iter):
            if not f > tol2:
                break
            iterations += 1
            if _step(m, qc, lower, upper, J, r, lam, A, g, d, free):
                for j in range(m.n):
                    joint_integrate(m, j, qc, d, tmp, qt)
                _clamp(m, lower, upper, qt)
                stack_rows(m, qt, tasks, r2, J2, sw)
                ft = _cost(r2)
            else:
                ft = np.inf
            if ft < f:
                f = ft
                for i in range(m.nq):
                    qc[i] = qt[i]
                r, r2 = r2, r
                J, J2 = J2, J
                lam = max(min(lam / 3.0, f), 1e-12)  # f = |r|²: Yamashita-Fukushima
                ring[accepted % (STALL_WINDOW + 1)] = f
                accepted += 1
                if (accepted > STALL_WINDOW and f > STALL_FLOOR
                        and f > STALL_RATIO * ring[(accepted - 1 - STALL_WINDOW)
                                                   % (STALL_WINDOW + 1)]):
                    break  # stalled
            else:
                lam *= 10.0
                if lam > LAMBDA_MAX:
                    break
        if f < best:  # r holds the rows at qc
            best = f
            for i in range(m.nq):
                q[i] = qc[i]
            for i in range(nr):
                res[i] = r[i]
        if not best > tol2:
            break
    info[CONVERGED] = 1.0 if not best > tol2 else 0.0
    info[RESIDUAL] = math.sqrt(best)
    info[ITERATIONS] = iterations
    info[RESTARTS_USED] = used
    return 0 if math.isfinite(best) else 2


@serial
def solve_single(packed, q0, lower, upper, tasks, options, q, res, info):
    """One target; a status (0, or 2 when no residual was finite)."""
    m = unpack(packed)
    nr = stack_dim(tasks)
    work = np.empty(workspace_size(m.n, m.nq, m.nv, m.nl, nr, STALL_WINDOW))
    # sample 0 as an int64, not a literal: the batch's signature, so solve_core compiles once
    return solve_core(m, q0, lower, upper, tasks, options, np.int64(0), q, res, info, work)


@parallel
def solve_batch(packed, q0, lower, upper, tasks, options, q, res, info, threads):
    """(B,) targets in parallel chunks: ``q0`` (B, nq), ``tasks`` (B, T, TASK_SIZE), ``q``
    (B, nq), ``res`` (B, nr), ``info`` (B, 4); returns a status per target (0 or 2)."""
    batch = tasks.shape[0]
    starts, stops = chunks(batch, threads)
    status = np.zeros(batch, dtype=np.int64)
    for c in prange(starts.shape[0]):
        m = unpack(packed)
        nr = stack_dim(tasks[starts[c]]) if stops[c] > starts[c] else 0
        work = np.empty(workspace_size(m.n, m.nq, m.nv, m.nl, nr, STALL_WINDOW))
        for b in range(starts[c], stops[c]):
            status[b] = solve_core(m, q0[b], lower, upper, tasks[b], options, b, q[b], res[b],
                                   info[b], work)
    return status
