"""``simulate``: rollouts of a robot's motion from Python, one compiled call for all.

This module checks and shapes the arguments, allocates the results and calls the compiled
loop of ``rollout.py`` once, parallel over rollouts; it then words what stopped a rollout.
"""

from __future__ import annotations

import numbers
import os
import warnings

import numba
import numpy as np

from .. import _arrays
from .._threads import PARALLEL_LOCK
from ..algorithms import _inputs
from ..algorithms.actuators import (
    activations,
    actuator_springs,
    control_torques,
    dynamic,
    state_dependent,
)
from ..algorithms.api import energy as _energy
from ..algorithms.api import link_placements
from ..algorithms.configuration import neutral
from ..algorithms.status import (
    CONSTRAINTS_CONFLICT,
    CONTACT_PAIR,
    CONTACT_UNSOLVED,
    DELASSUS_SINGULAR,
    DIVERGED,
    NONFINITE_RESULT,
    QUATERNION,
    SINGULAR,
    decode,
)
from ..constraints.model import pack
from ..constraints.operators import checked_settings
from ..contact.static_world import default_world
from ..multibody.joints.table import spring_deflection
from ..multibody.packed import DEFAULT_GRAVITY, with_armature
from . import pages
from .bodies import robot_and_bodies
from .contact import (
    COUPLING_TORQUE,
    FRICTION_TORQUE,
    JOINT_TORQUES,
    KEPT,
    LIMIT_TORQUE,
    REPORT,
    slots,
    world_arrays,
)
from .controllers import PD, GravityCompensation, actuated_gains
from .criteria import ContactScene
from .rollout import (
    ACTUATED,
    COORDS,
    DAMPING,
    EULER,
    IMPLICIT,
    KD,
    KP,
    PASSIVE,
    RK4,
    SEMI_IMPLICIT_EULER,
    SHIFT,
    SPEED_BOUND,
    SPRING,
    STIFFNESS,
    TENDON,
    energies,
    kept_row,
    kept_rows,
    rollouts,
    stop_row,
)
from .rollout import PD as PD_FLAG
from .trajectory import Deferred, Trajectory

INTEGRATORS = {"rk4": RK4, "semi_implicit_euler": SEMI_IMPLICIT_EULER, "euler": EULER}


class SimulationDiverged(RuntimeWarning):
    """A rollout stopped before its last step: its state diverged (a speed past what one step
    resolves, or no longer finite), or ABA found a singular articulated inertia.
    ``Trajectory.diverged`` says which rollouts, ``Trajectory.message`` why."""


MEMORY_SHARE = 0.8
"""The share of the memory available that the states of one ``simulate`` call may take."""
CHECKED_FROM = 1 << 24
"""Bytes of kept states from which ``_fits`` asks the system what memory is available
(reading ``/proc/meminfo``, a file, at each call); a run that needs less always fits where
Python runs at all, and the controller that calls ``simulate`` at every period for a short
horizon does not pay for the question."""


