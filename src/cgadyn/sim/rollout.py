"""Rollouts in one compiled call: the closed-loop dynamics, three integrators on the
configuration manifold, and the loop over steps, parallel over rollouts.

The state is ``(q, v)``; its time derivative is ``(v, q̈)`` with (Algorithms 1 and 3)

    q̈ = ABA(q, v, τ),   τ = τ_ol(t_k) + τ_ctrl(q, v)
    τ_ctrl = K_p (q_ref ⊖ q) + K_d (v_ref - v) + g(q),   g(q) = RNEA(q, 0, 0)  (Algorithm 2)

``τ_ol`` is held constant over each step (zero-order hold); the feedback law is evaluated
at every stage of the integrator, as part of the closed-loop vector field. Positions move
on the configuration manifold with ``q ⊕ δ`` (``multibody.joints.joint_integrate``: a sum
for one-dof joints, ``M exp(V / 2)`` for a free flyer). With ``h = dt``:

- ``EULER``: ``q' = q ⊕ h v``, ``v' = v + h q̈(q, v)``;
- ``SEMI_IMPLICIT_EULER`` (symplectic Euler): ``v' = v + h q̈(q, v)``, ``q' = q ⊕ h v'``;

  on a free flyer (and a planar joint), whose linear velocity v is in the body's own
  turning frame, both take that part in the frame the step starts from and move the result
  into the frame of q' (``algorithms.manifold.free_velocity``, ``transport``;
  docs/contact.md, K24)::

      v' = exp(-h ω̂') (v + h (v̇ + ω × v)),   ω̂' the rotation q ⊕ h · turns by

  so that a body that nothing pushes keeps its velocity in the world (read in the turning
  frame, ``v + h v̇`` grows it by ``h² |ω × v|²`` a step: the energy of a spinning body
  would rise), and move q' with ``joint_step``: the origin straight along that world
  velocity, ``p + h R v``, the body turned about it by ``R exp(h ω̂)`` (K24a; the screw
  motion of ``q ⊕ h v`` runs the origin on an arc);
- ``RK4``: the classical Runge-Kutta stages, each taken from q in the chart ``q ⊕ ·``::

      k_1 = (v, q̈(q, v))
      k_i = (v_i, q̈(q ⊕ c_i h v_{i-1}, v_i)),   v_i = v + c_i h q̈_{i-1},   c = (½, ½, 1)
      q' = q ⊕ h/6 (v + 2 v_2 + 2 v_3 + v_4),   v' = v + h/6 (q̈_1 + 2 q̈_2 + 2 q̈_3 + q̈_4)

  fourth order for one-dof joints; for the rotation of a free flyer the chart is not
  corrected by the inverse of the exponential's differential (Munthe-Kaas), so the order
  there is lower, as with the same scheme written on Pinocchio's ``integrate``.

Only the actuated coordinates are driven: ``τ_ctrl`` is multiplied coordinate by coordinate
by the model's actuation selector (1 for a joint's coordinate, 0 for a free flyer's: nothing
pushes on a floating base but external forces), so gravity compensation compensates the
joints only and a PD law has no gains on the base.

Every core called here (``aba_core``, ``rnea_core``, ``energy_core``) allocates nothing and
takes a workspace; each rollout owns one. Compiled code never raises: a rollout whose step
fails (a fault of ABA, a state that is no longer finite, or a speed past its bound) stops
there with a status, and the loop records how many steps it completed. The speed bound of
each velocity coordinate (``DIVERGED``) is what one step can resolve: an angle that turns
more than half a turn in one step, or a slide that moves further than the robot is large,
is an integration that has diverged, and is caught before ABA meets the overflowing state.

States are kept every ``every`` steps (state 0, every, 2 every, ...) and the last one; with
``every = 0`` only the last. The loop steps in two state buffers of its own and writes only
the states kept, so a long run needs memory for those alone.

With constraints (``docs/constraints.md``, "Rollouts"), every stage's q̈ is the constrained
dynamics instead of ABA, from the same torque (C6, C7):

    M q̈ = τ - h + Jᵀ λ,   J q̈ = -γ   (γ with each constraint's corrector, C5)

computed by ``constraints.core.constraint_core`` in the rollout's workspace; a singular
Delassus matrix (``DELASSUS_SINGULAR``) or a proximal solve left with a violated row
(``CONSTRAINTS_CONFLICT``) stops the rollout like a divergence. At each state kept the loop
also keeps, per constraint row, the position error (C5's e), the velocity error ``J v`` and
the force λ of that state (``X``).

The loop over steps computes no energy: ``energies`` computes the kinetic and potential
energy of every state reached afterwards, in one parallel call over all states, when a
``Trajectory``'s energy is first read (a rollout for control needs only q, v, q̈).
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import core, inline, parallel, serial
from .._threads import in_chunks
from ..algorithms import _workspace as ws
from ..algorithms._checks import finite
from ..algorithms._workspace import chunks
from ..algorithms.aba import aba_core
from ..algorithms.energy import energy_core
from ..algorithms.manifold import free_velocity, integrate_joints, step_joints, transport
from ..algorithms.rnea import rnea_core
from ..algorithms.status import CONSTRAINTS_CONFLICT, DIVERGED, NONFINITE_RESULT, OK, fault
from ..algorithms.work.aba import workspace_size as aba_workspace
from ..algorithms.work.crba import workspace_size as crba_workspace
from ..algorithms.work.energy import workspace_size as energy_workspace
from ..algorithms.work.rnea import workspace_size as rnea_workspace
from ..constraints.articulated import row_values
from ..constraints.core import FORWARD, INFO, constraint_core
from ..constraints.work.core import workspace as constraint_workspace
from ..constraints.work.core import workspace_size as constraint_workspace_size
from ..multibody.joints import joint_difference
from ..multibody.packed import unpack
from .contact import (
    carve_scratch,
    contact_velocity,
    correct_positions,
    factored_dynamics,
    scratch_size,
)
from .pairs import pair_count, pair_scratch_size
from .work.rollout import workspace, workspace_size

WORKSPACE = {  # one rollout's scratch, in order (tools/generate_workspaces.py)
    "K": (4, "nv"),  # the RK4 stages' velocities
    "Ka": (4, "nv"),  # and accelerations
    "tau": ("nv",),
    "g": ("nv",),
    "dq": ("nv",),
    "zero": ("nv",),  # zeros
    "none": (0, 6),  # no wrenches
    "tmp": (3, 8),
    "qs": ("nq",),  # the stage configuration
    "q": ("nq",),  # the loop's state
    "v": ("nv",),
    "qn": ("nq",),  # the next one
    "vn": ("nv",),
    "a": ("nv",),  # the acceleration
    "J": ("nr", "nv"),  # the core's J argument (C1, C2; not formed by FORWARD)
    "gam": ("nr",),  # their drift γ (C3-C5)
    "G": ("nr", "nr"),  # the Delassus matrix (C7)
    "lam": ("nr",),  # the forces λ
    "info": (5,),  # the solve's report (constraints.core)
    "X": (3, "nr"),  # at the step's state: the position error, J v and λ of each row
}

RK4, SEMI_IMPLICIT_EULER, EULER = 0, 1, 2
"""The integrators, by number."""

PD, GRAVITY, PASSIVE, IMPLICIT = 1, 2, 4, 8
"""Controller flags: joint-space PD around ``(q_ref, v_ref)``, gravity compensation, the
passive joint torques (dampers and springs, ``cgadyn.passive_torques``), and the implicit
step's shift of the torque by ``-dt (K_p + k) v`` (K40, ``docs/contact.md``)."""

