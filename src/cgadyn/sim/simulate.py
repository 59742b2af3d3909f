"""``simulate``: rollouts of a robot's motion from Python, one compiled call for all.

This module checks and shapes the arguments, allocates the results and calls the compiled
loop of ``rollout.py`` once, parallel over rollouts; it then words what stopped a rollout.
"""

from __future__ import annotations

import numbers
import warnings

import numba
import numpy as np

from .. import distributed
from ..algorithms import _inputs
from ..algorithms.api import energy as _energy
from ..algorithms.calls import _PARALLEL
from ..algorithms.status import NONFINITE_RESULT, QUATERNION, SINGULAR, decode
from ..multibody.packed import DEFAULT_GRAVITY
from .controllers import PD, GravityCompensation
from .rollout import EULER, RK4, SEMI_IMPLICIT_EULER, energies, rollouts
from .trajectory import Deferred, Trajectory

INTEGRATORS = {"rk4": RK4, "semi_implicit_euler": SEMI_IMPLICIT_EULER, "euler": EULER}


class SimulationDiverged(RuntimeWarning):
    """A rollout stopped before its last step: its state stopped being finite, or ABA
    found a singular articulated inertia. ``Trajectory.diverged`` says which."""


def simulate(model, q0, v0, dt, steps, tau=None, integrator: str = "rk4", gravity=None,
             f_ext=None, controller=None) -> Trajectory:
    """Integrate ``q̈ = ABA(q, v, τ)`` for ``steps`` steps of ``dt`` seconds.

    ``q0`` (nq,) and ``v0`` (nv,) for one rollout, or (B, nq) / (B, nv) for B (either one
    may be shared by all); ``tau``: None, open-loop torques per step (steps, nv) or per
    rollout (B, steps, nv), held over each step; ``integrator``: ``"rk4"``,
    ``"semi_implicit_euler"`` or ``"euler"`` (on the configuration manifold, see
    ``rollout.py``); ``gravity``: a world-frame 3-vector, default (0, 0, -9.81);
    ``f_ext``: constant external forces as for ``aba``, (n, 6) or (B, n, 6); ``controller``:
    None, ``PD(...)`` or ``GravityCompensation()``, evaluated inside the compiled loop and
    added to ``tau``.

    Returns a ``Trajectory``. A rollout that blows up (a state no longer finite, a singular
    articulated inertia) stops at that step: the ``Trajectory`` holds it up to there, says
    so (``diverged``, ``completed``, ``message``), and a ``SimulationDiverged`` warning is
    issued (turn it into an error with ``warnings.simplefilter("error", SimulationDiverged)``).

    dask arrays of states (``q0``/``v0`` (B, n), ``tau`` (B, steps, nv), chunked along B)
    give a ``Trajectory`` of dask arrays, one compiled call per chunk (``cgadyn.distributed``).
    """
    dt = _positive(dt)
    steps = _steps(steps)
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {', '.join(map(repr, INTEGRATORS))}, "
                         f"got {integrator!r}")
    if any(distributed.is_dask(x) for x in (q0, v0, tau)):  # chunks of rollouts, scheduled by dask
        return distributed.simulate(model, q0, v0, dt, steps, tau, dict(
            integrator=integrator, gravity=gravity, f_ext=f_ext, controller=controller))
    gravity = DEFAULT_GRAVITY if gravity is None else gravity
    packed = _inputs.packed(model, gravity)
    q0 = _inputs.state(model, q0, "q0", model.nq)
    v0 = _inputs.state(model, v0, "v0", model.nv)
    u = _torques(model, tau, steps)
    batch = _batch({"q0": q0, "v0": v0, "tau": u if u.ndim == 3 else None})
    B = batch or 1
    q0 = np.array(np.broadcast_to(q0, (B, model.nq)))  # own copies: one compiled signature
    v0 = np.array(np.broadcast_to(v0, (B, model.nv)))
    _energy(model, q0, v0, gravity)  # finite states, unit quaternions: its ValueError
    u = u.reshape((-1, steps, model.nv))
    f = _inputs.external(model, f_ext, (B,) if batch else ())
    f = np.empty((0, model.njoints, 6)) if f is None else np.array(
        f.reshape(-1, model.njoints, 6))
    flags, gains, q_ref, v_ref = _controller(model, controller, q0, B)

    shape = (B, steps + 1)
    Q, V, A = (np.full(shape + (n,), np.nan) for n in (model.nq, model.nv, model.nv))
    completed = np.zeros(B, dtype=np.int64)
    status = np.zeros(B, dtype=np.int64)
    with _PARALLEL:
        rollouts(packed, INTEGRATORS[integrator], q0, v0, u, f, flags, gains, q_ref, v_ref,
                 dt, Q, V, A, completed, status)
    message = _message(model, status, completed, dt, steps, batch)
    if message:
        warnings.warn(message, SimulationDiverged, stacklevel=2)
    t = dt * np.arange(steps + 1)
    diverged = status != 0
    last = np.where(diverged, completed, steps)  # the last state each rollout reached
    if not batch:
        end = int(last[0]) + 1
        Q, V, A, t = Q[0, :end], V[0, :end], A[0, :end], t[:end]
        completed, diverged = int(completed[0]), bool(diverged[0])
    deferred = Deferred(lambda: _energies(packed, Q, V, last))
    return Trajectory(t=t, q=Q, v=V, a=A, kinetic=deferred, potential=deferred,
                      completed=completed, diverged=diverged,
                      dt=dt, integrator=integrator, message=message)


