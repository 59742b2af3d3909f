"""Ropes: a bounded distance between two points of the model, unilateral rows of the contact
problem (``docs/contact.md``, "Ropes", K46): which ropes a model holds as the compiled loop
reads them (``rope_arrays``), and which of their bounds are rows of a step
(``rope_bounds``), for ``contact_step`` and the compiled rollout loop alike.

A rope joins the point ``x₁`` of one link to ``x₂`` of another (``Model.rope_*``: MuJoCo's
limited spatial tendon of two sites, dm_control ball_in_cup's string). Its length
``L = |p₁ - p₂|`` (``p`` the points in the world) changes at ``L̇ = u · (ṗ₁ - ṗ₂)``, ``u =
(p₁ - p₂) / L``: the row of the longest bound is ``-u · (J_p₁ - J_p₂)`` with the gap ``d =
longest - L``, of the shortest ``+u · (J_p₁ - J_p₂)`` with ``d = L - shortest``, each
``λ >= 0`` with K26's gap term, where the step may reach it.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import inline
from ..kernels.rigid import point_velocity, rigid_frame, rigid_rotate

__all__ = ["ROPE_COLUMNS", "ROPE_ROW", "rope_arrays", "rope_bounds", "rope_point",
           "rope_rates", "rope_row", "rope_system"]

JOINT1, POINT1, JOINT2, POINT2, SHORTEST, LONGEST = 0, 1, 4, 5, 8, 9
ROPE_COLUMNS = 10
"""Columns of ``rope_arrays``: the joint that carries end 1 (-1: the world) and its point
in that joint's frame (in the world's for -1), the same for end 2, the shortest and the
longest length."""
SIGN, GAP, SLOT, U, P1, P2 = 0, 1, 2, 3, 6, 9
ROPE_ROW = 12
"""Columns of the rows ``rope_bounds`` finds: +1 for a shortest bound, -1 for a longest,
the gap ``d``, the bound's slot (``2 i`` the shortest of rope i, ``2 i + 1`` its longest),
the unit direction ``u`` and the two ends ``p₁``, ``p₂`` in the world."""


def rope_arrays(model) -> np.ndarray:
    """(nr, ``ROPE_COLUMNS``) of the model's ropes: each end's link placement composed
    with its point once here, so that a step moves it by its joint's world motor alone."""
    out = np.zeros((len(model.rope_names), ROPE_COLUMNS))
    for i, (links, points) in enumerate(zip(model.rope_links, model.rope_points,
                                            strict=True)):
        for end, (link, x) in enumerate(zip(links, points, strict=True)):
            o = JOINT1 if end == 0 else JOINT2
            T = np.eye(4) if link < 0 else model.link_placement_matrices[link]
            out[i, o] = -1 if link < 0 else model.link_joint[link]
            out[i, o + 1:o + 4] = T[:3, :3] @ x + T[:3, 3]
        out[i, SHORTEST], out[i, LONGEST] = model.rope_range[i]
    return out


@inline
def rope_point(ropes, i, end, Mw):
    """End ``end`` of rope ``i`` in the world, moved by its joint's world motor ``Mw[j]``."""
    o = JOINT1 if end == 0 else JOINT2
    j = int(ropes[i, o])
    x, y, z = ropes[i, o + 1], ropes[i, o + 2], ropes[i, o + 3]
    if j < 0:
        return x, y, z
    rot, pos = rigid_frame(Mw[j])
    x, y, z = rigid_rotate(rot, x, y, z)
    return x + pos[0], y + pos[1], z + pos[2]


@inline
def rope_bounds(ropes, i, p1, p2, rates, dt, margin, rows, count):
    """The bounds of rope ``i`` with its ends at ``p1``, ``p2`` that are rows of the step
    (K46): where the gap is below ``margin`` plus ``dt sqrt(L̇² + L̇_free²)``, ``rates`` (2,
    3) the ends' relative velocity ``ṗ₁ - ṗ₂`` at v and at the free velocity. Appends to
    ``rows`` (``ROPE_ROW`` columns) from ``count``; the new count."""
    dx, dy, dz = p1[0] - p2[0], p1[1] - p2[1], p1[2] - p2[2]
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    if length > 0.0:
        ux, uy, uz = dx / length, dy / length, dz / length
    else:  # both ends at one point: only a shortest bound acts, along any direction
        ux, uy, uz = 0.0, 0.0, 1.0
    r0 = ux * rates[0, 0] + uy * rates[0, 1] + uz * rates[0, 2]
    r1 = ux * rates[1, 0] + uy * rates[1, 1] + uz * rates[1, 2]
    reach = margin + dt * math.sqrt(r0 * r0 + r1 * r1)
    for side in range(2):
        d = length - ropes[i, SHORTEST] if side == 0 else ropes[i, LONGEST] - length
        if side == 0 and ropes[i, SHORTEST] == 0.0:
            continue  # no shortest bound: a length is never below 0
        if d < reach:
            rows[count, SIGN] = 1.0 if side == 0 else -1.0
            rows[count, GAP], rows[count, SLOT] = d, 2 * i + side
            rows[count, U], rows[count, U + 1], rows[count, U + 2] = ux, uy, uz
            for c in range(3):
                rows[count, P1 + c], rows[count, P2 + c] = p1[c], p2[c]
            count += 1
    return count