TENDON = 4
"""Floats of a fixed tendon's row after its nv coefficients: stiffness, damping and the
relaxed lengths ``L_lo, L_hi`` (``_tendon``)."""

KP, KD, ACTUATED, SPEED_BOUND, DAMPING, STIFFNESS, SPRING, SHIFT = 0, 1, 2, 3, 4, 5, 6, 7
COORDS = 8
"""The rows of ``coords`` (COORDS, nv), one value per velocity coordinate: the PD gains K_p
and K_d, the actuation selector (1 actuated, 0 not), the speed bound, the joint damping and
stiffness, the spring reference of the coordinate (of the joints whose coordinates add,
the only ones with springs: ``Model.stiffness``), and ``dt (K_p + k)``, by which the
implicit step shifts the torque (K40)."""


@inline
def closed_loop_acceleration(m, q, v, u, f, ctrl, con, fac, qdd, sc, work):
    """``qdd = ABA(q, v, u + τ_ctrl(q, v))`` (the module's first equations), or the
    constrained dynamics of that torque; ``ctrl`` the controller ``(flags, coords (COORDS,
    nv), q_ref (nq), v_ref (nv), tendons (nt, nv + TENDON))``, ``con`` the constraints
    ``(pack, settings, workspace)`` (``_dynamics``). A status; ``qdd`` NaN where it fails."""
    status = _closed_loop(m, q, v, u, f, ctrl, con, fac, qdd, sc, work)
    if status != OK:
        for k in range(m.nv):
            qdd[k] = np.nan
    return status