def simulate(model, q0, v0, dt, steps, tau=None, integrator: str = "rk4", gravity=None,
             f_ext=None, controller=None, record_every: int = 1,
             final_only: bool = False, passive: bool = True, ctrl=None, constraints=None,
             damping: float = 0.0, world=None, collisions=None,
             contact=None, joint_limits: bool | None = None,
             friction_loss: bool | None = None, couplings: bool | None = None,
             act=None) -> Trajectory:
    """Integrate ``q̈ = ABA(q, v, τ)``, or the constrained dynamics of ``constraints``, for
    ``steps`` steps of ``dt`` seconds.

    ``q0`` (nq,) and ``v0`` (nv,) for one rollout, or (B, nq) / (B, nv) for B (either one
    may be shared by all); ``tau``: None, open-loop torques per step (steps, nv) or per
    rollout (B, steps, nv), held over each step; ``integrator``: ``"rk4"``,
    ``"semi_implicit_euler"`` or ``"euler"`` (on the configuration manifold, see
    ``rollout.py``); ``gravity``: a world-frame 3-vector, default (0, 0, -9.81);
    ``f_ext``: constant external forces as for ``aba``, (n, 6) or (B, n, 6); ``controller``:
    None, ``PD(...)`` or ``GravityCompensation()``, evaluated inside the compiled loop and
    added to ``tau`` on the actuated coordinates (a free flyer is never pushed by a
    controller: ``Model.actuated``); ``record_every``: keep every k-th state (0, k, 2k, ...)
    and the last, so that a long run needs memory for those alone; ``final_only``: keep the
    last state only; ``passive``: add the joints' damping and spring torques
    (``cgadyn.passive_torques``, ``Model.damping``, ``Model.stiffness``) at every stage,
    as MuJoCo does (``False``: the rigid-body dynamics alone); ``ctrl``: None, or controls
    per step for the model's actuators (``Model.actuators``), (steps, na) or (B, steps,
    na), held over each step: their torques (``cgadyn.actuator_torques``, MuJoCo's
    clamping; a position or velocity servo's at each stage's state) are added to ``tau``,
    so that a Gymnasium policy's actions drive the rollout unchanged; an actuator with
    activation dynamics (``Model.actuator_dynamics``: dm_control's quadruped's filters)
    takes its activation instead, stepped by A2 from ``act`` ((na,) or (B, na); zeros by
    default) and held over each step (``Trajectory.activation``);
    ``constraints``: None, or a list of ``cgadyn.Constraint`` of this model (loop closures,
    feet held, ``cgadyn.mujoco_constraints`` of an MJCF's equalities): every stage's q̈ then
    solves ``M q̈ = τ - h + Jᵀ λ``, ``J q̈ = -γ`` (``cgadyn.constrained_dynamics``, C6), γ
    with each constraint's Baumgarte ``corrector`` (C5), which pulls the drift of the
    integration back (``docs/constraints.md``, "Rollouts"); ``damping``: as in
    ``constrained_dynamics`` (0: a direct solve, a singular set stops the rollout; > 0:
    proximal iterations, the least-norm forces of a redundant set). ``world``: None, or a
    ``cgadyn.World`` whose ground and obstacles the shapes of ``collisions``
    (``cgadyn.collision_model``) touch (None with the collisions of an MJCF whose world
    body holds geoms: the world of those, its floor and static geoms,
    ``contact.static_world``; a World given replaces them): every step is then
    ``cgadyn.contact_step``'s (semi-implicit Euler with contact impulses; docs/contact.md,
    "Rollouts with contact"; a PD's gains and the joints' dampers and springs taken at
    the end of the step, K40), with the margin, stabilization, solvers, tolerance, warm
    start and ``accept`` of ``contact`` (a ``cgadyn.ContactSettings``, default
    ``ContactSettings()``); a step whose solvers end with a residual above ``accept``
    stops the rollout, naming the residuals.
    ``joint_limits``: with a world (the default there, None), the limits of the joints of
    one coordinate (``Model.lower``, ``Model.upper``), and the ropes' bounds (``Model.rope_*``,
    K46), are unilateral constraints of the same step (docs/contact.md, "Joint limits",
    K26); ``False`` turns them off. Without a world
    no limit is enforced (``True`` then raises ``ValueError``); ``World(ground=False)``
    with ``collisions=None`` enforces the limits alone. ``friction_loss``: the same for the
    joints' dry friction (``Model.friction``, box-bounded rows, K30). ``couplings``: with a
    world (the default there), the model's couplings (``Model.coupling_names``: an MJCF's
    joint and tendon equalities) are unbounded rows of the same step (K45); ``False``
    leaves them out. Without a world a model with couplings is refused unless
    ``couplings=False``: ``World(ground=False)`` holds them alone.

    Returns a ``Trajectory`` of the states kept. A rollout that diverges (a joint turning
    more than half a turn in one step, a slide moving further than the robot is large, a
    state no longer finite) or meets a singular articulated inertia stops at that step: the
    ``Trajectory`` holds it up to there, says so (``diverged``, ``completed``, ``message``:
    the step, the rollout, the quantity), and a ``SimulationDiverged`` warning is issued
    (turn it into an error with ``warnings.simplefilter("error", SimulationDiverged)``).
    A constrained rollout stops the same way, with its reason, where the constraints become
    singular (a loop through a singular pose, with ``damping`` 0) or have no solution.
    With constraints, the ``Trajectory`` also holds ``constraint_violation`` (the position
    and velocity error of each constraint at each state kept) and ``forces`` (λ). With a
    world, ``contact_count``, ``contact_forces``, ``contact_iterations``,
    ``contact_residual``, ``limit_torques``, ``friction_torques`` and ``coupling_torques``
    (``Trajectory``).
    A run whose states would not fit in the memory available is refused before it starts,
    with what to reduce.

    dask arrays of states (``q0``/``v0`` (B, n), ``tau`` (B, steps, nv), chunked along B)
    give a ``Trajectory`` of dask arrays, one compiled call per chunk (``cgadyn.distributed``).
    """
    dt = _inputs.time_step(dt)
    steps = _steps(steps)
    servos = activation = None
    if act is not None and (ctrl is None or not np.any(dynamic(model))):
        raise ValueError(f"simulate: act is the start of the activations of actuators with "
                         f"activation dynamics, driven by ctrl; {model.name!r} has none"
                         if ctrl is not None else "simulate: act needs ctrl (the controls "
                         "that drive the activations)")
    if ctrl is not None:  # the controls' torques, added to tau up front; a servo's spring
        if np.any(dynamic(model)):  # the force of step n takes w_n (A2): known up front
            activation = activations(model, ctrl, dt, act)
        u_ctrl = control_torques(model, ctrl, None if activation is None
                                 else activation[..., :-1, :])  # A1; the springs: tendons
        servos = actuator_springs(model) if np.any(state_dependent(model)) else None
        if u_ctrl.ndim not in (2, 3) or u_ctrl.shape[-2] != steps:
            raise ValueError(f"ctrl must have shape (steps, na) = ({steps}, "
                             f"{len(model.actuator_names)}) or (B, steps, na), got "
                             f"{np.shape(ctrl)}")
        tau = u_ctrl if tau is None else np.asarray(tau, dtype=float) + u_ctrl
    if world is None:  # an MJCF's own floor and geoms (K44), where collisions hold them
        world = default_world(collisions)
    model, collisions, q0, v0, tau, f_ext, controller, robot_joints = robot_and_bodies(
        model, world, collisions, q0, v0, tau, f_ext, controller)  # the bodies: links
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {', '.join(map(repr, INTEGRATORS))}, "
                         f"got {integrator!r}")
    every = _every(record_every, final_only, steps)
    shapes = _contact_world(model, world, collisions, integrator)
    contact = _contact_settings(contact, world)
    for name, flag in (("joint_limits", joint_limits), ("friction_loss", friction_loss),
                       ("couplings", couplings)):
        if flag is not None and not isinstance(flag, bool):
            raise ValueError(f"simulate: {name} must be True, False or None, got {flag!r}")
        if flag and world is None:
            raise ValueError(f"simulate: {name}=True needs a world (they are constraints of "
                             f"the contact step); pass world=cgadyn.World() or "
                             f"World(ground=False) for the joints alone")
    if world is None and model.coupling_names and couplings is not False:
        raise ValueError(f"simulate: {model.name!r} has the couplings "
                         f"{', '.join(map(repr, model.coupling_names))}, which the contact "
                         f"step holds (docs/contact.md, K45); pass a world "
                         f"(world=cgadyn.World(ground=False) for the couplings alone, with "
                         f"integrator='semi_implicit_euler'), or couplings=False to leave "
                         f"them out")
    p = pack(model, () if constraints is None else constraints)  # checked: type, model
    settings = checked_settings(damping, None, 1e-12)
    server = _arrays.server((q0, v0, tau))
    if server is not None and (p.nr or world is not None or servos is not None
                               or activation is not None):
        raise ValueError("simulate with constraints, a world, servo actuators or actuators "
                         "with activation dynamics takes numpy states; dask arrays of states "
                         "are not supported with them yet")
    if server is not None:  # dask arrays: chunks of rollouts, scheduled by dask
        return server.simulate(model, q0, v0, dt, steps, tau, dict(
            integrator=integrator, gravity=gravity, f_ext=f_ext, controller=controller,
            record_every=record_every, final_only=final_only, passive=passive))
    gravity = DEFAULT_GRAVITY if gravity is None else gravity
    packed = _inputs.packed(model, gravity)
    q0 = _inputs.state(model, q0, "q0", model.nq)
    v0 = _inputs.state(model, v0, "v0", model.nv)
    u = _torques(model, tau, steps)
    batch = _batch({"q0": q0, "v0": v0, "tau": u if u.ndim == 3 else None})
    B = batch or 1
    rows = kept_rows(steps, every)
    arrays = None if world is None else world_arrays(
        model, shapes, world, contact, joint_limits is not False, friction_loss is not False,
        robot_joints, couplings is not False)
    # the contact slots: each shape's, then each pair's (sim.pairs)
    K = 0 if world is None else slots(len(shapes) + (0 if arrays.pairs is None
                                                     else len(arrays.pairs)))
    _fits(model, B, steps, rows, p.nr, None if world is None else K)
    q0 = np.array(np.broadcast_to(q0, (B, model.nq)), order="C")  # own copies, C order:
    v0 = np.array(np.broadcast_to(v0, (B, model.nv)), order="C")  # one compiled signature
    _energy(model, q0, v0, gravity)  # finite states, unit quaternions: its ValueError
    u = u.reshape((-1, u.shape[-2], model.nv))
    f = _inputs.external(model, f_ext, (B,) if batch else ())
    f = np.empty((0, model.njoints, 6)) if f is None else np.array(
        f.reshape(-1, model.njoints, 6))
    coords = np.zeros((COORDS, model.nv))
    coords[SPEED_BOUND] = speed_bounds(model, dt)
    coords[ACTUATED] = model.actuated
    flags, q_ref, v_ref = _controller(model, controller, q0, B, coords)
    tendons = np.zeros((0, model.nv + TENDON))
    if passive and (np.any(model.damping) or np.any(model.stiffness)
                    or np.any(model.tendon_stiffness) or np.any(model.tendon_damping)):
        flags |= _passive(model, coords)
        tendons = _tendons(model)
    if servos is not None:  # evaluated as the passive tendons are, passive or not
        flags |= PASSIVE
        tendons = np.concatenate([tendons, _servo_rows(servos, model.nv)])
    step_model, step_inertia = packed, None
    if world is not None and flags & (PD_FLAG | PASSIVE):  # the contact step's gains implicit
        step_model, step_inertia = _implicit(packed, coords, dt)
        flags |= IMPLICIT

    shape = (B, rows)
    # unwritten: each rollout writes its own rows (states, or NaN) in the compiled loop
    Q, V, A = (np.empty(shape + (n,)) for n in (model.nq, model.nv, model.nv))
    X = np.empty(shape + (3, p.nr))
    completed = np.zeros(B, dtype=np.int64)
    status = np.zeros(B, dtype=np.int64)
    # without rows None: the loop compiled without the constraint core (rollout._dynamics)
    cons, solve = (np.array(p.array, dtype=float), settings) if p.nr else (None, None)
    CF = np.empty(shape + (KEPT if world is not None else 0,))
    # the slots' forces and the joints' limit and friction torques, slot- and coordinate-
    # major and zeros: pages no contact writes are never touched (rollout._keep_contacts,
    # sim/pages.py)
    CS = pages.zeros((B, K if world is not None else 0, rows, 3))
    CT = pages.zeros((B, JOINT_TORQUES, model.nv if world is not None else 0, rows))
    CR = np.full((B, REPORT), np.nan)
    with PARALLEL_LOCK:
        rollouts(step_model, INTEGRATORS[integrator], q0, v0, u, f, flags, coords, tendons,
                 q_ref, v_ref, cons, solve, arrays, dt, steps, every, Q, V, A, X, CF, CS, CT,
                 CR, completed, status)
    pairs = None if arrays is None or arrays.pairs is None else \
        [(shapes[i].name, shapes[j].name) for i, j in arrays.pairs]
    message = _message(model, status, completed, dt, steps, batch, coords, A, p, CR, pairs)
    if message:
        warnings.warn(message, SimulationDiverged, stacklevel=2)
    t = _times(dt, steps, every, rows)
    diverged = status != 0
    last = np.array([_last_row(int(c), steps, every) if d else rows - 1
                     for c, d in zip(completed, diverged, strict=True)], dtype=np.int64)
    count = forces = iterations = residual = limit = friction = coupling = None
    if world is not None:
        count = np.where(np.isnan(CF[..., 0]), -1, CF[..., 0]).astype(np.int64)
        iterations = np.where(np.isnan(CF[..., 1]), -1, CF[..., 1]).astype(np.int64)
        residual = CF[..., 2].copy()
        forces = CS.transpose(0, 2, 1, 3)  # (B, rows, K, 3), a view
        limit, friction, coupling = (CT[:, i].transpose(0, 2, 1) for i in
                                     (LIMIT_TORQUE, FRICTION_TORQUE, COUPLING_TORQUE))
    if not batch:
        end = int(last[0]) + 1
        Q, V, A, X, t = Q[0, :end], V[0, :end], A[0, :end], X[0, :end], t[:end].copy()
        if world is not None:
            count, forces = count[0, :end], forces[0, :end]
            iterations, residual = iterations[0, :end], residual[0, :end]
            limit, friction, coupling = limit[0, :end], friction[0, :end], coupling[0, :end]
        completed, diverged = int(completed[0]), bool(diverged[0])
        if diverged:
            t[-1] = completed * dt  # the last state it reached
    deferred = Deferred(lambda: _energies(packed, Q, V, last))
    if activation is not None:
        activation = _kept_activation(activation, B, steps, every, rows, completed,
                                      diverged, batch)
    return Trajectory(t=t, q=Q, v=V, a=A, kinetic=deferred, potential=deferred,
                      completed=completed, diverged=diverged,
                      dt=dt, integrator=integrator, message=message,
                      constraint_violation=_violation(X, p.starts), forces=X[..., 2, :],
                      contact_count=count, contact_forces=forces,
                      contact_iterations=iterations, contact_residual=residual,
                      limit_torques=limit, friction_torques=friction,
                      coupling_torques=coupling,
                      scene=None if world is None else ContactScene(
                          model, shapes, world, contact, step_inertia,
                          robot_joints), activation=activation)