def _energies(packed, Q, V, last):
    """``(kinetic, potential)`` of the states ``Q``, ``V`` ((B, steps+1, ·), or one
    rollout's (k, ·)) up to each rollout's ``last`` state, NaN after it: one parallel
    compiled call (``rollout.energies``)."""
    Q3, V3 = (np.ascontiguousarray(x.reshape((-1,) + x.shape[-2:])) for x in (Q, V))
    E = np.full(Q3.shape[:2] + (2,), np.nan)
    with _PARALLEL:
        energies(packed, Q3, V3, np.asarray(last, dtype=np.int64), E, numba.get_num_threads())
    E = E.reshape(Q.shape[:-1] + (2,))
    return E[..., 0], E[..., 1]


def _positive(dt) -> float:
    if isinstance(dt, bool) or not isinstance(dt, numbers.Real) or not np.isfinite(dt) \
            or dt <= 0:
        raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
    return float(dt)


def _steps(steps) -> int:
    if isinstance(steps, bool) or not isinstance(steps, numbers.Integral) or steps < 1:
        raise ValueError(f"steps must be a positive integer, got {steps!r}")
    return int(steps)


def _torques(model, tau, steps: int) -> np.ndarray:
    """Open-loop torques as (steps, nv) or (B, steps, nv) float64; zeros for None."""
    nv = model.nv
    if tau is None:
        return np.zeros((steps, nv))
    try:
        u = np.asarray(tau, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"tau must be an array of numbers of shape ({steps}, {nv}) or "
                         f"(B, {steps}, {nv}), got {tau!r}") from None
    if u.ndim not in (2, 3) or u.shape[-2:] != (steps, nv):
        raise ValueError(f"tau must have shape (steps, nv) = ({steps}, {nv}) or (B, {steps}, "
                         f"{nv}) (one torque per step, joints {', '.join(model.joint_names)}),"
                         f" got {u.shape}")
    bad = np.argwhere(~np.isfinite(u))
    if bad.size:
        raise ValueError(f"tau contains NaN or inf at index {tuple(int(i) for i in bad[0])}")
    return u if u.flags.c_contiguous and u.flags.writeable else np.array(u)


def _batch(arrays: dict) -> int:
    """The common number of rollouts B of the batched arrays (0: one rollout)."""
    sizes = {k: a.shape[0] for k, a in arrays.items() if a is not None and a.ndim >= 2}
    if len(set(sizes.values())) > 1:
        detail = ", ".join(f"{k} {arrays[k].shape}" for k in sizes)
        raise ValueError(f"the batched inputs disagree on the number of rollouts: {detail}")
    return next(iter(sizes.values()), 0)


def _controller(model, controller, q0: np.ndarray, B: int):
    """``(flags, gains (2, nv), q_ref (B, nq), v_ref (B, nv))`` for the compiled loop."""
    nq, nv = model.nq, model.nv
    gains = np.zeros((2, nv))
    q_ref, v_ref = q0.copy(), np.zeros((B, nv))
    if controller is None:
        return 0, gains, q_ref, v_ref
    if isinstance(controller, GravityCompensation):
        return controller.flags(), gains, q_ref, v_ref
    if not isinstance(controller, PD):
        raise ValueError(f"controller must be None, cgadyn.PD(...) or "
                         f"cgadyn.GravityCompensation(), got {controller!r}")
    for row, (name, g) in enumerate((("kp", controller.kp), ("kd", controller.kd))):
        if g.shape not in ((), (nv,)):
            raise ValueError(f"PD gain {name} must be a number or have shape ({nv},), "
                             f"got {g.shape}")
        gains[row] = g
    if controller.q_ref is not None:
        ref = _inputs.state(model, controller.q_ref, "q_ref", nq)
        if ref.ndim != 1 or not np.all(np.isfinite(ref)):
            raise ValueError(f"q_ref must be one finite configuration ({nq},), got {ref!r}")
        _energy(model, ref, np.zeros(nv))  # a free flyer's unit quaternion
        q_ref[:] = ref
    if controller.v_ref is not None:
        ref = _inputs.state(model, controller.v_ref, "v_ref", nv)
        if ref.ndim != 1 or not np.all(np.isfinite(ref)):
            raise ValueError(f"v_ref must be one finite velocity ({nv},), got {ref!r}")
        v_ref[:] = ref
    return controller.flags(), gains, q_ref, v_ref


_REASONS = {
    NONFINITE_RESULT: "the state stopped being finite (the step is too large for the "
                      "motion, or the torques too strong)",
    SINGULAR: "a singular articulated-body inertia",
    QUATERNION: "a free flyer's quaternion left unit length",
}


def _message(model, status: np.ndarray, completed: np.ndarray, dt: float, steps: int,
             batch: int) -> str:
    """What stopped the rollouts that stopped ("" if none did)."""
    stopped = np.flatnonzero(status)
    if stopped.size == 0:
        return ""
    first = int(stopped[0])
    code, joint, _ = decode(int(status[first]))
    reason = _REASONS.get(code, f"status {int(status[first])}")
    if joint >= 0:
        reason += f" at joint {model.joint_names[joint]!r}"
    k = int(completed[first])
    where = f"rollout {first} " if batch else ""
    more = f" ({stopped.size} of {batch} rollouts stopped)" if batch else ""
    return (f"simulation of {model.name!r}: {where}stopped after {k} of {steps} steps "
            f"(t = {k * dt:g} s): {reason}; the trajectory holds the states up to "
            f"t = {k * dt:g} s{more}")