@inline
def _closed_loop(m, q, v, u, f, ctrl, con, fac, qdd, sc, work):
    """``closed_loop_acceleration``, its ``qdd`` undefined where it fails."""
    flags, coords, q_ref, v_ref, tendons = ctrl
    if flags == 0:  # no feedback: τ = τ_ol
        return _dynamics(m, q, v, u, f, con, fac, qdd, sc, work)
    tau, g, dq, zero, none, tmp = sc.tau, sc.g, sc.dq, sc.zero, sc.none, sc.tmp
    for k in range(m.nv):
        tau[k] = u[k]
    if flags & GRAVITY:
        status = rnea_core(m, q, zero, zero, none, g, work)  # g(q) = RNEA(q, 0, 0)
        if status != OK:
            return status
        for k in range(m.nv):
            tau[k] += coords[ACTUATED, k] * g[k]  # the actuated coordinates' share of g(q)
    if flags & PD:
        _differences(m, q, q_ref, tmp, dq)  # q_ref ⊖ q
        for k in range(m.nv):  # K_p, K_d zero where not actuated
            tau[k] += coords[KP, k] * dq[k] + coords[KD, k] * (v_ref[k] - v[k])
    if flags & PASSIVE:  # τ_passive = -d v - k (q - q_spring), springs on additive joints
        for k in range(m.nv):
            tau[k] -= coords[DAMPING, k] * v[k]
            if coords[STIFFNESS, k] != 0.0:
                j = m.dof_joint[k]
                tau[k] -= coords[STIFFNESS, k] * (q[m.iq[j] + k - m.iv[j]] - coords[SPRING, k])
        for t in range(tendons.shape[0]):
            _tendon(m, q, v, tendons[t], tau)
    if flags & IMPLICIT:  # the stiffnesses at q ⊕ dt v⁺, linearised (K40)
        for k in range(m.nv):
            tau[k] -= coords[SHIFT, k] * v[k]
    return _dynamics(m, q, v, tau, f, con, fac, qdd, sc, work)


@inline
def _tendon(m, q, v, row, tau):
    """``tau += c (-k dev(c · q) - b c · v)``: one fixed tendon's spring and damper (P2,
    ``algorithms.passive``); ``row`` its coefficients over the nv coordinates, then ``k, b,
    L_lo, L_hi`` (``TENDON`` floats)."""
    nv = m.nv
    length, rate = 0.0, 0.0
    for k in range(nv):
        if row[k] != 0.0:  # coordinates that add only (Model._check_tendons)
            j = m.dof_joint[k]
            length += row[k] * q[m.iq[j] + k - m.iv[j]]
            rate += row[k] * v[k]
    lo, hi = row[nv + 2], row[nv + 3]
    dev = length - hi if length > hi else (length - lo if length < lo else 0.0)
    force = -row[nv] * dev - row[nv + 1] * rate
    for k in range(nv):
        tau[k] += row[k] * force


@serial
def _dynamics(m, q, v, tau, f, con, fac, qdd, sc, work):
    """``qdd = ABA(q, v, τ)`` without constraints (``con`` None); with them (``con = (pack,
    settings, cwork)``: ``constraints.core``'s pack and settings, its workspace) the
    constrained dynamics ``M q̈ = τ - h + Jᵀ λ``, ``J q̈ = -γ`` (C6, C7), λ in ``sc.lam``. A
    status: ``CONSTRAINTS_CONFLICT`` at the worst row where the proximal solve ends with no
    solution. With a world and no constraints (``fac`` its ``factored`` flags and
    constraint workspace, ``_factors``), ``M⁻¹ (τ - h)`` from the factors of M that its
    contact step then reuses (``sim.contact.factored_dynamics``); with both, the constrained
    dynamics, M left for the contact step to factor (C14). Compiled apart from its
    callers, for ``con`` and ``fac`` None or not: numba removes the branch of the other, so
    a rollout without constraints never compiles their core."""
    if fac is not None:
        return _world_dynamics(m, q, v, tau, f, con, fac, qdd, sc, work)
    if con is None:
        return aba_core(m, q, v, tau, f, qdd, work)
    return _constrained(m, q, v, tau, f, con, qdd, sc, work)


