"""One velocity-level time step with frictional contact on the ground and joint limits
(docs/contact.md, K20, K23-K26, K30, K43).

``contact_step`` joins the pieces of ``cgadyn.contact``: the contact points of the robot's
shapes with the ground (K21-K22), each a point constraint of its link held in the ground's
frame ``(t₁, t₂, n)``, the contact problem of the step (K20, K23), its forces by ADMM or PGS
(K11-K19), the velocity after the step and the configuration moved on the manifold with it
(K24, semi-implicit Euler), then the configuration alone moved out of any penetration left
(K43). The joints' limits near which the step may take a coordinate are
one-row constraints ``λ >= 0`` of the same problem (K26, ``limits.py``), and so is each
joint's friction loss, ``|λ| <= f dt`` (K30). It is the step of Carpentier et al. (RSS 2024)
and of Pinocchio's and MuJoCo's simulators, called from Python: one step, one configuration.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .correction import correction_impulses, correction_targets
from .pairs import candidate_pairs, contact_frame
from .problem import contact_compliance, contact_jacobian, gap_velocity
from .settings import ContactSettings, other_solver, residual
from .world import Contacts, World, world_contacts

__all__ = ["ContactStep", "contact_step", "ground_frame"]


def ground_frame(normal) -> np.ndarray:
    """The rows ``(t₁, t₂, n)`` of the frame of a contact with unit normal ``n``: the
    ground's, or a pair's from ``b`` to ``a`` (``pairs.contact_frame``, K37); for a level
    ground the world's own axes."""
    n = np.asarray(normal, dtype=float)
    F = np.empty((3, 3))
    contact_frame(float(n[0]), float(n[1]), float(n[2]), F)
    return F


@dataclass(frozen=True)
class ContactStep:
    """The result of ``contact_step``: the state after the step ``q``, ``v``; the contacts
    found at the start of the step (``contacts``) and the force of each on its shape in the
    world frame (``forces`` (K, 3), the impulse over ``dt``; a pair contact's on its first
    shape, ``a``, K37); the joint torques of the
    limits (``limit_torques`` (nv,), their impulse over ``dt``; zero where no limit acts;
    a rope's among them, K46), of the friction losses (``friction_torques`` (nv,)) and of
    the couplings (``coupling_torques`` (nv,), K45);
    the solver's report (``info``, a ``ContactSolveInfo``; None without contacts or limits)
    and which solver gave the forces (``solver``); ``velocities`` (K, 3), each contact's
    velocity after the step in its frame ``(t₁, t₂, n)`` with the gap's term of K23 (an
    open gap's ``d / dt``),
    ``σ = G λ + g`` (K11), and ``criteria``, the step's physical criteria (K31-K34);
    ``collisions``, the collision model of the step (the robot's shapes, then the World's
    bodies' and obstacles', K36, K44) whose indices ``contacts.collision`` and
    ``contacts.other`` are."""

    q: np.ndarray
    v: np.ndarray
    contacts: Contacts = field(repr=False)
    forces: np.ndarray = field(repr=False)
    limit_torques: np.ndarray = field(repr=False, default=None)
    friction_torques: np.ndarray = field(repr=False, default=None)
    info: object = None
    solver: str = ""
    velocities: np.ndarray = field(repr=False, default=None)
    collisions: object = field(repr=False, default=None)
    coupling_torques: np.ndarray = field(repr=False, default=None)

    @property
    def criteria(self):
        """The physical criteria of this step (a ``ContactCriteria``, K31-K34), from its
        forces, its contact ``velocities`` and its contacts' distances."""
        from .criteria import contact_frame_forces, step_criteria

        frames = np.array([ground_frame(n) for n in self.contacts.normal]).reshape(-1, 3, 3)
        return step_criteria(contact_frame_forces(self.forces, frames), self.velocities,
                             self.contacts.distance, self.contacts.friction)