def _contact_settings(contact, world):
    """``contact`` checked: a ``ContactSettings`` (None: the defaults), only with a world."""
    from ..contact.inputs import checked_settings

    if contact is not None and world is None:
        raise ValueError("simulate: contact settings given without a world; pass "
                         "world=cgadyn.World() for the ground they touch")
    return checked_settings(contact, "simulate")


def _contact_world(model, world, collisions, integrator: str):
    """The collision model of a rollout with ``world`` (None without), checked: a world
    needs semi-implicit Euler and ``collisions`` unless it has no ground."""
    from ..contact.inputs import checked_collisions, checked_world

    if world is None:
        if collisions is not None:
            raise ValueError("simulate: collisions given without a world; pass "
                             "world=cgadyn.World() for the ground they touch")
        return None
    world = checked_world(world, "simulate")
    if integrator != "semi_implicit_euler":
        raise ValueError(f"simulate: contact with a world steps with "
                         f"integrator='semi_implicit_euler' (the contact step, K24), got "
                         f"integrator={integrator!r}")
    return checked_collisions(model, collisions, world, "simulate")


def _violation(X: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """(..., rows, nc, 2): the norms of each constraint's position error (C5's e) and
    velocity error ``J v`` from the rows the loop kept ``X`` (..., rows, 3, nr)."""
    out = np.empty(X.shape[:-2] + (len(starts) - 1, 2))
    for c in range(len(starts) - 1):
        rows = X[..., :2, starts[c]:starts[c + 1]]
        out[..., c, :] = np.sqrt(np.sum(rows * rows, axis=-1))
    return out


def _energies(packed, Q, V, last):
    """``(kinetic, potential)`` of the states kept ``Q``, ``V`` ((B, rows, ·), or one
    rollout's (k, ·)) up to each rollout's ``last`` row, NaN after it: one parallel
    compiled call (``rollout.energies``)."""
    Q3, V3 = (np.ascontiguousarray(x.reshape((-1,) + x.shape[-2:])) for x in (Q, V))
    E = np.full(Q3.shape[:2] + (2,), np.nan)
    with PARALLEL_LOCK:
        energies(packed, Q3, V3, np.asarray(last, dtype=np.int64), E, numba.get_num_threads())
    E = E.reshape(Q.shape[:-1] + (2,))
    return E[..., 0], E[..., 1]


def _every(record_every, final_only, steps: int) -> int:
    """The compiled loop's ``every`` (``rollout.kept_row``): 0 for ``final_only``."""
    if not isinstance(final_only, bool | np.bool_):
        raise ValueError(f"final_only must be True or False, got {final_only!r}")
    if isinstance(record_every, bool) or not isinstance(record_every, numbers.Integral) \
            or record_every < 1:
        raise ValueError(f"record_every must be a positive integer (keep every k-th state), "
                         f"got {record_every!r}")
    return 0 if final_only else int(min(record_every, steps))


def _kept_activation(w: np.ndarray, B: int, steps: int, every: int, rows: int,
                     completed, diverged, batch) -> np.ndarray:
    """The activations (A2) of the states kept, from all of them ``w`` (..., steps + 1,
    na): the rows of ``kept_row``, a stopped rollout's last state at its step and NaN
    after it, as the states' arrays hold them."""
    w = np.broadcast_to(w, (B,) + w.shape[-2:])
    index = np.array([steps]) if every == 0 else np.arange(0, steps + 1, every)
    if index[-1] != steps:  # the last state, kept after the grid's (``kept_row``)
        index = np.append(index, steps)
    out = w[:, index].copy()
    done = np.atleast_1d(completed)
    for b in np.flatnonzero(np.atleast_1d(diverged)):
        r = _last_row(int(done[b]), steps, every)
        out[b, r] = w[b, int(done[b])]
        out[b, r + 1:] = np.nan
    if not batch:
        end = _last_row(int(done[0]), steps, every) + 1 if np.atleast_1d(diverged)[0] \
            else rows
        return out[0, :end]
    return out


def _times(dt: float, steps: int, every: int, rows: int) -> np.ndarray:
    """The time of each row kept (``rollout.kept_row``): ``every`` steps apart, the last at
    ``steps dt``."""
    if every == 0:
        return np.array([steps * dt])
    t = dt * every * np.arange(rows)
    t[-1] = steps * dt
    return t


def _last_row(done: int, steps: int, every: int) -> int:
    """The row holding the last state a stopped rollout reached (``rollout.rollouts``)."""
    r = getattr(kept_row, "py_func", kept_row)(done, steps, every)  # plain under NUMBA_DISABLE_JIT
    return r if r >= 0 else getattr(stop_row, "py_func", stop_row)(done, every)


def available_memory() -> int:
    """Bytes of memory available to a new allocation (Linux's ``MemAvailable``; the free
    physical pages elsewhere)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def _fits(model, B: int, steps: int, rows: int, nr: int = 0, slots: int | None = None) -> None:
    """Refuse, before anything is allocated, a run whose kept states (q, v, q̈, the two
    energies, the ``nr`` constraint rows' errors and forces and, with a world (``slots``
    not None), the contacts' count, iterations and residual, the forces of its ``slots``
    and the joint limits' and friction losses' torques of each) would take more than
    ``MEMORY_SHARE`` of the memory available."""
    world = 0 if slots is None else KEPT + 3 * slots + 2 * model.nv + 3
    per_row = 8 * (model.nq + 2 * model.nv + 2 + 3 * nr + 2 * nr + world)
    need = B * rows * per_row
    if need < CHECKED_FROM:
        return
    have = int(MEMORY_SHARE * available_memory())
    if need <= have:
        return
    fit = have // (B * per_row)  # rows that fit; kept_rows(steps, k) <= steps / k + 2
    every = -(-steps // (fit - 2)) if fit >= 3 else 0
    fix = (f"record_every={every} (keep every {every}-th state)" if every
           else "fewer rollouts")
    raise ValueError(f"simulate: {B} rollout(s) of {rows} kept states of {model.name!r} need "
                     f"{_size(need)}, more than the {_size(have)} of memory available; "
                     f"reduce the steps or the rollouts, keep fewer states with {fix}, or "
                     f"only the last with final_only=True")


def _size(n: float) -> str:
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n < 1024 or unit == "PiB":
            return f"{n:.1f} {unit}" if unit != "bytes" else f"{int(n)} bytes"
        n /= 1024
    return ""


def speed_bounds(model, dt: float) -> np.ndarray:
    """(nv,) the speed past which a rollout has diverged, by what each velocity coordinate
    is (``Model.coordinate_speeds``): an angle turning more than half a turn in one step
    (π / dt), a slide moving further in one step than the robot is large (its links'
    extent in the neutral configuration plus 1 m, over dt); a free body's linear velocity
    is not bounded (it may fall as long as it likes)."""
    kinds = model.coordinate_speeds()
    out = np.full(model.nv, np.inf)
    out[[k == "angular" for k in kinds]] = np.pi / dt
    if "linear" in kinds:
        origins = link_placements(model, neutral(model))[:, :3, 3]
        size = float(np.max(np.ptp(origins, axis=0))) + 1.0 if origins.size else 1.0
        out[[k == "linear" for k in kinds]] = size / dt
    return out


def _steps(steps) -> int:
    if isinstance(steps, bool) or not isinstance(steps, numbers.Integral) or steps < 1:
        raise ValueError(f"steps must be a positive integer, got {steps!r}")
    return int(steps)


def _torques(model, tau, steps: int) -> np.ndarray:
    """Open-loop torques as (steps, nv) or (B, steps, nv) float64; for None one row of
    zeros (1, nv), which the loop holds over every step."""
    nv = model.nv
    if tau is None:
        return np.zeros((1, nv))
    if np.iscomplexobj(tau):
        raise ValueError("tau has complex values; expected real torques")
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
    empty = [k for k, n in sizes.items() if n == 0]
    if empty:
        raise ValueError(f"{empty[0]} holds no rollout (shape {arrays[empty[0]].shape}); "
                         f"expected at least one row")
    if len(set(sizes.values())) > 1:
        detail = ", ".join(f"{k} {arrays[k].shape}" for k in sizes)
        raise ValueError(f"the batched inputs disagree on the number of rollouts: {detail}")
    return next(iter(sizes.values()), 0)


def _passive(model, coords: np.ndarray) -> int:
    """The damping, stiffness and spring reference per velocity coordinate into ``coords``
    (``rollout.DAMPING``, ``STIFFNESS``, ``SPRING``); the flag that turns them on."""
    coords[DAMPING] = model.damping
    coords[STIFFNESS] = model.stiffness
    coords[SPRING] = spring_deflection(model, np.zeros(model.nq)) * -1.0  # q_spring, by v
    return PASSIVE


def _tendons(model) -> np.ndarray:
    """The fixed tendons' rows for the compiled loop (``rollout._tendon``): coefficients,
    then stiffness, damping and the relaxed lengths."""
    return np.ascontiguousarray(np.column_stack([
        model.tendon_coefficients, model.tendon_stiffness, model.tendon_damping,
        model.tendon_spring_length]).reshape(-1, model.nv + TENDON))


def _servo_rows(servos: tuple, nv: int) -> np.ndarray:
    """The servos' springs and dampers (``algorithms.actuators.actuator_springs``) as rows
    of the compiled loop's tendons (rest length 0), their moment arms padded with zeros to
    ``nv`` (the World's free bodies come after the robot's coordinates)."""
    W, stiffness, damping = servos
    rows = np.zeros((len(W), nv + TENDON))
    rows[:, :W.shape[1]] = W
    rows[:, nv], rows[:, nv + 1] = stiffness, damping
    return rows


def _implicit(packed: np.ndarray, coords: np.ndarray, dt: float
              ) -> tuple[np.ndarray, np.ndarray]:
    """The contact step's joint stiffnesses and dampers taken at the end of the step (K40):
    the PD's and the springs' ``K = K_p + k`` and the PD's and the dampers' ``D = K_d + d``
    act on ``v⁺`` and ``q ⊕ dt v⁺``, so the step solves with ``M + dt D + dt² K`` and the
    torque shifted by ``-dt K v`` (``rollout.SHIFT``). The packed model with that armature,
    and the diagonal added."""
    stiff = coords[KP] + coords[STIFFNESS]
    extra = dt * (coords[KD] + coords[DAMPING]) + dt * dt * stiff
    coords[SHIFT] = dt * stiff
    return with_armature(packed, extra), extra


def _controller(model, controller, q0: np.ndarray, B: int, coords: np.ndarray):
    """``(flags, q_ref (B, nq), v_ref (B, nv))`` for the compiled loop; a PD law's gains
    into ``coords`` (``rollout.KP``, ``KD``), zero where no actuator drives."""
    nq, nv = model.nq, model.nv
    q_ref, v_ref = q0.copy(), np.zeros((B, nv))
    if controller is None:
        return 0, q_ref, v_ref
    if isinstance(controller, GravityCompensation):
        return controller.flags(), q_ref, v_ref
    if not isinstance(controller, PD):
        raise ValueError(f"controller must be None, cgadyn.PD(...) or "
                         f"cgadyn.GravityCompensation(), got {controller!r}")
    coords[KP] = actuated_gains(model, controller.kp, "kp")
    coords[KD] = actuated_gains(model, controller.kd, "kd")
    if controller.q_ref is not None:
        ref = _inputs.state(model, controller.q_ref, "q_ref", nq)
        if ref.ndim != 1 or not np.all(np.isfinite(ref)):
            raise ValueError(f"q_ref must be one finite configuration ({nq},), got {ref!r}")
        _energy(model, ref, np.zeros(nv))  # unit quaternions (free flyers, spherical joints)
        q_ref[:] = ref
    if controller.v_ref is not None:
        ref = _inputs.state(model, controller.v_ref, "v_ref", nv)
        if ref.ndim != 1 or not np.all(np.isfinite(ref)):
            raise ValueError(f"v_ref must be one finite velocity ({nv},), got {ref!r}")
        v_ref[:] = ref
    return controller.flags(), q_ref, v_ref


_CAUSE = "the step dt is likely too large for the motion, or the gains or torques too strong"


def _constraint_reason(code: int, row: int, p) -> str:
    """Why the constraints stopped a rollout: a singular Delassus matrix or no solution, at
    the constraint of ``row``."""
    k = int(np.searchsorted(p.starts, max(row, 0), side="right") - 1)
    which = f"constraint {k} ({p.constraints[k].name})"
    if code == DELASSUS_SINGULAR:
        return (f"the constraints became singular: {which} has rows that depend on the "
                f"others' (the Delassus matrix G = J M⁻¹ Jᵀ lost rank, a loop through a "
                f"singular pose or a redundant set); pass damping > 0 (e.g. 1e-8) for the "
                f"least-norm forces of a redundant set")
    return (f"the constraints have no solution: after the proximal iterations {which} is "
            f"still violated (its rows conflict with those of the others)")


def _reason(model, code: int, joint: int, k: int, coords: np.ndarray, dt: float,
            initial: bool, p=None, report=None, pairs=None) -> str:
    """Why a rollout stopped after ``k`` steps, in words: divergence (the quantity that blew
    up, and the likely cause), the constraints (``joint`` then holds their row), or, when
    ABA failed on the ``initial`` state itself, a fault of the model or of that state."""
    if code in (DELASSUS_SINGULAR, CONSTRAINTS_CONFLICT) and p is not None and p.nr:
        return _constraint_reason(code, joint, p)
    if code == CONTACT_PAIR and pairs is not None:
        a, b = pairs[joint]
        return (f"at step {k + 1} the penetration depth of the shapes {a!r} and {b!r} was not "
                f"computed (an overlap of a curved shape that EPA and its refinement do not "
                f"settle, docs/contact.md K9a); the rollout stops rather than step without their "
                f"contact (a smaller dt keeps overlaps shallower)")
    if code == CONTACT_UNSOLVED and report is not None:
        return (f"the contact solvers did not converge in {int(report[0])} iterations at "
                f"step {k + 1} (residuals: primal {report[1]:.2e}, dual {report[2]:.2e}, "
                f"complementarity {report[3]:.2e}, above ContactSettings.accept)")
    name = f" {model.joint_names[joint]!r}" if joint >= 0 else ""
    if code == DIVERGED:
        dofs = model.joint_dofs(joint)
        bound = float(np.min(coords[SPEED_BOUND, dofs.start:dofs.stop]))
        unit, what = (("rad/s", "half a turn") if bound == np.pi / dt
                      else ("m/s", "further than the robot is large"))
        return (f"the state diverged: a velocity of joint{name} passed {bound:.3g} {unit}, "
                f"moving {what} in one step of dt = {dt:g} s; {_CAUSE}")
    if code == NONFINITE_RESULT:
        return f"the state diverged: it stopped being finite; {_CAUSE}"
    if code == SINGULAR and not initial:
        return (f"the state diverged: the articulated-body inertia at joint{name} lost "
                f"positive definiteness in floating point within step {k + 1}, from a "
                f"state where it had it; {_CAUSE}")
    if code == SINGULAR:
        return (f"a singular articulated-body inertia at joint{name} in the initial state "
                f"(a subtree without mass?)")
    if code == QUATERNION:
        return f"the quaternion of joint{name} left unit length; {_CAUSE}"
    return f"status {code}"


def _message(model, status: np.ndarray, completed: np.ndarray, dt: float, steps: int,
             batch: int, coords: np.ndarray, A: np.ndarray, p=None, report=None,
             pairs=None) -> str:
    """What stopped the rollouts that stopped ("" if none did); ``A`` the accelerations
    kept, NaN in row 0 where ABA failed on a rollout's initial state."""
    stopped = np.flatnonzero(status)
    if stopped.size == 0:
        return ""
    first = int(stopped[0])
    code, joint, _ = decode(int(status[first]))
    k = int(completed[first])
    initial = k == 0 and not np.isfinite(A[first, 0]).all()
    reason = _reason(model, code, joint, k, coords, dt, initial, p,
                     None if report is None else report[first], pairs)
    where = f"rollout {first} " if batch else ""
    more = f" ({stopped.size} of {batch} rollouts stopped)" if batch else ""
    return (f"simulation of {model.name!r}: {where}stopped after {k} of {steps} steps "
            f"(t = {k * dt:g} s): {reason}; the trajectory holds the states up to "
            f"t = {k * dt:g} s{more}")