@core
def _world_dynamics(m, q, v, tau, f, con, fac, qdd, sc, work):
    """``_dynamics`` with a world: from M's factors without constraints (``con`` None),
    else the constrained dynamics, M left for the contact step to factor (C14)."""
    factored, cwork = fac
    if con is None:
        return factored_dynamics(m, factored, cwork, q, v, tau, f, qdd, sc.zero, work)
    factored[0] = 0.0
    return _constrained(m, q, v, tau, f, con, qdd, sc, work)


@serial
def _constrained(m, q, v, tau, f, con, qdd, sc, work):
    """The constrained dynamics of ``_dynamics`` (C6, C7), λ in ``sc.lam``."""
    cons, settings, cwork = con
    # np.int64: the constant would be a literal type, a variant of the core of its own
    status = constraint_core(m, cons, q, v, tau, settings, np.int64(FORWARD), sc.J, sc.gam,
                             sc.G, qdd, sc.lam, sc.info, cwork, f)
    if status == OK and sc.info[INFO - 1] >= 0.0:
        return fault(CONSTRAINTS_CONFLICT, int(sc.info[INFO - 1]))
    return status


@serial
def _record(m, con, status, sc):
    """``sc.X``: the position error (C5's e), the velocity error ``J v`` and the force λ of
    each row at the state whose dynamics ``_dynamics`` just solved with ``status``; NaN
    where it failed (``J v`` from the bodies' twists that solve left in the constraint
    workspace, C12's rows as wrenches). Nothing without constraints (``con`` None: pruned
    as in ``_dynamics``)."""
    if con is None:
        return
    cons, settings, cwork = con
    nr = int(cons[1])
    X = sc.X
    if status != OK:
        for i in range(3):
            for r in range(nr):
                X[i, r] = np.nan
        return
    k_ = constraint_workspace(ws.data_pointer(cwork), m, nr)
    row_values(m, nr, k_.Vw, k_, X[1])  # J v
    for r in range(nr):
        X[0, r], X[2, r] = k_.e[r], sc.lam[r]


@serial
def _rows_of(cons):
    """The constraint rows of a pack (``constraints.core``); 0 for none (``cons`` None)."""
    if cons is None:
        return np.int64(0)  # not the literal 0: one variant of what takes it
    return int(cons[1])


@serial
def _bind(cons, settings, cwork):
    """``_dynamics``'s ``con``: None without constraints, else their pack, settings and
    workspace."""
    if cons is None:
        return None
    return (cons, settings, cwork)


@core
def _contact(m, world, q, v, dt, vn, work, con, sc):
    """The contact impulses of ``world`` on the free velocity ``vn`` (``free_velocity``,
    ``sim.contact``); nothing without a world (``world`` None: pruned, no contact code
    compiled)."""
    if world is None:
        return OK
    return contact_velocity(m, world, q, v, vn, dt, work, con, sc)


@serial
def _bind_world(world, buf, n, nq, nv, nl, nr):
    """None without a world, else it and this rollout's scratch (``carve_scratch``)."""
    if world is None:
        return None
    return carve_scratch(world, buf, n, nq, nv, nl, nr)


@serial
def _factors(world):
    """None without a world, else its ``factored`` flags and constraint workspace: what
    ``_dynamics`` needs of it (a small tuple, not the world's whole scratch, through the
    calls of every step)."""
    if world is None:
        return None
    return (world.factored, world.cwork)


@serial
def _world_size(world, n, nq, nv, nl, nr):
    """Floats of a rollout's contact scratch; 0 without a world."""
    if world is None:
        return 0
    return scratch_size(n, nq, nv, nl, world.kinds.shape[0] + pair_count(world.pairs),
                        world.limits.shape[0], world.frictions.shape[0],
                        world.couplings.shape[0], world.ropes.shape[0], nr) \
        + pair_scratch_size(world.pairs)


@serial
def _kept(world):
    """None without a world, else what ``_keep_contacts`` reads of it: the slots' forces,
    which slots held a contact (``had``), the contacts' number, the solvers' report and the
    joint torques of the limits and friction losses (a small tuple, not the world's whole
    scratch, as ``_factors``)."""
    if world is None:
        return None
    return (world.force, world.had, world.count, world.report, world.joint_torques)


