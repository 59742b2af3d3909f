"""The contact step inside the compiled rollout loop (docs/contact.md, "Rollouts with
contact", K20-K26, K30).

``contact_velocity`` turns the free velocity of a semi-implicit Euler step, ``v_free = v +
dt q̈(q, v)`` (K20), into the velocity after the contact impulses, ``v⁺ = v_free + M⁻¹ Jᵀ
λ`` (K24), as ``contact.step.contact_step`` does from Python: the contacts of the shapes
with the ground at q whose gap the step may close (``manifold.shapes_on_plane``, K21-K22),
each a point of its link held in the ground frame ``(t₁, t₂, n)``, ``G = J M⁻¹ Jᵀ`` and ``g
= J v_free`` with the gap term (K23; a compliant shape's spring and damper instead, with
their compliance ``R`` on the normal row, K41), λ by the solver ``ContactSettings`` names,
then the other from its λ where the first stops short (K11-K19). A contact found in the
previous step at the same slot (shape, patch point) starts from its λ there (K25). The
bounds of the joint limits near which the step may take a coordinate
(``contact.limits.active_limits``) are rows ``±e_v`` (``-aᵀ`` on a cone-limited joint's ω,
K26') after the contacts', with the same gap term and ``λ >= 0`` (K26), warm-started from
their slot alike; then a row ``e_k`` per coordinate with a friction loss,
``|λ| <= f dt`` (K30), warm-started from its impulse in the step before; then a row ``a``
per coupling of coordinates, unbounded (K45), and a row per rope bound near which the step
may go, ``λ >= 0`` (K46), warm-started alike. It is one
function called from one site of the loop, compiled only for a rollout with a world (the
loop passes None otherwise and numba prunes the call), and compiled as a core
(``_jit.core``: without reference counts, as are the solvers and the detection it calls):
it allocates nothing, so counting the references of the arrays it hands down at every step
could never free anything.

The world reaches compiled code as a named tuple (``WorldArrays``, ``world_arrays``): the
shapes' kinds, sizes, vertices and offsets, their placements in their joints' frames and those
joints (``_joint_frames``), their links,
which touch the ground, the ground plane ``[n, δ]``, its frame, ``params`` (``PARAMS``, then
the solver's ``ncp.SETTINGS``), the joint limits enforced (``contact.limits.joint_limits``;
none where ``joint_limits`` is off), the friction losses
(``contact.limits.joint_frictions``; none where ``friction_loss`` is off), the shapes'
compliance (K41) and bounding radii (``contact.pairs.bounding_radii``: a shape out of reach
of the ground forms no candidate, K21a; a pair out of reach is skipped, K39), and the pairs
of shapes that may touch and the shapes' friction coefficients (``sim.pairs.pair_world``;
two None without free bodies and self-collision, which prunes the pairs' code, K37-K39).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from .._jit import core, inline, serial
from ..algorithms import _workspace as ws
from ..algorithms.aba import aba_core
from ..algorithms.crba import crba_core
from ..algorithms.ltdl import ltdl, ltdl_solve
from ..algorithms.manifold import integrate_joints
from ..algorithms.rnea import rnea_core
from ..algorithms.status import (
    CONTACT_PAIR,
    CONTACT_UNSOLVED,
    NONFINITE_RESULT,
    OK,
    SINGULAR,
    fault,
)
from ..constraints.core import _add_columns, _delassus, _world_columns, constraint_system
from ..constraints.work.core import workspace as constraint_workspace
from ..constraints.work.core import workspace_size as constraint_workspace_size
from ..contact import manifold as C
from ..contact import ncp
from ..contact.admm import SCRATCH_ROWS
from ..contact.correction import correction_impulses, correction_targets
from ..contact.couplings import coupling_shift
from ..contact.limits import (
    LIMIT_COLUMNS,
    ROW_COLUMNS,
    ROW_SLOT,
    active_limits,
    limit_gap,
    limit_row,
    limit_shift,
)
from ..contact.problem import normal_row, open_gap, row_starts
from ..contact.ropes import GAP as ROPE_GAP
from ..contact.ropes import ROPE_ROW, rope_bounds, rope_point, rope_rates, rope_row
from ..contact.ropes import SLOT as ROPE_SLOT
from ..contact.solver import ADMM, PGS, solve_one
from ..kernels.rigid import rigid_frame, rigid_rotate
from .pairs import (
    carve_pairs,
    detect_pairs,
    failed_pair,
    ground_friction,
    keep_pairs,
    keep_slot,
    pair_count,
    pair_gaps,
    pair_rows,
    pair_world,
)

WorldArrays = namedtuple("WorldArrays", (
    "kinds", "sizes", "vertices", "offsets", "frames", "joints", "links", "active", "ground",
    "ground_pose", "frame", "params", "limits", "tendons", "frictions", "couplings", "ropes",
    "compliance", "radii", "pairs", "shape_friction"))
"""The world as the loop reads it (``world_arrays``): the shapes' kinds, sizes, vertices
and offsets, their placements in the frames of their links' joints (``frames`` (shapes, 3,
4), the top rows of the homogeneous matrices; in the world's for a link fixed to it) and
those joints (``joints``, -1: the world), their links, which touch the ground, the
ground plane ``[n, δ]`` and its pose, the ground's frame ``(t₁, t₂, n)``, ``params``, the
joint limits (``contact.limits.joint_limits``) and the fixed tendons they may bound
(``contact.limits.tendon_arrays``), the friction losses, the couplings
(``contact.couplings.coupling_rows``), the ropes (``contact.ropes.rope_arrays``; none
where ``joint_limits`` is off), each shape's normal
stiffness and damping on the ground (``CollisionModel.compliance``, K41) and its bounding
radius; then the pairs of shapes that may touch and the shapes' friction
(``sim.pairs.pair_world``: each None without free bodies or self-collision, which prunes the
pairs' code)."""

ContactScratch = namedtuple("ContactScratch", (
    "world", "poses", "out", "counts", "cand", "big", "mu", "info", "settings", "prev",
    "force", "had", "count", "report", "cwork", "lrows", "bounds", "lprev",
    "lhad", "twists", "bodies", "factored", "pairs", "joint_torques", "depth", "shift",
    "errors", "rrows", "rates"))
"""A rollout's contact scratch (``carve_scratch``) beside its ``WorldArrays`` (``world``):
the shapes' poses, the contacts found (``out``, ``counts``), candidates, the problem's
matrices (``big``), the cones' μ, the solver's info and settings, each slot's impulse of the
previous step (``prev``, ``had``) and force of this one (``force``), the contacts' number,
the limit rows' and whether ``shift`` holds a correction (``count``: ``correct_positions``
reads the last two after the step) and
the report of the step (``report``), the constraint workspace, the active
limits' rows, the interval rows' bounds and previous impulses (``lprev``, ``lhad``), the
shapes' link twists (K21a) and the joints' (``bodies``), ``factored`` (whether the
workspace holds M's factors at this step's q; whether the last step had rows), the pairs'
scratch (``sim.pairs.carve_pairs``; None without pairs), and ``joint_torques``
(``JOINT_TORQUES``, nv): the generalised forces of the joint limits (with the ropes'), of
the friction losses and of the couplings in the last step (their impulses over dt, as
``contact.step.ContactStep``'s ``limit_torques``, ``friction_torques`` and
``coupling_torques``); each contact's signed distance (``depth``, NaN for a compliant one)
and the configuration's correction out of the contacts' penetrations (``shift`` (nv,),
K43); the couplings' errors (``errors``, scratch of K45a); the ropes' bounds that are rows
of the step (``rrows``, ``contact.ropes.rope_bounds``) and the scratch of their ends'
relative velocity (``rates``, K46)."""

MARGIN, STABILIZATION, FRICTION, WARM, FIRST, ACCEPT, PATCH = range(7)
PARAMS = 7
"""``params``: the margin, the stabilization, the ground's friction, warm start (1) or not,
the solver tried first (``contact.solver``'s code), the residual a step may end with
(``ContactSettings.accept``), the narrowest patch; then the solver's ``ncp.SETTINGS``."""
REPORT = 4
"""The report of the last contact step: ``[iterations (both solvers), primal, dual,
complementarity]`` (zeros for a step without a contact problem)."""
LIMIT_TORQUE, FRICTION_TORQUE, COUPLING_TORQUE = range(3)
JOINT_TORQUES = 3
"""The generalised forces a step keeps (``joint_torques``' rows): the joint limits' (with
the ropes'), the friction losses', the couplings'."""
KEPT = 3
"""A kept row's columns: the contacts' number, the solvers' iterations and the largest
residual of the step (``rollout._keep_contacts``, which writes the slots' forces and the
joint limits', friction losses' and couplings' generalised forces into arrays of their
own)."""


WORLDS_KEPT = 16
"""How many ``world_arrays`` results are kept for the next calls (``_WORLDS``)."""
_WORLDS: dict[tuple, tuple] = {}


def world_arrays(model, collisions, world, contact, joint_limits: bool = True,
                 friction_loss: bool = True, robot_joints: int | None = None,
                 couplings: bool = True) -> tuple:
    """The tuple the loop reads (the module's docstring), with the settings of
    ``contact`` (a ``ContactSettings``); the joints from ``robot_joints`` on (default: none)
    are the World's free bodies. Made once per model, collision model, world and settings
    and kept (the last ``WORLDS_KEPT``): a controller that calls ``simulate`` at every
    period with the same scene would otherwise build them again each time (the candidate
    pairs, the shapes' bounding radii and frames), half of such a call's own cost. Each
    input is immutable: a model's arrays are read-only, a collision model is made from
    frozen records (``compliant`` and ``on`` return new ones), a world and settings are
    frozen records, compared by value (a world of free bodies by identity)."""
    try:
        scene = hash(world)
        scene = world
    except TypeError:  # a world of bodies whose records hold arrays: by identity
        scene = id(world)
    key = (id(model), id(collisions), scene, contact, joint_limits, friction_loss,
           robot_joints, couplings)
    found = _WORLDS.get(key)
    if found is not None:  # the entry holds the objects, so their ids are still theirs
        return found[1]
    arrays = _world_arrays(model, collisions, world, contact, joint_limits, friction_loss,
                           robot_joints, couplings)
    if len(_WORLDS) >= WORLDS_KEPT:
        _WORLDS.clear()
    _WORLDS[key] = ((model, collisions, world), arrays)
    return arrays


def _world_arrays(model, collisions, world, contact, joint_limits: bool,
                  friction_loss: bool, robot_joints: int | None, couplings: bool) -> tuple:
    """``world_arrays``, made anew."""
    from ..contact.couplings import coupling_rows
    from ..contact.limits import joint_frictions, tendon_arrays
    from ..contact.limits import joint_limits as limits_of
    from ..contact.pairs import bounding_radii
    from ..contact.ropes import ROPE_COLUMNS, rope_arrays
    from ..contact.solve import _settings
    from ..contact.step import ground_frame
    from ..contact.world import touches_ground

    cm = collisions
    active = touches_ground(model, cm, world)
    first = ADMM if contact.solver == "admm" else PGS
    params = np.concatenate([[contact.margin, contact.stabilization, world.friction,
                              float(contact.warm_start), first, contact.accept,
                              contact.patch],
                             _settings(contact.tolerance, 0.0, contact.max_iterations, False,
                                       1e-6)])
    return WorldArrays(
        np.ascontiguousarray(cm.kinds), np.ascontiguousarray(cm.sizes, dtype=float),
        np.ascontiguousarray(cm.vertices, dtype=float), np.ascontiguousarray(cm.offsets),
        *_joint_frames(model, cm),
        np.ascontiguousarray(cm.links, dtype=np.int64), active,
        np.array(world.plane.packed_size, dtype=float), np.eye(4),
        ground_frame(world.ground_normal), params,
        np.ascontiguousarray(limits_of(model) if joint_limits
                             else np.zeros((0, LIMIT_COLUMNS))), tendon_arrays(model),
        joint_frictions(model) if friction_loss else np.zeros((0, model.nv + 1)),
        coupling_rows(model)[:len(model.coupling_names) if couplings else 0],
        rope_arrays(model) if joint_limits else np.zeros((0, ROPE_COLUMNS)),
        np.ascontiguousarray(cm.compliance, dtype=float), bounding_radii(cm),
        *pair_world(model, cm, world, model.njoints if robot_joints is None
                    else robot_joints))


def _joint_frames(model, cm) -> tuple[np.ndarray, np.ndarray]:
    """Each shape's placement in the frame of its link's joint, the top three rows of its
    homogeneous matrix (shapes, 3, 4), and that joint (shapes,), -1 where the link is fixed
    to the world (the placement then the world's) or the shape is the world's own: the link
    placement composed once here, so that a step moves each shape by its joint's world
    motor alone (``_detect``)."""
    n = len(cm.links)
    frames, joints = np.empty((n, 3, 4)), np.full(n, -1, dtype=np.int64)
    for s, link in enumerate(np.asarray(cm.links)):
        T = np.asarray(cm.placements[s], dtype=float)
        if link >= 0:
            T = model.link_placement_matrices[link] @ T
            joints[s] = model.link_joint[link]
        frames[s] = T[:3]
    return frames, joints


def slots(shapes: int) -> int:
    """The contact slots of ``shapes`` shapes: ``MAX_CONTACTS`` each."""
    return C.MAX_CONTACTS * shapes


@serial
def scratch_size(n, nq, nv, nl, shapes, limits, frictions, couplings, ropes, nr):
    """Floats of one rollout's contact scratch (``carve_scratch``) for ``shapes`` shapes,
    ``limits`` joint limits (two bounds each), ``frictions`` friction losses,
    ``couplings`` couplings, ``ropes`` ropes (two bounds each) and ``nr`` rows of
    bilateral constraints."""
    K = C.MAX_CONTACTS * shapes
    L = 2 * limits
    F = frictions + couplings + 2 * ropes  # the other interval rows with a slot each
    m = 3 * K + L + F + nr
    return (shapes * 16 + shapes * C.MAX_CONTACTS * C.OUT + shapes
            + C.CANDIDATES * C.CANDIDATE_COLUMNS + shapes * 12
            + m * nv + 2 * m * m + 3 * m + SCRATCH_ROWS * max(m, 6) + K + ncp.INFO
            + ncp.SETTINGS + 2 * K * 3 + K + 2 + REPORT
            + L * ROW_COLUMNS + 2 * (L + F + nr) + 2 * (L + F)
            + constraint_workspace_size(n, nq, nv, nl, m) + n * 12 + 2
            + JOINT_TORQUES * nv + 1 + K
            + nv + couplings + 2 * ropes * ROPE_ROW + 6)


@serial
def carve_scratch(world, buf, n, nq, nv, nl, nr):
    """The world of ``world_arrays`` and a rollout's scratch carved from ``buf``
    (``scratch_size``, ``nr`` rows of bilateral constraints), as one tuple."""
    shapes = world.kinds.shape[0]
    K = C.MAX_CONTACTS * (shapes + pair_count(world.pairs))  # the pairs' slots after the shapes'
    L = 2 * world.limits.shape[0]
    E = world.couplings.shape[0]
    P = 2 * world.ropes.shape[0]
    F = world.frictions.shape[0] + E + P  # the friction rows' slots, couplings', ropes'
    m = 3 * K + L + F + nr
    p = ws.data_pointer(buf)
    poses, o = ws.carve(p, 0, (shapes, 4, 4))
    out, o = ws.carve(p, o, (shapes, C.MAX_CONTACTS, C.OUT))
    counts, o = ws.carve(p, o, (shapes,))
    cand, o = ws.carve(p, o, (C.CANDIDATES, C.CANDIDATE_COLUMNS))
    big, o = ws.carve(p, o, (m * nv + 2 * m * m + 3 * m + SCRATCH_ROWS * max(m, 6),))
    mu, o = ws.carve(p, o, (K,))
    info, o = ws.carve(p, o, (ncp.INFO,))
    settings, o = ws.carve(p, o, (ncp.SETTINGS,))
    prev, o = ws.carve(p, o, (K, 3))
    force, o = ws.carve(p, o, (K, 3))
    had, o = ws.carve(p, o, (K,))
    count, o = ws.carve(p, o, (3,))
    report, o = ws.carve(p, o, (REPORT,))
    cwork, o = ws.carve(p, o, (constraint_workspace_size(n, nq, nv, nl, m),))
    lrows, o = ws.carve(p, o, (L, ROW_COLUMNS))
    bounds, o = ws.carve(p, o, (L + F + nr, 2))
    lprev, o = ws.carve(p, o, (L + F,))  # the limits' slots, the friction rows', the couplings'
    lhad, o = ws.carve(p, o, (L + F,))
    twists, o = ws.carve(p, o, (shapes, 2, 6))
    bodies, o = ws.carve(p, o, (n, 2, 6))
    factored, o = ws.carve(p, o, (2,))
    joint_torques, o = ws.carve(p, o, (JOINT_TORQUES, nv))
    depth, o = ws.carve(p, o, (K,))
    shift, o = ws.carve(p, o, (nv,))
    errors, o = ws.carve(p, o, (E,))
    rrows, o = ws.carve(p, o, (P, ROPE_ROW))
    rates, o = ws.carve(p, o, (2, 3))
    ps = carve_pairs(world.pairs, p, o)
    for k in range(K):
        had[k] = 0.0
        for i in range(3):
            prev[k, i] = 0.0
            force[k, i] = 0.0
    for k in range(L + F):
        lhad[k], lprev[k] = 0.0, 0.0
    count[0] = count[1] = count[2] = 0.0
    factored[0], factored[1] = 0.0, 1.0
    return ContactScratch(_bare_world(world), poses, out, counts, cand, big, mu, info,
                          settings, prev, force, had, count, report, cwork, lrows, bounds,
                          lprev, lhad, twists, bodies, factored, ps, joint_torques, depth,
                          shift, errors, rrows, rates)


@serial
def _bare_world(wa):
    """The ``WorldArrays`` with each array a bare view of it (``_views.carve``: no owner):
    the loop hands the world down its calls at every step, and each array that owns its
    memory would have its reference count raised and dropped, a call into numba's runtime,
    at each. Valid while ``wa`` lives (the rollout's argument)."""
    return WorldArrays(
        _bare(wa.kinds), _bare(wa.sizes), _bare(wa.vertices), _bare(wa.offsets),
        _bare(wa.frames), _bare(wa.joints), _bare(wa.links), _bare(wa.active),
        _bare(wa.ground), _bare(wa.ground_pose), _bare(wa.frame), _bare(wa.params),
        _bare(wa.limits), _bare(wa.tendons), _bare(wa.frictions), _bare(wa.couplings),
        _bare(wa.ropes), _bare(wa.compliance), _bare(wa.radii),
        _bare_or_none(wa.pairs), _bare_or_none(wa.shape_friction))


@inline
def _bare(x):
    """A C-contiguous array as a bare view of its data, of its shape."""
    return ws.carve(ws.data_pointer(x), 0, x.shape)[0]


@serial
def _bare_or_none(x):
    """``_bare(x)``, None for None (a world without pairs)."""
    if x is None:
        return None
    return _bare(x)


@serial
def _shape_twists(m, Sw, links, v, vn, twists, bodies):
    """``twists[s]``: the world twists ``[v, ω]`` of shape ``s``'s link at the velocities
    ``v`` and ``vn``, zeros for a shape that does not move (K21a): ``bodies[j]``, each
    joint's ``V_j = V_λ + Σ S_k v_k`` (C1's columns ``Sw``), once per joint down the tree."""
    for j in range(m.n):
        p = m.parents[j]
        for t in range(2):
            for i in range(6):
                bodies[j, t, i] = bodies[p, t, i] if p >= 0 else 0.0
        for k in range(m.iv[j], m.iv[j + 1]):
            for i in range(6):
                bodies[j, 0, i] += Sw[k, i] * v[k]
                bodies[j, 1, i] += Sw[k, i] * vn[k]
    for s in range(links.shape[0]):
        j = m.link_joint[links[s]] if links[s] >= 0 else -1
        for t in range(2):
            for i in range(6):
                twists[s, t, i] = bodies[j, t, i] if j >= 0 else 0.0


@inline
def _factor(m, q, H, work):
    """``H = M(q)`` by CRBA, then its factors ``Lᵀ D L`` in place (L1-L2). A status:
    ``SINGULAR`` at the joint of a pivot that is not positive."""
    status = crba_core(m, q, H, work)
    if status != OK:
        return status
    k = ltdl(m, H)
    return fault(SINGULAR, m.dof_joint[k]) if k >= 0 else OK


@core
def factored_dynamics(m, factored, cwork, q, v, tau, f, qdd, zero, work):
    """``qdd = M⁻¹ (τ - h)``: ``h = RNEA(q, v, 0)`` with the wrenches ``f`` (Algorithm 2),
    ``M`` by CRBA into the world's constraint workspace and factored there (``H = Lᵀ D
    L``, L1-L2; ``cwork``, flags in ``factored``), where ``contact_velocity`` finds it
    at the same ``q``: one factorisation of M serves the free velocity (K20), the Delassus
    operator (K23, L7) and the impulses' velocity change (K24), where ABA and then CRBA
    computed the same inertias twice. Where the step before had no contact, limit or
    friction row (a robot in the air), ABA alone, cheaper than RNEA, CRBA and the factors,
    which the contact step then forms only if it needs them. ``zero`` (nv) holds zeros. A
    status: ``SINGULAR`` at the joint of a pivot that is not positive."""
    factored[0] = 0.0
    if factored[1] == 0.0:
        return aba_core(m, q, v, tau, f, qdd, work)
    k_ = constraint_workspace(ws.data_pointer(cwork), m, 0)
    status = rnea_core(m, q, v, zero, f, qdd, work)  # h, into qdd
    if status != OK:
        return status
    status = _factor(m, q, k_.H, work)
    if status != OK:
        return status
    for i in range(m.nv):
        qdd[i] = tau[i] - qdd[i]
    ltdl_solve(m, k_.H, qdd)  # L5, L6
    factored[0] = 1.0
    return OK


@core
def contact_velocity(m, world, q, v, vn, dt, work, con, sc):
    """``vn``: ``v_free`` in, ``v⁺`` out (the module's docstring; K20-K25); the forces of
    the contacts into the slots of ``force`` (world frame, λ / dt; zero where none), their
    number into ``count``, the solvers' report into ``report``. A status:
    ``CONTACT_UNSOLVED`` where neither solver converges and a residual exceeds
    ``accept``, ``CONTACT_PAIR`` (at the pair's index) where a pair's penetration depth is
    not computed. With bilateral constraints (``con``, ``rollout._bind``'s; None for none),
    their rows follow the others, unbounded, and hold ``J v⁺ = J v_free``: the free
    velocity satisfies them (the constrained dynamics, C6-C7), and the impulses may not
    break them (C14); their impulses over dt are added to the forces λ of the state in
    ``sc.X``."""
    w_ = world
    k_ = constraint_workspace(ws.data_pointer(w_.cwork), m, 0)
    _world_columns(m, q, v, False, k_)  # the joints' world motors and Jacobian columns
    nc, nl, nrp, failed = _detect(m, w_, k_, q, v, vn, dt)
    if failed >= 0:  # a pair's depth not computed: stop rather than go on without it
        return fault(CONTACT_PAIR, failed)
    nf, ne = w_.world.frictions.shape[0], w_.world.couplings.shape[0]
    n0, n1, n2, n3, end = row_starts(nc, nl, nf, ne, nrp)
    for k in range(w_.force.shape[0]):  # the slots read (``had``): zero unless _keep writes
        if w_.had[k] != 0.0:
            for i in range(3):
                w_.force[k, i] = 0.0
    w_.count[0], w_.count[1], w_.count[2] = nc, nl, 0.0  # correct_positions reads the last two
    for i in range(REPORT):
        w_.report[i] = 0.0
    for i in range(JOINT_TORQUES):
        for k in range(m.nv):
            w_.joint_torques[i, k] = 0.0
    w_.factored[1] = 1.0 if end > 0 else 0.0
    if end == 0:
        for k in range(w_.had.shape[0]):
            w_.had[k] = 0.0
        for k in range(w_.lhad.shape[0]):
            w_.lhad[k] = 0.0
        return OK
    mc = end + bilateral_count(con)
    p = ws.data_pointer(w_.big)
    J, o = ws.carve(p, 0, (mc, m.nv))
    G, o = ws.carve(p, o, (mc, mc))
    Cs, o = ws.carve(p, o, (mc, mc))
    g, o = ws.carve(p, o, (mc,))
    lam, o = ws.carve(p, o, (mc,))
    R, o = ws.carve(p, o, (mc,))
    w = ws.carve(p, o, (SCRATCH_ROWS, max(mc, 6)))[0]
    k_ = constraint_workspace(ws.data_pointer(w_.cwork), m, mc)
    warm = _rows(m, w_, k_, nc, nl, nrp, J, lam, R, dt)
    status = _bilateral(m, con, q, v, J, w_.bounds, lam, end, end - n0, sc)
    if status != OK:
        return status
    if w_.factored[0] == 0.0:  # the free velocity came from ABA: M's factors here
        status = _factor(m, q, k_.H, work)
        if status != OK:
            return status
    _delassus(m, J, k_, G)  # G = J M⁻¹ Jᵀ from M's factors (L7)
    _free_term(m, w_, nc, nl, nrp, J, g, R, vn, dt)
    for r in range(end, mc):
        g[r] = 0.0  # J v⁺ = J v_free on the bilateral rows (C14)
    status = _solve(w_, nc, mc - n0, warm, G, g, lam, R, Cs, w)
    if status != OK:
        return status
    _correction(m, w_, k_, nc, J, G, g, lam, dt, w)  # K43, applied after the step
    _rope_correction(m, w_, k_, n3, nrp, J, G)  # K46a, likewise
    _keep_bilateral(con, lam, end, dt, sc)
    return _keep(m, w_, k_, nc, nl, nrp, J, lam, vn, dt)


@core
def correct_positions(m, world, qn, tmp, dq, qs):
    """``qn``, the configuration after the step, with each coordinate that the step began
    past a joint limit moved back by the fraction ``stabilization`` of its overshoot
    (``contact.limits.limit_shift``, K26a), then moved by the contacts' correction
    ``shift`` where the step left one (``qn ⊕ δ``, K43; ``qs`` and ``dq`` scratch); nothing
    without a world (None: pruned). A core, as ``contact_velocity``: the scratch it takes
    holds some forty arrays, and a function with reference counts raised and dropped each
    of them at every step; the joints' exponentials are a core of their own
    (``algorithms.manifold.integrate_joints``), called only on a step that leaves a
    correction."""
    if world is None:
        return
    wa = world.world
    limit_shift(wa.limits, wa.tendons, world.lrows, int(world.count[1]),
                wa.params[STABILIZATION], qn)
    if world.count[2] != 0.0:
        integrate_joints(m, qn, world.shift, 1.0, tmp, dq, qs)  # qs = qn ⊕ δ
        for i in range(m.nq):
            qn[i] = qs[i]
    coupling_shift(wa.couplings, wa.params[STABILIZATION], qn, world.errors)  # K45a


@serial
def bilateral_count(con):
    """The rows of a rollout's bilateral constraints (``con``: ``rollout._bind``'s), 0 for
    none (None: pruned, no constraint code compiled)."""
    if con is None:
        return 0
    cons, settings, cwork = con
    return int(cons[1])


@serial
def _bilateral(m, con, q, v, J, bounds, lam, r0, b0, sc):
    """Rows ``r0..`` of J: the constraints' Jacobian at q (C1, C2), unbounded (``bounds``
    from ``b0``), their λ from zero. A status: ``NONFINITE_RESULT`` where J is not finite.
    Nothing without constraints (``con`` None)."""
    if con is None:
        return OK
    cons, settings, cwork = con
    nr = int(cons[1])
    k_ = constraint_workspace(ws.data_pointer(cwork), m, nr)
    Jc = ws.carve(ws.data_pointer(J), r0 * m.nv, (nr, m.nv))[0]
    constraint_system(m, cons, q, v, False, Jc, sc.gam, k_)
    for r in range(nr):
        lam[r0 + r] = 0.0
        bounds[b0 + r, 0], bounds[b0 + r, 1] = -math.inf, math.inf
        for k in range(m.nv):
            if not math.isfinite(Jc[r, k]):
                return fault(NONFINITE_RESULT, -1)
    return OK


@serial
def _keep_bilateral(con, lam, r0, dt, sc):
    """The bilateral rows' impulses over dt added to the state's constraint forces λ
    (``sc.X[2]``, written by ``rollout._record``); nothing without constraints."""
    if con is None:
        return
    cons, settings, cwork = con
    for r in range(int(cons[1])):
        sc.X[2, r] += lam[r0 + r] / dt


@inline
def _detect(m, w_, k_, q, v, vn, dt):
    """The shapes' poses, each its joint's world motor (as R, p) times its placement in that
    joint's frame (K10, ``_joint_frames``); their contacts
    with the ground and with each other whose gap the step may close (K21, K21a, K22, K37,
    K39) into ``out``, ``counts`` and the pairs' scratch; the joint limits' bounds near which
    the step may go into ``lrows`` (K26), the ropes' into ``rrows`` (K46). Returns
    ``(contacts, limit rows, rope rows, the first pair whose distance was not computed or
    -1)``."""
    wa = w_.world
    links, poses, frames = wa.links, w_.poses, wa.frames
    for s in range(links.shape[0]):
        j = wa.joints[s]
        if j < 0:
            for i in range(3):
                for c in range(4):
                    poses[s, i, c] = frames[s, i, c]
        else:
            r, p = rigid_frame(k_.Mw[j])
            for c in range(4):
                x0, x1, x2 = rigid_rotate(r, frames[s, 0, c], frames[s, 1, c], frames[s, 2, c])
                poses[s, 0, c] = x0 + p[0] if c == 3 else x0
                poses[s, 1, c] = x1 + p[1] if c == 3 else x1
                poses[s, 2, c] = x2 + p[2] if c == 3 else x2
        for c in range(4):
            poses[s, 3, c] = 1.0 if c == 3 else 0.0
    _shape_twists(m, k_.Sw, links, v, vn, w_.twists, w_.bodies)
    params = wa.params
    C.shapes_on_plane(wa.kinds, wa.sizes, wa.vertices, wa.offsets, poses, wa.radii,
                      wa.active, wa.compliance, wa.ground, wa.ground_pose, params[MARGIN],
                      params[PATCH], w_.cand, w_.out, w_.counts, w_.twists,
                      dt)  # K21, K21a, K22, K22'
    nc = 0
    for s in range(links.shape[0]):
        nc += int(w_.counts[s])
    nc += detect_pairs(wa.pairs, wa.radii, w_.pairs, wa.kinds, wa.sizes, wa.vertices,
                       wa.offsets, poses, params[MARGIN], params[PATCH], w_.twists,
                       dt)  # K21a, K37, K39
    nl = active_limits(wa.limits, wa.tendons, q, v, vn, dt, params[MARGIN],
                       w_.lrows)  # K26, K26', K26''
    nr = 0
    for i in range(wa.ropes.shape[0]):  # K46
        p1 = rope_point(wa.ropes, i, 0, k_.Mw)
        p2 = rope_point(wa.ropes, i, 1, k_.Mw)
        rope_rates(wa.ropes, i, w_.bodies, p1, p2, w_.rates)
        nr = rope_bounds(wa.ropes, i, p1, p2, w_.rates, dt, params[MARGIN], w_.rrows, nr)
    return nc, nl, nr, failed_pair(wa.pairs, w_.pairs)


@inline
def _rows(m, w_, k_, nc, nl, nrp, J, lam, R, dt):
    """The rows of J, each warm-started in ``lam`` from its slot's λ of the previous step
    (K25): ``(t₁, t₂, n)`` per contact point with the ground, held in the ground frame
    (K23) at the plane's point under the shape's (K42); the pairs' (K37); ``±e_v`` (a
    cone's ``-aᵀ``) per limit bound near which the step may go, ``λ >= 0`` (K26); ``e_k``
    per friction loss, ``|λ| <= f dt`` (K30), the interval rows' bounds into
    ``bounds``; ``a_c`` per coupling, unbounded (K45); ``±u · (J_p₁ - J_p₂)`` per rope
    bound near which the step may go, ``λ >= 0`` (K46). ``R`` zeros. Whether any row
    starts from a previous λ."""
    wa = w_.world
    links, out, frame, prev, had = wa.links, w_.out, wa.frame, w_.prev, w_.had
    lrows, bounds, lprev, lhad = w_.lrows, w_.bounds, w_.lprev, w_.lhad
    shapes, nf, L = links.shape[0], wa.frictions.shape[0], 2 * wa.limits.shape[0]
    ne = wa.couplings.shape[0]
    n0, n1, n2, n3, _ = row_starts(nc, nl, nf, ne, nrp)
    for r in range(J.shape[0]):
        R[r] = 0.0
        for k in range(m.nv):
            J[r, k] = 0.0
    c = 0
    warm = False
    for s in range(shapes):
        for j in range(int(w_.counts[s])):
            r0 = 3 * c
            d = out[s, j, 3]  # the plane's point under the shape's (K42)
            at = (out[s, j, 0] - d * frame[2, 0], out[s, j, 1] - d * frame[2, 1],
                  out[s, j, 2] - d * frame[2, 2])
            _add_columns(k_.Sw, m.parents, m.iv, m.link_joint[links[s]], 1.0, at, 3, r0, J,
                         k_.T[0], False)
            for k in range(m.nv):
                x, y, z = J[r0, k], J[r0 + 1, k], J[r0 + 2, k]
                for i in range(3):
                    J[r0 + i, k] = frame[i, 0] * x + frame[i, 1] * y + frame[i, 2] * z
            w_.mu[c] = ground_friction(wa.shape_friction, s, wa.params[FRICTION])  # K38
            slot = C.MAX_CONTACTS * s + j
            for i in range(3):
                lam[r0 + i] = prev[slot, i] if had[slot] != 0.0 else 0.0
            if had[slot] != 0.0:
                warm = True
            c += 1
    c, warm_pairs = pair_rows(wa.pairs, wa.shape_friction, w_.pairs, m, k_.Sw, links, J,
                              w_.mu, lam, prev, had, c, shapes)
    warm = warm or warm_pairs
    for k in range(nl):
        r, slot = n0 + k, int(lrows[k, ROW_SLOT])
        limit_row(lrows, k, wa.tendons, J, r)  # ±e_v, a cone's -aᵀ on ω, a tendon's ±c
        lam[r] = lprev[slot] if lhad[slot] != 0.0 else 0.0
        if lhad[slot] != 0.0:
            warm = True
        bounds[r - n0, 0], bounds[r - n0, 1] = 0.0, math.inf
    for k in range(nf):
        r, slot = n1 + k, L + k
        for i in range(m.nv):  # e_k, or a tendon's c
            J[r, i] = wa.frictions[k, i]
        lam[r] = lprev[slot] if lhad[slot] != 0.0 else 0.0
        if lhad[slot] != 0.0:
            warm = True
        bounds[r - n0, 0], bounds[r - n0, 1] = -dt * wa.frictions[k, m.nv], \
            dt * wa.frictions[k, m.nv]
    for k in range(ne):
        r, slot = n2 + k, L + nf + k
        for i in range(m.nv):
            J[r, i] = wa.couplings[k, i]
        lam[r] = lprev[slot] if lhad[slot] != 0.0 else 0.0
        if lhad[slot] != 0.0:
            warm = True
        bounds[r - n0, 0], bounds[r - n0, 1] = -math.inf, math.inf
    for k in range(nrp):  # K46
        r, slot = n3 + k, L + nf + ne + int(w_.rrows[k, ROPE_SLOT])
        rope_row(m, k_.Sw, wa.ropes, w_.rrows, k, J, r)
        lam[r] = lprev[slot] if lhad[slot] != 0.0 else 0.0
        if lhad[slot] != 0.0:
            warm = True
        bounds[r - n0, 0], bounds[r - n0, 1] = 0.0, math.inf
    return warm


@inline
def _free_term(m, w_, nc, nl, nrp, J, g, R, vn, dt):
    """``g = J v_free`` with the gap's term on the ground contacts' normal rows (K23), or a
    compliant shape's spring and damper with its compliance in ``R`` (K41), the pairs' and
    the limit rows' gap terms (K37, K26); each contact's signed distance into ``depth``
    (NaN for a compliant one: K43 leaves it to its spring)."""
    wa = w_.world
    for r in range(J.shape[0]):
        acc = 0.0
        for k in range(m.nv):
            acc += J[r, k] * vn[k]
        g[r] = acc
    c = 0
    for s in range(wa.kinds.shape[0]):
        for j in range(int(w_.counts[s])):
            d, k, damping = w_.out[s, j, 3], wa.compliance[s, 0], wa.compliance[s, 1]
            term, R[3 * c + 2] = normal_row(d, k, damping, dt)
            g[3 * c + 2] += term
            w_.depth[c] = d if k == 0.0 and damping == 0.0 else math.nan
            c += 1
    pair_gaps(wa.pairs, w_.pairs, g, w_.depth, c, dt)
    n0, _, _, n3, _ = row_starts(nc, nl, wa.frictions.shape[0], wa.couplings.shape[0], nrp)
    for k in range(nl):
        g[n0 + k] += limit_gap(w_.lrows, k, dt)  # K26, K26a
    for k in range(nrp):
        g[n3 + k] += open_gap(w_.rrows[k, ROPE_GAP], dt)  # K46


@inline
def _solve(w_, nc, ni, warm, G, g, lam, R, Cs, w):
    """λ by the solver ``params`` names first (from the warm start where ``warm`` and the
    settings allow it, else from zero), then by the other from the first one's λ where the
    first stops short (K18); the report of both into ``report``; ``ni`` interval rows
    after the cones' (``bounds``). A status:
    ``CONTACT_UNSOLVED`` where neither converges and a residual exceeds ``accept``."""
    params, settings, info, report = w_.world.params, w_.settings, w_.info, w_.report
    for i in range(ncp.SETTINGS):
        settings[i] = params[PARAMS + i]
    settings[ncp.WARM] = 1.0 if warm and params[WARM] != 0.0 else 0.0
    if settings[ncp.WARM] == 0.0:
        for r in range(lam.shape[0]):
            lam[r] = 0.0
    muv, bv = w_.mu[:nc], w_.bounds[:ni]
    first = int(params[FIRST])
    solve_one(first, G, g, muv, bv, R, settings, lam, info, Cs, w)
    iterations = info[ncp.ITERATIONS]
    if info[ncp.CONVERGED] == 0.0:
        settings[ncp.WARM] = 1.0
        solve_one(PGS if first == ADMM else ADMM, G, g, muv, bv, R, settings, lam, info, Cs,
                  w)
        iterations += info[ncp.ITERATIONS]
    report[0], report[1], report[2], report[3] = iterations, info[ncp.PRIMAL], \
        info[ncp.DUAL], info[ncp.COMPLEMENTARITY]
    if info[ncp.CONVERGED] == 0.0 and max(report[1], report[2], report[3]) > params[ACCEPT]:
        return fault(CONTACT_UNSOLVED, -1)
    return OK


@inline
def _correction(m, w_, k_, nc, J, G, g, lam, dt, w):
    """The configuration's correction out of the rigid contacts' penetrations at the end
    of the step, ``δ = M⁻¹ J_Nᵀ μ`` (K43, ``contact.correction``) into ``shift``, from M's
    factors, and ``count[2] = 1``; nothing where no contact ends the step inside. ``w``:
    the solvers' scratch, free after them (its rows 0 and 1: ``b`` and ``μ``)."""
    b, mu = w[0, :nc], w[1, :nc]
    deepest = correction_targets(G, g, lam, w_.depth, nc, w_.world.params[STABILIZATION],
                                 dt, b)
    if not deepest > 0.0:
        return
    correction_impulses(G, nc, b, deepest, mu)
    shift = w_.shift
    for i in range(m.nv):
        acc = 0.0
        for c in range(nc):
            acc += J[3 * c + 2, i] * mu[c]
        shift[i] = acc
    ltdl_solve(m, k_.H, shift)
    w_.count[2] = 1.0


@inline
def _rope_correction(m, w_, k_, r0, nrp, J, G):
    """The configuration's correction out of the ropes stretched past a bound at the start
    of the step, added to ``shift`` (``count[2]`` then 1): ``β |d| M⁻¹ J_rᵀ / G_rr`` per
    such row ``r`` from ``r0`` (K46a), each the least displacement in M's metric that
    takes its row back by ``β |d|``, from M's factors; nothing where none is."""
    beta, dv = w_.world.params[STABILIZATION], k_.dq
    any_back = False
    for i in range(m.nv):
        dv[i] = 0.0
    for k in range(nrp):
        d = w_.rrows[k, ROPE_GAP]
        if d < 0.0 and G[r0 + k, r0 + k] > 0.0:
            c = -beta * d / G[r0 + k, r0 + k]
            for i in range(m.nv):
                dv[i] += c * J[r0 + k, i]
            any_back = True
    if not any_back:
        return
    ltdl_solve(m, k_.H, dv)
    if w_.count[2] == 0.0:
        for i in range(m.nv):
            w_.shift[i] = 0.0
    for i in range(m.nv):
        w_.shift[i] += dv[i]
    w_.count[2] = 1.0


@inline
def _add_torque(J, r, f, torques, i):
    """``torques[i] += J_rᵀ f``: a row's generalised force from its force ``f`` (its
    impulse over dt)."""
    for k in range(J.shape[1]):
        if J[r, k] != 0.0:
            torques[i, k] += J[r, k] * f


@inline
def _keep(m, w_, k_, nc, nl, nrp, J, lam, vn, dt):
    """``v⁺ = v_free + M⁻¹ Jᵀ λ`` into ``vn`` (K24); each row's λ kept in its slot for the
    next step's warm start (K25), the contacts' forces in ``force``. A status:
    ``NONFINITE_RESULT`` where v⁺ is not finite."""
    wa = w_.world
    had, lhad, lprev, lrows = w_.had, w_.lhad, w_.lprev, w_.lrows
    dv = k_.dq
    for i in range(m.nv):  # Jᵀ λ, then M⁻¹ Jᵀ λ from M's factors (L5, L6)
        acc = 0.0
        for r in range(lam.shape[0]):
            acc += J[r, i] * lam[r]
        dv[i] = acc
    ltdl_solve(m, k_.H, dv)
    for i in range(m.nv):
        vn[i] += dv[i]
    for k in range(had.shape[0]):
        had[k] = 0.0
    c = 0
    for s in range(wa.kinds.shape[0]):
        for j in range(int(w_.counts[s])):
            keep_slot(C.MAX_CONTACTS * s + j, lam, c, wa.frame, dt, w_.prev, had, w_.force)
            c += 1
    keep_pairs(wa.pairs, w_.pairs, lam, w_.prev, had, w_.force, c, wa.kinds.shape[0], dt)
    for k in range(lhad.shape[0]):
        lhad[k] = 0.0
    nf, ne = wa.frictions.shape[0], wa.couplings.shape[0]
    n0, n1, _, n3, _ = row_starts(nc, nl, nf, ne, nrp)
    for k in range(nl):  # τ_limit = Σ J_rᵀ λ_r / dt
        slot, r = int(lrows[k, ROW_SLOT]), n0 + k
        lhad[slot], lprev[slot] = 1.0, lam[r]
        _add_torque(J, r, lam[r] / dt, w_.joint_torques, LIMIT_TORQUE)
    L = 2 * wa.limits.shape[0]
    for k in range(nf + ne):  # the friction rows, then the couplings': their impulses kept
        lhad[L + k], lprev[L + k] = 1.0, lam[n1 + k]
    for r in range(n1, n3):  # τ_friction = Σ e_k λ / dt, τ_coupling = Σ a λ / dt
        _add_torque(J, r, lam[r] / dt, w_.joint_torques,
                    FRICTION_TORQUE if r < n1 + nf else COUPLING_TORQUE)
    for k in range(nrp):  # the ropes' bounds (K46), limits of a tendon's length
        slot = L + nf + ne + int(w_.rrows[k, ROPE_SLOT])
        lhad[slot], lprev[slot] = 1.0, lam[n3 + k]
        _add_torque(J, n3 + k, lam[n3 + k] / dt, w_.joint_torques, LIMIT_TORQUE)
    for i in range(m.nv):
        if not math.isfinite(vn[i]):
            return fault(NONFINITE_RESULT, -1)
    return OK
