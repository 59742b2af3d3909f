"""Contacts between shapes of different links, compiled (docs/contact.md, "Free bodies and
pairs", K37-K39).

Two shapes ``a`` and ``b`` closer than a margin touch at their witness points, along the
normal ``n`` from ``b`` to ``a`` (``distance.pair_distance``). One point cannot hold a box
lying on another box: as on the ground (K21-K22), the contact is a patch. ``pair_patch``
takes the candidates of each shape against the tangent plane of the other at its witness
point (``manifold.candidates``), keeps those whose distance to the other shape itself is
below the margin (so that a corner overhanging the other's face is left out), adds the
witness pair, and reduces them to at most ``MAX_CONTACTS`` spanning the patch (K22). Each
contact is a point ``x_a`` on ``a``, its signed distance ``d`` and the point ``x_b = x_a -
d n`` on ``b`` (K37). ``pair_contacts`` runs it over a list of pairs after a broad phase on
bounding spheres (K39). Nothing allocates.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import serial
from .distance import OK, pair_distance
from .manifold import (
    CANDIDATE_COLUMNS,
    CANDIDATES,
    MAX_CONTACTS,
    OUT,
    candidates,
    mark_within,
    reach_bound,
    reduce_patch,
)
from .shapes import BOX, CAPSULE, CYLINDER, ELLIPSOID, MESH, PLANE, SPHERE

__all__ = ["PAIR_CANDIDATES", "bounding_radii", "candidate_pairs", "contact_frame",
           "pair_margin",
           "pair_contacts", "pair_patch"]

PAIR_CANDIDATES = 2 * CANDIDATES + 1
"""Scratch rows of ``pair_patch``: each shape's candidates and the witness pair."""


@serial
def contact_frame(n0, n1, n2, F):
    """The rows ``(t₁, t₂, n)`` of the frame of a contact with unit normal ``n`` (the
    ground's, or a pair's from ``b`` to ``a``) into ``F`` (K37): ``t₁`` the world's x made
    orthogonal to ``n`` (the world's y where x is nearly along ``n``), ``t₂ = n × t₁``."""
    x0, x1 = (1.0, 0.0) if abs(n0) < 0.9 else (0.0, 1.0)
    s = x0 * n0 + x1 * n1
    t0, t1, t2 = x0 - s * n0, x1 - s * n1, -s * n2
    r = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    t0, t1, t2 = t0 / r, t1 / r, t2 / r
    F[0, 0], F[0, 1], F[0, 2] = t0, t1, t2
    F[1, 0], F[1, 1], F[1, 2] = n1 * t2 - n2 * t1, n2 * t0 - n0 * t2, n0 * t1 - n1 * t0
    F[2, 0], F[2, 1], F[2, 2] = n0, n1, n2


@serial
def _point_distance(x0, x1, x2, kb, sb, vb, Tb, zero, P, work, tmp):
    """The signed distance of the point ``x`` to shape ``b``: a sphere of radius 0 at ``x``
    (``zero``: its size) against it (K4); NaN where it is not computed."""
    for i in range(4):
        for j in range(4):
            P[i, j] = 1.0 if i == j else 0.0
    P[0, 3], P[1, 3], P[2, 3] = x0, x1, x2
    # np.int64: a constant argument is a literal type, which numba compiles pair_distance
    # (GJK, EPA) again for
    if pair_distance(np.int64(SPHERE), zero, vb[:0], P, kb, sb, vb, Tb, work, tmp) != OK:
        return np.nan
    return tmp[0]


@serial
def _keep(cand, c, count, n0, n1, n2, sign, kb, sb, vb, Tb, margin, zero, P, work, tmp):
    """Of rows ``c .. c + count`` of ``cand`` (candidates against a tangent plane), keep
    those within ``margin`` of shape ``b`` itself, compacted from row ``c``, each with that
    distance; ``sign`` -1: the candidates lie on ``b``'s partner seen from the other side,
    so the kept row holds the point on ``a``, ``x + d n``. Returns the new row count."""
    m = c
    for i in range(c, c + count):
        if cand[i, 3] >= margin:
            continue
        d = _point_distance(cand[i, 0], cand[i, 1], cand[i, 2], kb, sb, vb, Tb, zero, P,
                            work, tmp)
        if not d < margin:  # NaN too
            continue
        shift = d if sign < 0.0 else 0.0
        cand[m, 0] = cand[i, 0] + shift * n0
        cand[m, 1] = cand[i, 1] + shift * n1
        cand[m, 2] = cand[i, 2] + shift * n2
        cand[m, 3] = d
        m += 1
    return m