@core
def _keep_contacts(kept, row, CS, CT, r):
    """``row = [count, iterations, residual]`` of the last contact step
    (``sim.contact.KEPT``), and into row ``r`` of ``CS`` (K, rows, 3) and ``CT``
    (``JOINT_TORQUES``, nv, rows), the forces of the slots that held a contact and the
    limits', friction losses' and couplings' nonzero generalised forces; nothing without a
    world. ``CS`` and ``CT`` are slot-major and come in as untouched zero pages of 4 KiB
    (``simulate``, ``sim/pages.py``): a slot that never holds a contact, a coordinate no
    limit, friction loss or coupling acts on, is never written and costs no memory, and
    each written stream is contiguous in the steps."""
    if kept is None:
        return
    force, had, count, report, torques = kept
    row[0] = count[0]
    row[1] = report[0]
    row[2] = max(report[1], report[2], report[3])
    for k in range(force.shape[0]):
        if had[k] != 0.0:
            for i in range(3):
                CS[k, r, i] = force[k, i]
    for i in range(torques.shape[0]):
        for k in range(torques.shape[1]):
            if torques[i, k] != 0.0:
                CT[i, k, r] = torques[i, k]


@serial
def _unset_contacts(kept, CS, CT, r):
    """NaN into row ``r`` of ``CS`` and ``CT`` (``_keep_contacts``), a state no step
    reached or whose contacts could not be computed; nothing without a world."""
    if kept is None:
        return
    for k in range(CS.shape[0]):
        for i in range(3):
            CS[k, r, i] = np.nan
    for i in range(CT.shape[0]):
        for k in range(CT.shape[1]):
            CT[i, k, r] = np.nan


@serial
def _report(world, out):
    """The report of a contact step that failed (``sim.contact.REPORT``) into ``out``."""
    if world is None:
        return
    for i in range(out.shape[0]):
        out[i] = world.report[i]


@inline
def _advance(m, q, v, h, tmp, dq, out, euler):
    """``out = q ⊕ h v`` (``dq`` receives ``h v``); an Euler step's move where ``euler``
    (``joint_step``: a free flyer's or planar joint's origin along the world vector of its
    linear velocity, held there through the step, K24a)."""
    if m.flat:  # every joint additive: a sum, coordinate-wise
        for k in range(m.nv):
            dq[k] = h * v[k]
            out[k] = q[k] + dq[k]
        return
    if euler:
        step_joints(m, q, v, h, tmp, dq, out)
    else:
        integrate_joints(m, q, v, h, tmp, dq, out)


@core
def _differences(m, q, q_ref, tmp, dq):
    """``dq = q_ref ⊖ q`` joint by joint (``joint_difference``), compiled once and called
    (as ``algorithms.manifold.integrate_joints``)."""
    for j in range(m.n):
        joint_difference(m, j, q, q_ref, tmp, dq)


@inline
def step(m, method, q, v, u, f, ctrl, con, world, fac, dt, qn, vn, a, sc, work):
    """One step of ``method`` from ``(q, v)`` to ``(qn, vn)``; ``a = q̈(q, v)`` (and ``sc.X``
    the constraints' record of ``(q, v)``, ``_record``). A status.

    Every method evaluates its stages in one loop (one for the Euler methods, four for
    RK4) and moves ``q`` once at the end: each kernel appears once in the compiled loop.
    With a ``world`` (semi-implicit Euler only) the contact impulses change ``v'`` before
    ``q`` moves (``_contact``)."""
    K, Ka, tau, dq, tmp, qs = sc.K, sc.Ka, sc.tau, sc.dq, sc.tmp, sc.qs
    for i in range(4 if method == RK4 else 1):
        h = dt if i == 3 else 0.5 * dt
        if i == 0:
            for k in range(m.nv):
                K[0, k] = v[k]
        else:
            _advance(m, q, K[i - 1], h, tmp, dq, qs, False)  # q ⊕ c_i h v_{i-1}
            for k in range(m.nv):
                K[i, k] = v[k] + h * Ka[i - 1, k]  # v_i = v + c_i h q̈_{i-1}
        status = closed_loop_acceleration(m, q if i == 0 else qs, K[i], u, f, ctrl, con, fac,
                                          Ka[i], sc, work)
        if i == 0:
            for k in range(m.nv):
                a[k] = Ka[0, k]
            _record(m, con, status, sc)
        if status != OK:
            return status
    w = dt
    if method == EULER:
        for k in range(m.nv):
            tau[k] = v[k]
        free_velocity(m, v, a, dt, vn)
    elif method == SEMI_IMPLICIT_EULER:
        free_velocity(m, v, a, dt, vn)
        status = _contact(m, world, q, v, dt, vn, work, con, sc)
        if status != OK:
            return status
        for k in range(m.nv):
            tau[k] = vn[k]
    else:
        w = dt / 6.0
        for k in range(m.nv):
            tau[k] = K[0, k] + 2.0 * K[1, k] + 2.0 * K[2, k] + K[3, k]
            vn[k] = v[k] + w * (Ka[0, k] + 2.0 * Ka[1, k] + 2.0 * Ka[2, k] + Ka[3, k])
    _advance(m, q, tau, w, tmp, dq, qn, method != RK4)  # dt v, dt v⁺ (K24a); RK4's sum
    if method == SEMI_IMPLICIT_EULER:
        correct_positions(m, world, qn, tmp, dq, qs)  # past a bound, into the ground: K26a, K43
    if method != RK4:
        transport(m, tau, dt, vn)  # v' in the frames of q' (K24)
    if not (finite(qn) and finite(vn)):
        return fault(NONFINITE_RESULT, -1)
    return _within_bounds(m, vn, ctrl[1])


