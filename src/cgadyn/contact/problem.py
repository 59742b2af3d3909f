"""``contact_problem``: the Delassus matrix and free velocity of a velocity-level step with
point contacts (``docs/contact.md``, K20), from the operators of ``cgadyn.constraints``."""

from __future__ import annotations

import numpy as np

from .._jit import inline
from ..algorithms._inputs import time_step
from ..algorithms.api import aba
from ..constraints.model import check_constraints
from ..constraints.operators import constraint_jacobian, delassus


def contact_problem(model, q, v, tau, dt: float, constraints) -> tuple[np.ndarray, np.ndarray]:
    """``(G, g)`` of the contact problem (K11) of one step of length ``dt`` from ``(q, v)``
    under ``tau``: ``G = J M⁻¹ Jᵀ`` (C7) and ``g = J v_free`` with ``v_free = v + dt M⁻¹(τ -
    h)`` (K20), for point ``Constraint``s in ``"local_world_aligned"`` frame, each a contact
    whose rows are the world's ``(x, y, z)`` at the point: the normal is the world's z (the
    last row, as ``solve_contacts`` reads it), the ground's normal for a floor ``z = const``.
    Batches of ``q, v, tau`` give (B, m, m) and (B, m). ``σ = G λ + g`` is then the contact
    points' velocity after the step, ``v⁺ = v_free + M⁻¹ Jᵀ λ``, with ``λ`` the impulses."""
    constraints = check_constraints(model, constraints)
    for k, c in enumerate(constraints):
        if c.kind != "point" or c.frame != "local_world_aligned":
            raise ValueError(f"constraint {k} ({c.name}) must be a point constraint in "
                             f"'local_world_aligned' frame to be a contact (its rows the "
                             f"world's x, y and z, the normal z), got kind {c.kind!r}, frame "
                             f"{c.frame!r}")
    step = time_step(dt)
    J = constraint_jacobian(model, q, constraints)
    G = delassus(model, q, constraints)
    v_free = np.asarray(v, dtype=float) + step * aba(model, q, v, tau)  # K20
    g = np.einsum("...rk,...k->...r", J, v_free)
    return G, g


@inline
def row_starts(nc, nl, nf, ne, nr):
    """Where each kind of row begins in a step's problem, the one order that
    ``step.contact_step`` and the compiled step (``sim.contact``) share: from row 0 the
    three rows ``(t₁, t₂, n)`` of each of ``nc`` contacts (K23, K37), then ``nl`` limit
    bounds (K26), ``nf`` friction losses (K30), ``ne`` couplings (K45), ``nr`` rope bounds
    (K46), and at the end any bilateral constraints (C14). Returns the first row of the
    limits, frictions, couplings and ropes, and the end; the rows from the limits' on are
    the problem's interval rows, ``bounds[r - limits]`` bounding row ``r``."""
    limits = 3 * nc
    frictions = limits + nl
    couplings = frictions + nf
    ropes = couplings + ne
    return limits, frictions, couplings, ropes, ropes + nr


@inline
def open_gap(d, dt):
    """The gap's term of a rigid contact's normal row or a limit's row (K23, K26): ``d /
    dt`` for an open gap (the step may close it, no sooner), 0 for a penetration (the step
    takes the point no further in; the position update takes it back, K43, K26a)."""
    return max(d, 0.0) / dt


@inline
def normal_row(d, k, c, dt):
    """``(gap term, R)`` of a contact's normal row at the signed distance ``d``: rigid
    (``k = c = 0``), K23's term (``open_gap``) and ``R = 0``; a spring ``k`` and damper
    ``c`` (K41), the force ``f = -k d⁺ - c σ_N`` at the end of the step (``d⁺ = d + dt
    σ_N``), which is ``0 <= λ ⊥ σ_N + k d / (dt k + c) + λ / (dt (dt k + c)) >= 0``: the
    term ``k d / (dt k + c)`` and ``R = 1 / (dt (dt k + c))`` (an open gap: ``d / dt``, as
    K23)."""
    if k == 0.0 and c == 0.0:
        return open_gap(d, dt), 0.0
    r = 1.0 / (dt * (dt * k + c))
    if d > 0.0:
        return d / dt, r
    return k * d / (dt * k + c), r


def contact_compliance(collisions, contacts) -> np.ndarray:
    """(nc, 2) each contact's stiffness and damping (K41): its shape's
    (``CollisionModel.compliance``) for a contact with the ground, zeros for a pair's."""
    return np.where((contacts.other < 0)[:, None], collisions.compliance[contacts.collision],
                    0.0)


def gap_velocity(distance, dt: float, compliance=None) -> tuple[np.ndarray, np.ndarray]:
    """``normal_row`` of each contact at ``distance`` (nc,) with ``compliance`` (nc, 2)
    (stiffness, damping; None: rigid): the gap's terms (nc,) and the diagonal ``R`` (nc,)
    of their normal rows (K23, K41)."""
    d = np.asarray(distance, dtype=float).reshape(-1)
    kc = np.zeros((len(d), 2)) if compliance is None else np.asarray(compliance, float)
    rows = [normal_row(float(x), float(k), float(c), float(dt))
            for x, (k, c) in zip(d, kc.reshape(len(d), 2), strict=True)]
    out = np.array(rows, dtype=float).reshape(len(d), 2)
    return out[:, 0], out[:, 1]


def contact_jacobian(model, q, contacts, frames) -> np.ndarray:
    """(3 nc, nv): the rows ``(t₁, t₂, n)`` of each contact of ``contacts`` (a ``Contacts``)
    at ``q``, a point of its link held where it is (C1): for a contact with the ground the
    point of the plane under the shape's (``Contacts.acting``, K42); for a pair's, held to the
    other shape's point, on its link where ``other_link`` >= 0 (C2, K37); its world rows
    turned into its frame (``frames`` (nc, 3, 3), rows ``t₁, t₂, n``:
    ``step.ground_frame`` of its normal): ``J v`` is the contact points' (relative)
    velocity in their frames (K20)."""
    from ..algorithms import link_placements
    from ..constraints.model import Constraint

    nc = len(contacts)
    if nc == 0:
        return np.zeros((0, model.nv))
    links = link_placements(model, q)
    acting = contacts.acting  # K42
    constraints = []
    for k in range(nc):
        at, other = np.eye(4), np.eye(4)
        at[:3, 3] = acting[k]
        other[:3, 3] = contacts.other_point[k]  # a pair's other point (the ground is still)
        b = int(contacts.other_link[k])
        constraints.append(Constraint(
            model, "point", int(contacts.link[k]),
            placement=np.linalg.inv(links[contacts.link[k]]) @ at,
            other=b if b >= 0 else None,
            other_placement=np.linalg.inv(links[b]) @ other if b >= 0 else other))
    J = constraint_jacobian(model, q, constraints).reshape(nc, 3, model.nv)
    return np.einsum("cij,cjk->cik", frames, J).reshape(3 * nc, model.nv)