@serial
def pair_patch(ka, sa, va, Ta, kb, sb, vb, Tb, margin, patch, zero, P, work, tmp, cand, out,
               normal):
    """The contacts of shapes ``a`` and ``b`` closer than ``margin`` (K37): at most
    ``MAX_CONTACTS`` rows ``[x_a, d]`` in ``out`` and the normal from ``b`` to ``a`` in
    ``normal``. Returns their number, or ``-status`` of ``pair_distance`` where it fails
    (a penetration it does not compute)."""
    status = pair_distance(ka, sa, va, Ta, kb, sb, vb, Tb, work, tmp)
    if status != OK:
        return -status
    if not tmp[0] < margin:
        return 0
    n0, n1, n2 = -tmp[7], -tmp[8], -tmp[9]  # from b to a
    normal[0], normal[1], normal[2] = n0, n1, n2
    pa0, pa1, pa2, pb0, pb1, pb2 = tmp[1], tmp[2], tmp[3], tmp[4], tmp[5], tmp[6]
    d = tmp[0]
    # a's candidates against b's tangent plane π = n + (n · p_b) e∞ (K1, K21)
    count = candidates(ka, sa, va, Ta, n0, n1, n2, n0 * pb0 + n1 * pb1 + n2 * pb2,
                       cand[0:CANDIDATES], math.inf)
    c = _keep(cand, np.int64(0), count, n0, n1, n2, 1.0, kb, sb, vb, Tb, margin, zero, P, work, tmp)
    # b's against a's tangent plane, whose normal is -n
    count = candidates(kb, sb, vb, Tb, -n0, -n1, -n2, -(n0 * pa0 + n1 * pa1 + n2 * pa2),
                       cand[c:c + CANDIDATES], math.inf)
    c = _keep(cand, c, count, n0, n1, n2, -1.0, ka, sa, va, Ta, margin, zero, P, work, tmp)
    # the witnesses last: of candidates level with them (a face's corners) those come first
    cand[c, 0], cand[c, 1], cand[c, 2], cand[c, 3] = pa0, pa1, pa2, d
    c += 1
    if mark_within(cand, c, margin) == 0:
        return 0
    return reduce_patch(cand, c, patch, n0, n1, n2, out, False)


@serial
def pair_contacts(kinds, sizes, vertices, offsets, poses, pairs, radii, margin, patch, zero,
                  P, work, tmp, cand, out, counts, normals, status):
    """``pair_patch`` of every pair ``pairs[p] = (a, b)`` whose bounding spheres (``radii``
    about the shapes' origins) are at most ``margin`` apart (K39), into ``out[p]``
    (``MAX_CONTACTS`` rows ``[x_a, d]``), ``normals[p]``, ``counts[p]``; ``status[p]``
    the distance's status (a pair it fails on gets no contact)."""
    for p in range(pairs.shape[0]):
        a, b = pairs[p, 0], pairs[p, 1]
        counts[p], status[p] = 0, 0
        e0 = poses[a, 0, 3] - poses[b, 0, 3]
        e1 = poses[a, 1, 3] - poses[b, 1, 3]
        e2 = poses[a, 2, 3] - poses[b, 2, 3]
        reach = radii[a] + radii[b] + margin
        if e0 * e0 + e1 * e1 + e2 * e2 > reach * reach:
            continue
        k = pair_patch(kinds[a], sizes[a], vertices[offsets[a]:offsets[a + 1]], poses[a],
                       kinds[b], sizes[b], vertices[offsets[b]:offsets[b + 1]], poses[b],
                       margin, patch, zero, P, work, tmp, cand, out[p], normals[p])
        if k < 0:
            status[p] = -k
        else:
            counts[p] = k


@serial
def pair_margin(margin, radii, poses, twists, dt):
    """The margin of the pairs' contacts in a step of ``dt`` (K21a for pairs): ``margin``
    plus twice the farthest way any point of a moving shape may travel in the step
    (``manifold.reach_bound`` of its bounding radius, K39, at its link's twists
    ``twists[s]`` (K, 2, 6)); a shape of infinite radius (a plane) never moves."""
    reach = 0.0
    for s in range(radii.shape[0]):
        if math.isfinite(radii[s]):
            reach = max(reach, reach_bound(poses, s, radii[s], twists, dt))
    return margin + 2.0 * reach