@inline
def _within_bounds(m, v, coords):
    """OK, or ``DIVERGED`` at the joint of the first velocity coordinate past its speed
    bound (the module's docstring)."""
    for k in range(m.nv):
        if abs(v[k]) > coords[SPEED_BOUND, k]:
            return fault(DIVERGED, m.dof_joint[k])
    return OK


@inline
def core_workspace_size(n, nq, nv, nl):
    """The largest workspace of the cores a step calls, shared by them in turn."""
    return max(aba_workspace(n, nq, nv, nl), rnea_workspace(n, nq, nv, nl),
               crba_workspace(n, nq, nv, nl))


@inline
def heap_size(n, nq, nv, nl, nr):
    """The cores' shared workspace, then the constraint core's own (none without rows)."""
    extra = constraint_workspace_size(n, nq, nv, nl, nr) if nr > 0 else 0
    return core_workspace_size(n, nq, nv, nl) + extra


def rollouts(packed, method, q0, v0, u, f, flags, coords, tendons, q_ref, v_ref, cons, settings,
             world, dt, steps, every, Q, V, A, X, CF, CS, CT, CR, completed, status) -> None:
    """``B = q0.shape[0]`` rollouts of ``steps`` steps, in parallel.

    ``q0`` (B, nq), ``v0`` (B, nv); ``u`` the open-loop torques (1 or B, steps or 1, nv),
    one row held over every step where it has one;
    ``f`` wrenches (0, 1 or B, n, 6); ``coords`` (COORDS, nv) per velocity coordinate (``KP``,
    ``KD``, ``ACTUATED``, ``SPEED_BOUND``); ``tendons`` (nt, nv + TENDON) the fixed tendons'
    springs and dampers (``_tendon``); ``q_ref`` (B, nq), ``v_ref`` (B, nv); ``every``
    the states kept (``kept_row``); ``cons`` the constraints' pack (``constraints.core``;
    None for none, which compiles a loop without them) and ``settings`` their solve's (None
    with ``cons``); ``world`` the contact world (``sim.contact.world_arrays``; None, which
    compiles a loop without contact). Writes the kept states into ``Q``
    (B, rows, nq), ``V``, ``A`` (B, rows, nv), the constraints' record of each (``_record``)
    into ``X`` (B, rows, 3, nr), the contacts of each (``_keep_contacts``) into ``CF`` (B,
    rows, KEPT), ``CS`` (B, K, rows, 3) and ``CT`` (B, JOINT_TORQUES, nv, rows), these two
    zeros when they come in, a failed contact step's report into ``CR`` (B, REPORT), and per
    rollout the steps ``completed`` and the ``status`` (0, or the fault that stopped it). The
    acceleration at the last state takes the last open-loop torque. The outputs may come in
    unwritten (so that their pages are first touched by the thread that writes them, in
    parallel): each rollout writes every one of its rows once, a state or NaN (``_unset``);
    a rollout that stops writes the last state it reached into the row of that state, or
    the next one (``stop_row``), and NaN after it.

    The rollouts run in contiguous chunks, one per thread of numba's, each chunk one call
    of ``rollout_range`` on a Python thread (``_threads.in_chunks``), not a ``prange`` loop,
    whose body numba would compile again with everything it calls (``docs/architecture.md``,
    "Compiling and caching").
    """
    size, csize, wsize = rollout_sizes(packed, cons, world)

    def run(b0: int, b1: int) -> None:
        rollout_range(packed, b0, b1, method, q0, v0, u, f, flags, coords, tendons, q_ref,
                      v_ref, cons, settings, world, dt, steps, every, Q, V, A, X, CF, CS, CT, CR,
                      completed, status, np.empty(size), np.empty(csize), np.empty(wsize))

    in_chunks(run, q0.shape[0])