def contact_step(model, collisions, q, v, tau, dt: float, world: World | None = None,
                 contact: ContactSettings | None = None, passive: bool = True,
                 joint_limits: bool = True, friction_loss: bool = True,
                 couplings: bool = True) -> ContactStep:
    """One step of length ``dt`` from ``(q, v)`` under the joint torques ``tau`` (nv,)
    with the ground and obstacles of ``world`` (default: the static world of an MJCF's
    collisions, its floor and geoms, ``contact.static_world``, else ``World()``) touched
    by the shapes of ``collisions`` (``collision_model(model, ...)``; None: no shapes, for a
    ``World(ground=False)`` only), the joints' limits (``joint_limits``) and their friction
    loss (``friction_loss``). With ``World(bodies=[...])`` the bodies are links of the
    model (``bodies.with_bodies``, built once): ``q`` and ``v`` are then the whole model's
    (the robot's, then 7 and 6 per body), ``tau`` the robot's (nv,) or the whole model's,
    and the contacts include those between shapes of different links (K37-K39):

    ``contact`` (a ``ContactSettings``, default ``ContactSettings()``) holds the margin,
    the stabilization and the solvers' settings named below.

    1. the contacts whose gap, less the way the point may travel in the step at ``v`` or
       ``v_free``, is below ``margin``, no two of a patch closer than ``patch`` (K21-K22),
       each a point of its link (held in the world, or, for a pair, to the other shape's
       point, K37);
    2. the contact problem (K20, K23): ``G = J M⁻¹ Jᵀ`` and ``g = J v_free`` in each
       contact's frame ``(t₁, t₂, n)`` (``ground_frame``), with the normal velocity allowed
       to close an open gap within the step (``g_N + d / dt`` for ``d > 0``) and a
       penetration held where it is (nothing added for ``d < 0``: step 5 takes it back), or,
       on a shape made compliant
       (``CollisionModel.compliant``), a spring and damper's term and compliance (K41); with
       ``joint_limits``, after the contacts' rows, one row ``±e_v`` per bound of a joint of
       one coordinate (``limits.py``) whose gap is below ``margin`` plus ``|v_i| dt``, with
       ``λ >= 0`` and the open gap's term, none past the bound: the position update takes
       such a coordinate back by ``stabilization`` of its overshoot instead, adding no
       velocity (K26, K26a; joints of several coordinates get none); with
       ``friction_loss``, one row ``e_k`` per velocity coordinate with ``Model.friction``
       ``f > 0``, its impulse in ``[-f dt, f dt]`` (K30); with ``joint_limits`` also
       one row per bound of a rope (``Model.rope_*``) that the step may reach, ``λ >= 0``
       with the gap's term (K46); with ``couplings``, one
       unbounded row ``a`` per coupling of the model (``Model.coupling_coefficients``),
       ``σ = a · v⁺ = 0`` (K45);
    3. the impulses ``λ`` in the friction cones of ``World.friction`` by ``solver``
       (``"admm"`` or ``"pgs"``, ``solve_contacts``); where it does not converge (ADMM may
       cycle on redundant contacts with sliding, docs/contact.md), the other goes on from
       its last forces; where neither meets ``tolerance``, forces whose residuals are all
       at most ``accept`` are kept (``info.converged`` is then False);
    4. ``v⁺ = v_free + M⁻¹ Jᵀ λ`` and ``q⁺ = q ⊕ dt v⁺`` (K24; a free flyer's origin
       straight along the world vector of its linear part, K24a), ``v⁺`` then moved into
       the frames of ``q⁺`` (a free flyer's linear velocity, taken in the frame of ``q``
       through the step: ``v_free = v + dt (v̇ + ω × v)`` there, K24);
    5. where a rigid contact ends the step inside (``d + dt σ_N < 0``), ``q⁺`` moved by
       the smallest displacement in M's metric that takes every such penetration back by
       the fraction ``stabilization`` and takes no other inside (K43, ``correction.py``): a
       correction of the configuration alone, ``v⁺`` unchanged, so that a body started
       inside the ground rises to its surface and is not thrown; a rope stretched past its
       bound taken back by ``stabilization`` of the stretch likewise (K46a); then the
       couplings' coordinates moved by the least displacement that takes the fraction
       ``stabilization`` of their errors back (K45a).

    ``passive``: add the joints' damping and spring torques (``passive_torques``) as
    ``simulate`` does. Raises ``ValueError`` where the solvers end with a residual above
    ``accept`` (naming the residuals) or for bad input.
    """
    from ..algorithms import aba, crba, integrate
    from ..algorithms._inputs import time_step
    from ..algorithms.manifold import (
        step_free_velocity,
        step_moved_configuration,
        step_moved_velocity,
    )
    from ..algorithms.passive import passive_torques
    from .bodies import world_model
    from .couplings import coupling_rows, coupling_shift
    from .inputs import checked_collisions, checked_settings, checked_world
    from .limits import (
        LIMIT_COLUMNS,
        ROW_COLUMNS,
        active_limits,
        joint_frictions,
        limit_gap,
        limit_row,
        limit_shift,
        tendon_arrays,
    )
    from .limits import joint_limits as joint_limits_of
    from .problem import open_gap, row_starts
    from .ropes import GAP as ROPE_GAP
    from .ropes import ROPE_ROW, rope_system
    from .solve import solve_contacts
    from .static_world import default_world

    if world is None:  # an MJCF's own floor and geoms (K44), where collisions hold them
        world = default_world(collisions)
    world = checked_world(world, "contact_step")
    contact = checked_settings(contact, "contact_step")
    margin, stabilization = contact.margin, contact.stabilization
    step = time_step(dt)
    cm = checked_collisions(model, collisions, world, "contact_step")
    robot_joints, robot_nv = model.njoints, model.nv
    # the bodies are links of the model (K36), the obstacles shapes of the world (K44)
    model, cm = world_model(model, None if collisions is None else cm, world)[:2]
    q = np.asarray(q, dtype=float)
    v, tau = np.asarray(v, dtype=float), np.asarray(tau, dtype=float)
    if tau.shape == (robot_nv,) and robot_nv != model.nv:  # the bodies are not actuated
        tau = np.concatenate([tau, np.zeros(model.nv - robot_nv)])
    for name, x, size in (("v", v, model.nv), ("tau", tau, model.nv)):
        if x.shape != (size,):
            raise ValueError(f"{name}: expected shape ({size},) for {model.name!r}, got "
                             f"{x.shape}")
    for name, flag in (("joint_limits", joint_limits), ("friction_loss", friction_loss),
                       ("couplings", couplings)):
        if not isinstance(flag, bool):
            raise ValueError(f"{name} must be True or False, got {flag!r}")
    torque = tau + passive_torques(model, q, v) if passive else tau
    v_free = step_free_velocity(model, v, aba(model, q, v, torque), step)  # K20, K24
    # a gap that the step may close is a contact (K21a)
    pairs = candidate_pairs(cm, robot_joints, world.self_collision)  # K38
    contacts = world_contacts(model, cm, q, world, margin, pairs, v, v_free, step,
                              contact.patch)
    limits = joint_limits_of(model) if joint_limits else np.zeros((0, LIMIT_COLUMNS))
    rows = np.empty((2 * len(limits), ROW_COLUMNS))
    tendons = tendon_arrays(model)
    nl = active_limits(limits, tendons, q, v, v_free, step, float(margin), rows)  # K26
    frictions = joint_frictions(model) if friction_loss else np.zeros((0, model.nv + 1))
    tied = coupling_rows(model)[:len(model.coupling_names) if couplings else 0]
    ropes, rope_J = rope_system(model, q, v, v_free, step, float(margin)) if joint_limits \
        else (np.zeros((0, ROPE_ROW)), np.zeros((0, model.nv)))  # K46
    nc, nf, ne, nr = len(contacts), len(frictions), len(tied), len(ropes)
    if nc + nl + nf + ne + nr == 0:
        return ContactStep(step_moved_configuration(model, q, step * v_free),
                           step_moved_velocity(model, v_free, step), contacts,
                           np.zeros((0, 3)), np.zeros(model.nv), np.zeros(model.nv),
                           velocities=np.zeros((0, 3)), collisions=cm,
                           coupling_torques=np.zeros(model.nv))
    frames = np.array([ground_frame(n) for n in contacts.normal]).reshape(nc, 3, 3)  # K37
    n0, n1, n2, n3, end = row_starts(nc, nl, nf, ne, nr)  # the first limit, friction,
    J = np.zeros((end, model.nv))  # coupling and rope row
    J[:n0] = contact_jacobian(model, q, contacts, frames)  # K20, K37
    for k in range(nl):  # ±e_v, or -aᵀ on a cone-limited joint's ω (K26, K26')
        limit_row(rows, k, tendons, J, n0 + k)
    J[n1:n2] = frictions[:, :model.nv]  # K30: e_k, or a tendon's c
    J[n2:n3] = tied[:, :model.nv]  # K45
    J[n3:] = rope_J  # K46
    G = J @ np.linalg.solve(crba(model, q), J.T)  # G = J M⁻¹ Jᵀ (C7) over every row
    G = 0.5 * (G + G.T)
    g = J @ v_free
    stiffness = contact_compliance(cm, contacts)
    term, compliance = gap_velocity(contacts.distance, step, stiffness)  # K41
    g[3 * np.arange(nc) + 2] += term  # K23, K41
    g[n0:n1] += [limit_gap(rows, k, step) for k in range(nl)]  # K26, K26a
    g[n3:] += [open_gap(d, step) for d in ropes[:, ROPE_GAP]]  # K46
    soft_rows = np.zeros(len(g))  # R: the compliance of each row (K41)
    soft_rows[3 * np.arange(nc) + 2] = compliance
    bounds = np.concatenate([np.tile([0.0, np.inf], (nl, 1)),  # λ >= 0 (K26)
                             step * np.outer(frictions[:, model.nv], [-1.0, 1.0]),  # K30
                             np.tile([-np.inf, np.inf], (ne, 1)),  # K45
                             np.tile([0.0, np.inf], (nr, 1))])  # K46
    used, lam = contact.solver, None
    for used in (contact.solver, other_solver(contact.solver)):  # the other from its λ
        lam, info = solve_contacts(G, g, contacts.friction, compliance=soft_rows, solver=used,
                                   tolerance=contact.tolerance,
                                   max_iterations=contact.max_iterations, warm_start=lam,
                                   bounds=bounds)
        if info.converged:
            break
    if not info.converged and residual(info) > contact.accept:
        raise ValueError(f"the contact solvers ({contact.solver}, then "
                         f"{other_solver(contact.solver)}) did not converge in "
                         f"{contact.max_iterations} iterations each (residuals: primal "
                         f"{info.primal:.2e}, dual {info.dual:.2e}, complementarity "
                         f"{info.complementarity:.2e}, above accept = {contact.accept:g}); "
                         f"raise ContactSettings' max_iterations or accept")
    impulse = J.T @ lam  # joint impulses of the contacts
    v_next = v_free + aba(model, q, np.zeros(model.nv), impulse, gravity=np.zeros(3))  # K24
    forces = np.einsum("ki,kij->kj", lam[:n0].reshape(nc, 3), frames) / step  # world
    limit_torques = (J[n0:n1].T @ lam[n0:n1] + J[n3:].T @ lam[n3:]) / step  # ropes: K46
    friction_torques = J[n1:n2].T @ lam[n1:n2] / step
    coupling_torques = J[n2:n3].T @ lam[n2:n3] / step
    sigma = (G[:n0] @ lam + g[:n0]).reshape(nc, 3)  # σ = G λ + g (K11)
    q_next = step_moved_configuration(model, q, step * v_next)  # K24a
    limit_shift(limits, tendons, rows, nl, stabilization, q_next)  # past a bound: back (K26a)
    depth = np.where(np.any(stiffness != 0.0, axis=1), np.nan, contacts.distance)
    b, mu = np.empty(nc), np.empty(nc)
    deepest = correction_targets(G, g, lam, depth, nc, stabilization, step, b)  # K43
    if deepest > 0.0:  # a contact ends the step inside: q⁺ ⊕ M⁻¹ J_Nᵀ μ
        correction_impulses(G, nc, b, deepest, mu)
        shift = aba(model, q, np.zeros(model.nv), J[2:n0:3].T @ mu,
                    gravity=np.zeros(3))
        q_next = integrate(model, q_next, shift)
    back = stabilization * np.maximum(-ropes[:, ROPE_GAP], 0.0) / np.diag(G)[n3:]
    if np.any(back > 0.0):  # a rope past its bound: back by β |d| in M's metric (K46a)
        q_next = integrate(model, q_next, aba(model, q, np.zeros(model.nv), J[n3:].T @ back,
                                              gravity=np.zeros(3)))
    coupling_shift(tied, stabilization, q_next, np.empty(ne))  # K45a
    return ContactStep(q_next, step_moved_velocity(model, v_next, step), contacts, forces,
                       limit_torques, friction_torques, info, used, sigma, cm,
                       coupling_torques)