@inline
def rope_rates(ropes, i, bodies, p1, p2, rates):
    """``rates[t] = ṗ₁ - ṗ₂`` of rope ``i``'s ends at v (t = 0) and at the free velocity
    (t = 1), each ``v + ω × p`` of its joint's world twist in ``bodies`` (K46)."""
    for t in range(2):
        for c in range(3):
            rates[t, c] = 0.0
        for end in range(2):
            j = int(ropes[i, JOINT1 if end == 0 else JOINT2])
            if j < 0:
                continue
            s = 1.0 if end == 0 else -1.0
            p = p1 if end == 0 else p2
            b = bodies[j, t]
            x, y, z = point_velocity(b[0], b[1], b[2], b[3], b[4], b[5], p[0], p[1], p[2])
            rates[t, 0] += s * x
            rates[t, 1] += s * y
            rates[t, 2] += s * z


@inline
def rope_row(m, Sw, ropes, rows, k, J, r):
    """Row ``r`` of J for the rope bound ``rows[k]`` (K46): ``sign u · (J_p₁ - J_p₂)``, each
    end's point Jacobian from the world twists ``Sw`` of the coordinates on its joint's path
    to the root (C1: ``v + ω × p``)."""
    i = int(rows[k, SLOT]) // 2
    ux, uy, uz = rows[k, U], rows[k, U + 1], rows[k, U + 2]
    for end in range(2):
        j = int(ropes[i, JOINT1 if end == 0 else JOINT2])
        o = P1 if end == 0 else P2
        px, py, pz = rows[k, o], rows[k, o + 1], rows[k, o + 2]
        s = rows[k, SIGN] if end == 0 else -rows[k, SIGN]
        while j >= 0:
            for c in range(m.iv[j], m.iv[j + 1]):
                vx, vy, vz = point_velocity(Sw[c, 0], Sw[c, 1], Sw[c, 2], Sw[c, 3], Sw[c, 4],
                                            Sw[c, 5], px, py, pz)
                J[r, c] += s * (ux * vx + uy * vy + uz * vz)
            j = m.parents[j]


def rope_system(model, q, v, v_free, dt: float, margin: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """The rope bounds that are rows of a step from ``q`` (``rope_bounds``, K46) and their
    rows of J (count, nv), from Python, what ``contact_step`` takes: ``J_p₁ - J_p₂`` of
    each rope is the Jacobian of a point constraint holding its first end on its second
    (``constraint_jacobian``, C1-C2), with the ends swapped (and the sign) where the
    first is fixed in the world."""
    from ..algorithms.api import link_placements
    from ..constraints.model import Constraint
    from ..constraints.operators import constraint_jacobian

    ropes = rope_arrays(model)
    nr = len(model.rope_names)
    rows = np.zeros((2 * nr, ROPE_ROW))
    if nr == 0:
        return rows, np.zeros((0, model.nv))
    T = link_placements(model, q)
    ends, count = [], 0
    for i, (links, points) in enumerate(zip(model.rope_links, model.rope_points,
                                            strict=True)):
        frames = [np.eye(4) if link < 0 else T[link].copy() for link in links]
        for frame, x in zip(frames, points, strict=True):
            frame[:3, 3] = frame[:3, :3] @ x + frame[:3, 3]  # the end's frame in the world
        p = [frame[:3, 3] for frame in frames]
        moving = [link >= 0 and model.link_joint[link] >= 0 for link in links]
        Jd = np.zeros((3, model.nv))
        if any(moving):
            a, b = (0, 1) if moving[0] else (1, 0)  # the first end of the constraint moves
            other = int(links[b]) if moving[b] else None
            held = Constraint(model, "point", int(links[a]),
                              placement=np.linalg.inv(T[links[a]]) @ frames[a], other=other,
                              other_placement=frames[b] if other is None
                              else np.linalg.inv(T[other]) @ frames[b])
            Jd = (1.0 if a == 0 else -1.0) * constraint_jacobian(model, q, [held])
        rates = np.array([Jd @ v, Jd @ v_free])
        count = rope_bounds(ropes, i, p[0], p[1], rates, dt, margin, rows, count)
        ends.append(Jd)
    J = np.array([rows[k, SIGN] * rows[k, U:U + 3] @ ends[int(rows[k, SLOT]) // 2]
                  for k in range(count)]).reshape(count, model.nv)
    return rows[:count], J