@serial
def rollout_sizes(packed, cons, world):
    """Floats of one thread's buffers for ``rollout_range``: its scratch (``workspace``), its
    cores' workspace (``heap_size``) and its contact scratch (``_world_size``)."""
    m = unpack(packed)
    nr = _rows_of(cons)
    return (workspace_size(m.n, m.nq, m.nv, m.nl, nr), heap_size(m.n, m.nq, m.nv, m.nl, nr),
            _world_size(world, m.n, m.nq, m.nv, m.nl, nr))


@serial
def rollout_range(packed, b0, b1, method, q0, v0, u, f, flags, coords, tendons, q_ref, v_ref,
                  cons, settings, world, dt, steps, every, Q, V, A, X, CF, CS, CT, CR, completed,
                  status, buf, heap, wbuf):
    """Rollouts ``b0 .. b1 - 1`` of ``rollouts``, one after the other, in the scratch ``buf``
    (``workspace``) and the cores' workspace ``heap`` (``heap_size``: the shared one, then
    the constraint core's), and the contact scratch ``wbuf``, which each rollout sets up
    afresh. Bare views (``_views.carve``) are valid only while the array they view lives,
    and compiled code frees a local array after its last use, not at the end of its scope:
    so the buffers are this function's arguments, alive until it returns."""
    mb = unpack(packed)
    held = u.shape[1]
    nr = _rows_of(cons)
    shared = core_workspace_size(mb.n, mb.nq, mb.nv, mb.nl)
    work, o = ws.carve(ws.data_pointer(heap), 0, (shared,))  # bare: no reference counts
    cwork = ws.carve(ws.data_pointer(heap), o, (heap.shape[0] - shared,))[0]
    con = _bind(cons, settings, cwork)
    sc = workspace(ws.data_pointer(buf), mb, nr)
    for k in range(mb.nv):
        sc.zero[k] = 0.0
    q, v, qn, vn, a = sc.q, sc.v, sc.qn, sc.vn, sc.a
    rows = Q.shape[1]
    hold = 1 if held == steps else 0  # a row of u per step, or one for all
    for b in range(b0, b1):
        wd = _bind_world(world, wbuf, mb.n, mb.nq, mb.nv, mb.nl, nr)  # warm starts cleared
        fac = _factors(wd)
        kept = _kept(wd)
        # bare views of this rollout's contact outputs (no reference counts at each step)
        CSb = ws.carve(ws.data_pointer(CS[b]), 0, CS[b].shape)[0]
        CTb = ws.carve(ws.data_pointer(CT[b]), 0, CT[b].shape)[0]
        # bare views of this rollout's rows (no reference counts in the loop over steps)
        Qb = _rows(Q[b], rows, mb.nq)
        Vb = _rows(V[b], rows, mb.nv)
        Ab = _rows(A[b], rows, mb.nv)
        Xb = _rows(X[b], rows, 3 * nr)
        CFb = _rows(CF[b], rows, CF.shape[2])
        ub = _rows(u[0], held, mb.nv)  # shared by all rollouts, or
        if u.shape[0] > 1:
            ub = _rows(u[b], held, mb.nv)  # this rollout's own
        fb = sc.none  # no wrenches, or
        if f.shape[0] == 1:
            fb = _rows(f[0], mb.n, 6)
        elif f.shape[0] > 1:
            fb = _rows(f[b], mb.n, 6)
        ctrl = (flags, _rows(coords, COORDS, mb.nv), _rows(q_ref[b], 1, mb.nq)[0],
                _rows(v_ref[b], 1, mb.nv)[0], _rows(tendons, tendons.shape[0], mb.nv + TENDON))
        for k in range(mb.nq):
            q[k] = q0[b, k]
        for k in range(mb.nv):
            v[k] = v0[b, k]
        s = OK
        done = 0
        last = -1  # the last row written
        for i in range(steps):
            s = step(mb, method, q, v, ub[hold * i], fb, ctrl, con, wd, fac, dt, qn, vn, a, sc,
                     work)
            r = kept_row(i, steps, every)
            if r >= 0:
                _keep(q, v, a, sc.X, Qb[r], Vb[r], Ab[r], Xb[r])
                _keep_contacts(kept, CFb[r], CSb, CTb, r)
                last = r
            if s != OK:
                _report(wd, CR[b])
                break
            for k in range(mb.nq):
                q[k] = qn[k]
            for k in range(mb.nv):
                v[k] = vn[k]
            done = i + 1
        if s == OK:
            s = closed_loop_acceleration(mb, q, v, ub[hold * (steps - 1)], fb, ctrl, con, fac,
                                         a, sc, work)
            _record(mb, con, s, sc)
            r = kept_row(steps, steps, every)
            if s == OK:  # the contacts at the last state: those of one more step from it (and
                free_velocity(mb, v, a, dt, vn)  # the constraints' share, C14)
                _contact(mb, wd, q, v, dt, vn, work, con, sc)
            _keep(q, v, a, sc.X, Qb[r], Vb[r], Ab[r], Xb[r])
            if s == OK:
                _keep_contacts(kept, CFb[r], CSb, CTb, r)
            else:
                _unset(CFb[r])
                _unset_contacts(kept, CSb, CTb, r)
            last = r
        elif kept_row(done, steps, every) < 0:
            last = stop_row(done, every)
            _keep(q, v, a, sc.X, Qb[last], Vb[last], Ab[last], Xb[last])
            _unset(CFb[last])
            _unset_contacts(kept, CSb, CTb, last)
        for x in (Qb, Vb, Ab, Xb, CFb):  # NaN in the rows no state reached
            for r in range(last + 1, x.shape[0]):
                _unset(x[r])
        for r in range(last + 1, rows):
            _unset_contacts(kept, CSb, CTb, r)
        completed[b] = done
        status[b] = s


