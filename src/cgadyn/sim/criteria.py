"""The contacts and the physical criteria of each step of a rollout with contact, computed
after the run from what its ``Trajectory`` keeps (``docs/contact.md``, "The physical
criteria of a step", K31-K34).

The compiled loop keeps, for the step taken from each state ``(q_k, v_k)``, the world-frame
force of each contact slot (slot ``4 s + i``: the ``i``-th patch point of shape ``s`` on
the ground; ``4 (K + p) + i``: of the ``p``-th pair of shapes that may touch, K37) and
the free acceleration ``a_k`` (``v_free = v_k + dt a_k``, K20, with a free flyer's
``dt ω × v``, K24: ``algorithms.manifold.step_free_velocity``). From them this module finds
the step's contacts again at ``q_k`` (``world_contacts`` as the step finds them: each
point's gap at the end of the step at ``v_k`` and ``v_free`` below the margin, K21a, K22,
K37-K39, with ``ContactSettings.patch``), and with the next state's velocity ``v_{k+1}``,
which is ``v⁺`` moved into the frames of ``q_{k+1}`` (K24: ``step_moved_velocity`` at
``-dt`` moves it back),
their velocities after the step ``σ = J(q_k) v⁺`` plus the gap's term (K23), which is all
``contact.criteria.step_criteria`` needs.

The loop keeps forces by slot, not the points they act at. Where a shape's candidates tie
(a box flat on the ground: four corners at the same distance to rounding), the loop and
``ground_contacts`` may order the same patch points differently (K22), so each shape's slots
are matched to the points found again by the step's momentum: the contact impulses satisfy
``Σ J_cᵀ λ_c = M (v⁺ - v_free)`` on the coordinates no joint limit or friction loss acts on
(K24; a free flyer's six), and of the orderings of a shape's slots the one that satisfies it
best is kept (``CriteriaHistory.reordered`` counts the steps where it was not the order
found).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..algorithms.manifold import step_free_velocity, step_moved_velocity
from ..contact.criteria import CRITERIA, SLIP, contact_frame_forces, step_criteria

__all__ = ["ContactPoint", "ContactScene", "CriteriaHistory", "trajectory_contacts",
           "trajectory_criteria"]


@dataclass(frozen=True)
class ContactScene:
    """What a rollout with contact ran with, kept by ``simulate`` on its ``Trajectory``
    (``Trajectory.scene``) so that its contacts can be found again: the model, the collision
    model, the ``World`` and the ``ContactSettings``, the diagonal the step added to the
    mass matrix for its implicit gains (``dt D + dt² K``, K40; None without them) and the
    robot's joints (the model's joints from ``robot_joints`` on are the World's free
    bodies; None: no bodies)."""

    model: object = field(repr=False)
    collisions: object = field(repr=False)
    world: object
    settings: object
    step_inertia: object = field(default=None, repr=False)
    robot_joints: int | None = None


@dataclass(frozen=True)
class ContactPoint:
    """One contact of a kept state: the ``link`` and ``shape`` names, the contact ``point``
    on the shape (world frame), the ``normal`` (the ground's, or for a contact between two
    shapes from the ``other`` shape to this one), the signed ``distance`` (m; < 0 a
    penetration), the ``force`` on this shape there (world frame, N; of the ground, or of
    the other shape) in the step taken from that state, its ``slot`` (``4 s + i`` on the
    ground, ``4 (K + p) + i`` for pair ``p``, ``sim.pairs``), and the ``other`` shape's
    name (None for the ground)."""

    link: str
    shape: str
    point: np.ndarray
    normal: np.ndarray
    distance: float
    force: np.ndarray
    slot: int
    other: str | None = None


@dataclass(frozen=True)
class CriteriaHistory:
    """The criteria (K31-K34) of every step of a rollout, each the largest over the step's
    contacts (0 for a step without one, NaN for a step not taken): ``signorini`` (W),
    ``approach`` (m/s), ``cone`` (N), ``dissipation`` (W), ``friction_direction`` (N),
    ``penetration`` (m), each
    (steps,) or (B, steps) for B rollouts, for the steps from the states at ``t``;
    ``contacts`` the number of contacts of each step; ``unmatched``: the steps whose
    contacts found again differ from the loop's count (a candidate exactly at the margin;
    their criteria are those of the contacts found again); ``reordered``: the steps whose
    slots were matched to the points in another order than found (the module's docstring).
    ``maxima()`` gives the largest
    of each criterion over the run."""

    t: np.ndarray
    signorini: np.ndarray
    approach: np.ndarray
    cone: np.ndarray
    dissipation: np.ndarray
    friction_direction: np.ndarray
    penetration: np.ndarray
    contacts: np.ndarray
    unmatched: int = 0
    reordered: int = 0

    def maxima(self) -> dict[str, float]:
        """The largest value of each criterion over every step taken (``CRITERIA``)."""
        out = {}
        for name in CRITERIA:
            x = getattr(self, name)
            out[name] = float(np.nanmax(x)) if np.any(np.isfinite(x)) else 0.0
        return out


def _scene(traj) -> ContactScene:
    scene = getattr(traj, "scene", None)
    if scene is None or traj.contact_forces is None:
        raise ValueError("this Trajectory has no contact: its contacts and criteria come from "
                         "a rollout with a world, simulate(..., world=cgadyn.World(), "
                         "collisions=cgadyn.collision_model(model, ...))")
    return scene


def _rollout(traj, rollout):
    """``(q, v, a, forces, count)`` of one rollout of ``traj``."""
    if traj.batch:
        B = traj.q.shape[0]
        if isinstance(rollout, bool) or not isinstance(rollout, int | np.integer) or \
                not 0 <= rollout < B:
            raise ValueError(f"rollout must be an index in [0, {B}) for a Trajectory of "
                             f"{B} rollouts, got {rollout!r}")
        r = int(rollout)
        return (traj.q[r], traj.v[r], traj.a[r], traj.contact_forces[r],
                traj.contact_count[r])
    if rollout not in (None, 0):
        raise ValueError(f"rollout must be None (or 0) for a Trajectory of one rollout, got "
                         f"{rollout!r}")
    return traj.q, traj.v, traj.a, traj.contact_forces, traj.contact_count


def _found(scene: ContactScene, dt: float, q, v, a):
    """The contacts of the step taken from ``(q, v)`` (free acceleration ``a``), with the
    ground and between shapes (K21a, K22, K37-K39, as the step finds them), and the slot
    of each: ``4 s + i`` for shape ``s``'s ``i``-th point on the ground, ``4 (K + p) + i``
    for pair ``p``'s (``sim.pairs``)."""
    from ..contact.manifold import MAX_CONTACTS
    from ..contact.pairs import candidate_pairs
    from ..contact.world import world_contacts

    settings, cm = scene.settings, scene.collisions
    robot = scene.model.njoints if scene.robot_joints is None else scene.robot_joints
    pairs = candidate_pairs(cm, robot, scene.world.self_collision)
    contacts = world_contacts(scene.model, cm, q, scene.world, settings.margin, pairs, v,
                              step_free_velocity(scene.model, v, a, dt), dt,
                              settings.patch)  # v_free (K20, K24), K21a
    index = {(int(x), int(y)): p for p, (x, y) in enumerate(pairs)}
    slots = np.empty(len(contacts), dtype=np.int64)
    for i, (s, o) in enumerate(zip(contacts.collision, contacts.other, strict=True)):
        before = np.count_nonzero((contacts.collision[:i] == s) & (contacts.other[:i] == o))
        first = s if o < 0 else len(cm) + index[(int(s), int(o))]
        slots[i] = MAX_CONTACTS * first + before
    return contacts, slots


def _momentum_free(model) -> np.ndarray:
    """The velocity coordinates on which no row but the contacts' may act: no joint or
    tendon limit, friction loss, coupling or rope (K26, K30, K45, K46); there the contact
    impulses alone change the momentum in a step (K24)."""
    from ..contact.limits import CONE, CONE_LIMIT, JOINT, V, joint_frictions, joint_limits

    limits = joint_limits(model)
    busy = np.zeros(model.nv, dtype=bool)
    busy[limits[limits[:, CONE] == JOINT, V].astype(np.int64)] = True
    for k in limits[limits[:, CONE] == CONE_LIMIT, V].astype(np.int64):
        busy[k:k + 3] = True  # a cone's row reads its joint's three ω
    limited = np.isfinite(model.tendon_range).any(axis=1)
    rows = [joint_frictions(model)[:, :model.nv], model.coupling_coefficients,
            model.tendon_coefficients[limited]]
    busy |= np.any(np.concatenate(rows) != 0.0, axis=0)
    for link in model.rope_links.reshape(-1):  # a rope's ends: every joint above them
        j = int(model.link_joint[link]) if link >= 0 else -1
        while j >= 0:
            busy[model.joint_dofs(j).start:model.joint_dofs(j).stop] = True
            j = int(model.parents[j])
    return np.flatnonzero(~busy)


def _match(scene, dt, q, v, a, v_next, contacts, slots, forces, J) -> tuple[np.ndarray, bool]:
    """``slots`` reordered within each shape so that the slots' impulses at the points found
    satisfy the step's momentum best (the module's docstring); whether it changed them."""
    from itertools import permutations

    from ..algorithms import crba

    free = _momentum_free(scene.model)
    ends = np.stack([contacts.collision, contacts.other], axis=1)
    shapes = [np.flatnonzero((ends == e).all(axis=1)) for e in np.unique(ends, axis=0)]
    if free.size == 0 or all(len(p) < 2 for p in shapes):
        return slots, False
    frames = _frames(contacts)
    lam = contact_frame_forces(forces[slots], frames) * dt  # impulses, found order
    push = np.einsum("cin,ci->cn", J.reshape(-1, 3, J.shape[1])[:, :, free], lam)
    M = np.asarray(crba(scene.model, q))
    if scene.step_inertia is not None:  # the step's mass matrix (K40)
        M = M + np.diag(scene.step_inertia)
    target = (M @ (v_next - step_free_velocity(scene.model, v, a, dt)))[free]
    residual = target - push.sum(axis=0)
    tie = 1e-9 * (np.linalg.norm(target) + 1e-12)
    if np.linalg.norm(residual) <= tie:  # the order found satisfies it: no other needed
        return slots, False
    order = slots.copy()
    for points in shapes:
        if len(points) < 2:
            continue
        base = residual + push[points].sum(axis=0)  # without this shape's impulses
        best, best_norm = None, np.linalg.norm(residual) - tie
        for perm in permutations(range(len(points))):
            trial = slots[points[list(perm)]]
            lt = contact_frame_forces(forces[trial], frames[points]) * dt
            pt = np.einsum("cin,ci->cn", J.reshape(-1, 3, J.shape[1])[points][:, :, free], lt)
            norm = np.linalg.norm(base - pt.sum(axis=0))
            if norm < best_norm:
                best, best_norm, best_push = trial, norm, pt
        if best is not None:
            order[points] = best
            push[points] = best_push
            residual = base - best_push.sum(axis=0)
    return order, bool(np.any(order != slots))


def _frames(contacts) -> np.ndarray:
    """(nc, 3, 3): each contact's frame, rows ``(t₁, t₂, n)`` (``step.ground_frame``)."""
    from ..contact.step import ground_frame

    return np.array([ground_frame(n) for n in contacts.normal]).reshape(-1, 3, 3)


def _every_state(traj) -> bool:
    """Whether ``traj`` kept every state (``record_every=1``)."""
    t = np.asarray(traj.t)
    return t.size >= 2 and bool(np.allclose(np.diff(t[np.isfinite(t)]), traj.dt, rtol=1e-9,
                                            atol=0.0))


def trajectory_contacts(traj, k: int, rollout: int | None = None) -> list[ContactPoint]:
    """The contacts of kept state ``k`` of ``traj`` (a ``Trajectory`` of
    ``simulate(..., world=...)``; ``rollout``: which one of a batch): each shape's patch
    points at ``q_k`` (K21a, K22, as the step taken from it found them) with the force
    the ground put on the robot there in that step. Any ``record_every`` works; with every
    state kept the slots are matched to the points by the step's momentum (the module's
    docstring), else taken in the order found."""
    scene = _scene(traj)
    q, v, a, forces, count = _rollout(traj, rollout)
    rows = q.shape[0]
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or not -rows <= k < rows:
        raise ValueError(f"k must index a kept state, in [{-rows}, {rows}), got {k!r}")
    if not np.all(np.isfinite(q[k])) or count[k] < 0:
        raise ValueError(f"kept state {k} was not reached (the rollout stopped before it)")
    k = int(k) % rows
    contacts, slots = _found(scene, traj.dt, q[k], v[k], a[k])
    if k + 1 < rows and _every_state(traj) and np.all(np.isfinite(v[k + 1])):
        from ..contact.problem import contact_jacobian

        J = contact_jacobian(scene.model, q[k], contacts, _frames(contacts))
        slots, _ = _match(scene, traj.dt, q[k], v[k], a[k],
                          step_moved_velocity(scene.model, v[k + 1], -traj.dt), contacts, slots,
                          forces[k], J)
    model, cm = scene.model, scene.collisions
    return [ContactPoint(model.link_names[contacts.link[i]], cm[contacts.collision[i]].name,
                         contacts.point[i].copy(), contacts.normal[i].copy(),
                         float(contacts.distance[i]), forces[k, slots[i]].copy(),
                         int(slots[i]),
                         cm[contacts.other[i]].name if contacts.other[i] >= 0 else None)
            for i in range(len(contacts))]


def trajectory_criteria(traj, rollout: int | None = None, slip: float = SLIP
                        ) -> CriteriaHistory:
    """The criteria (K31-K34) of every step of ``traj`` (a ``Trajectory`` of
    ``simulate(..., world=...)`` with every state kept, ``record_every=1``: a step's
    criteria need the velocity after it, the next state's), recomputed in Python from the
    kept states and contact forces; ``rollout``: one rollout of a batch (None: all of
    them, (B, steps) arrays); ``slip``: as in ``step_criteria``."""
    from ..contact.problem import contact_compliance, contact_jacobian, gap_velocity

    scene = _scene(traj)
    dt = float(traj.dt)
    t = np.asarray(traj.t)
    if not _every_state(traj):
        raise ValueError("trajectory_criteria needs every state of the run (the velocity after "
                         "each step is the next state's): simulate with record_every=1 and "
                         "final_only=False")
    if traj.batch and rollout is None:
        parts = [trajectory_criteria(traj, r, slip) for r in range(traj.q.shape[0])]
        return CriteriaHistory(parts[0].t, *(np.array([getattr(p, n) for p in parts])
                                             for n in (*CRITERIA, "contacts")),
                               unmatched=sum(p.unmatched for p in parts),
                               reordered=sum(p.reordered for p in parts))
    q, v, a, forces, count = _rollout(traj, rollout)
    steps = q.shape[0] - 1
    out = {name: np.full(steps, np.nan) for name in CRITERIA}
    number = np.full(steps, -1, dtype=np.int64)
    unmatched = reordered = 0
    for k in range(steps):
        if not (np.all(np.isfinite(q[k + 1])) and np.all(np.isfinite(v[k + 1]))
                and count[k] >= 0):
            break  # the rollout stopped here
        contacts, slots = _found(scene, dt, q[k], v[k], a[k])
        nc = len(contacts)
        number[k] = nc
        unmatched += int(nc != count[k])
        frames = _frames(contacts)
        J = contact_jacobian(scene.model, q[k], contacts, frames)
        v_plus = step_moved_velocity(scene.model, v[k + 1], -dt)  # v⁺ in the frames of q_k
        slots, moved = _match(scene, dt, q[k], v[k], a[k], v_plus, contacts, slots,
                              forces[k], J)
        reordered += int(moved)
        sigma = (J @ v_plus).reshape(nc, 3)  # σ = J v⁺ (K20, K24)
        soft = contact_compliance(scene.collisions, contacts)
        sigma[:, 2] += gap_velocity(contacts.distance, dt, soft)[0]  # K23, K41
        crit = step_criteria(contact_frame_forces(forces[k, slots], frames), sigma,
                             contacts.distance, contacts.friction, slip)
        for name, value in crit.maxima().items():
            out[name][k] = value
    return CriteriaHistory(t[:steps], *(out[n] for n in CRITERIA), number, unmatched,
                           reordered)