def bounding_radii(cm) -> np.ndarray:
    """(K,) the radius of each shape's bounding sphere about its frame's origin (K39): a
    sphere's radius, a capsule's half length plus radius, a box's half diagonal, a
    cylinder's ``sqrt(r² + (L/2)²)``, an ellipsoid's largest radius, a convex mesh's farthest
    vertex; a plane's ``inf``."""
    out = np.empty(len(cm))
    for k, c in enumerate(cm):
        s = c.shape.packed_size
        kind = c.shape.kind
        out[k] = (s[0] if kind == SPHERE else s[0] + s[1] if kind == CAPSULE
                  else np.linalg.norm(s[:3]) if kind == BOX
                  else np.hypot(s[0], s[1]) if kind == CYLINDER
                  else np.max(s[:3]) if kind == ELLIPSOID
                  else np.max(np.linalg.norm(c.shape.packed_vertices, axis=1)) if kind == MESH
                  else np.inf)
    return out


def candidate_pairs(cm, robot_joints: int, self_collision: bool = False) -> np.ndarray:
    """(P, 2) the pairs of shapes of ``cm`` that may touch (K38): shapes of different
    bodies (joints), at least one of which moves, a plane only where it does not move (a wall,
    K44a: a half-space on a moving link is no shape cgadyn collides), allowed by
    ``contype``/``conaffinity``; a free body's shape (a joint at or
    after ``robot_joints``) or a shape of the world itself (link -1: an obstacle, K44) with
    every other shape; two of the robot's only with ``self_collision``, and then not on a
    parent and its child (``adjacent``). A shape that does not move (the world's, or on a
    link welded to it) is the second of its pair (``b``: the contact's point, link and
    force are the moving shape's)."""
    pairs = []
    for i in range(len(cm)):
        for j in range(i + 1, len(cm)):
            a, b = int(cm.bodies[i]), int(cm.bodies[j])
            moving_plane = (cm.kinds[i] == PLANE and a >= 0) or (cm.kinds[j] == PLANE and b >= 0)
            if a == b or (a < 0 and b < 0) or moving_plane or not cm.can_touch(i, j):
                continue
            world = cm.links[i] < 0 or cm.links[j] < 0
            robot = not world and a < robot_joints and b < robot_joints
            if robot and (not self_collision or cm.adjacent(i, j)):
                continue
            pairs.append((j, i) if a < 0 else (i, j))  # the one that does not move second
    return np.array(pairs, dtype=np.int64).reshape(-1, 2)


def pair_rows(model, cm, poses, pairs, margin: float, patch: float = 0.0) -> tuple:
    """The pair contacts at ``poses`` (``collision_poses``): ``(pair (C,), x_a (C, 3),
    x_b (C, 3), normal (C, 3), d (C,))`` from one compiled ``pair_contacts`` call; raises
    ``ValueError`` naming a pair whose distance is not computed."""
    from .api import explain
    from .distance import WORK

    P = len(pairs)
    out = np.empty((P, MAX_CONTACTS, OUT))
    counts = np.zeros(P)  # floats, as in the compiled loop's scratch: one signature
    normals = np.zeros((P, 3))
    status = np.zeros(P)
    pair_contacts(cm.kinds, cm.sizes, cm.vertices, cm.offsets, np.ascontiguousarray(poses),
                  pairs, bounding_radii(cm), float(margin), float(patch), np.zeros(4),
                  np.empty((4, 4)), np.empty(WORK), np.empty(10),
                  np.empty((PAIR_CANDIDATES, CANDIDATE_COLUMNS)), out, counts, normals, status)
    bad = np.flatnonzero(status)
    if bad.size:
        i, j = pairs[int(bad[0])]
        raise ValueError(f"collisions {cm[i].name!r} and {cm[j].name!r}: "
                         f"{explain(int(status[bad[0]]), cm[i].shape, cm[j].shape)}")
    counts = counts.astype(np.int64)
    which = np.repeat(np.arange(P), counts)
    rows = out[which, np.concatenate([np.arange(k) for k in counts]).astype(np.int64)] \
        if P else np.zeros((0, OUT))
    n = normals[which]
    return which, rows[:, :3].copy(), rows[:, :3] - rows[:, 3:4] * n, n, rows[:, 3].copy()