@inline
def _unset(row):
    """NaN into a row of an output that no step wrote."""
    for c in range(row.shape[0]):
        row[c] = np.nan


@inline
def kept_row(i, steps, every):
    """The row of ``Q`` that keeps state ``i``, or -1: states ``0, every, 2 every, ...`` and
    the last (``steps``); ``every = 0`` keeps the last alone (row 0)."""
    if every == 0:
        return 0 if i == steps else -1
    if i % every == 0:
        return i // every
    return i // every + 1 if i == steps else -1


@inline
def stop_row(done, every):
    """The row that keeps the last state a stopped rollout reached, ``done``, where
    ``kept_row`` keeps none: the one after the last row it filled."""
    return 0 if every == 0 else done // every + 1


def kept_rows(steps: int, every: int) -> int:
    """The rows of ``Q`` for ``steps`` steps keeping every ``every``-th state
    (``kept_row``)."""
    return 1 if every == 0 else steps // every + 1 + (steps % every != 0)


@inline
def _keep(q, v, a, x, Qr, Vr, Ar, Xr):
    """Write a state, its acceleration (NaN where ``step`` could not compute it) and its
    constraints' record ``x`` (3, nr) into its row."""
    for k in range(q.shape[0]):
        Qr[k] = q[k]
    for k in range(v.shape[0]):
        Vr[k] = v[k]
        Ar[k] = a[k]
    nr = x.shape[1]
    for i in range(3):
        for r in range(nr):
            Xr[i * nr + r] = x[i, r]


@inline
def _rows(x, rows, cols):
    """A C-contiguous array ``x`` as a bare (rows, cols) view (``_views.carve``)."""
    return ws.carve(ws.data_pointer(x), 0, (rows, cols))[0]


@parallel
def energies(packed, Q, V, last, E, threads):
    """``E[b, i] = (T, U)`` (``energy_core``) of the states kept ``Q[b, i], V[b, i]`` that
    rollout b reached, rows ``i <= last[b]``, in parallel chunks of all B rows; ``E`` comes
    in filled with NaN, which stays after each rollout's last state (and where a state's
    energy is not finite)."""
    m = unpack(packed)
    B, rows = Q.shape[0], Q.shape[1]
    size = energy_workspace(m.n, m.nq, m.nv, m.nl)
    starts, stops = chunks(B * rows, threads)
    for c in prange(starts.shape[0]):
        _energies_of(packed, Q, V, last, E, starts[c], stops[c], np.empty(size))


@serial
def _energies_of(packed, Q, V, last, E, start, stop, heap):
    """Rows ``start`` to ``stop`` of ``energies``, in the workspace ``heap`` (an argument,
    so alive while its bare view is used: ``_rollout``)."""
    m = unpack(packed)
    rows = Q.shape[1]
    work = ws.carve(ws.data_pointer(heap), 0, (heap.shape[0],))[0]
    for r in range(start, stop):
        b, i = r // rows, r % rows
        if i <= last[b]:
            energy_core(m, Q[b, i], V[b, i], E[b, i], work)  # a fault leaves NaN
