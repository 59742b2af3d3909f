"""The contact points of a shape resting on a plane, compiled (docs/contact.md, K21-K22).

A sphere touches a plane at one point; a box lying on a face, a cylinder standing on a cap
or a convex mesh on a flat side touch it over a patch, which one point cannot hold still:
a contact solver needs the corners of the patch. ``plane_contacts`` gives every shape's
candidate points, each with its signed distance ``X · π`` to the plane (K1, K21), keeps
those whose gap after the step's free motion is below a margin (K21a: a contact is found
one step before it closes, and a point at rest is one only where it touches) and reduces
them to at most ``MAX_CONTACTS`` that span the patch (K22). It allocates nothing
and returns the number of contacts written.
"""

from __future__ import annotations

import math

from .._jit import core, inline
from ..kernels.rigid import point_velocity
from .distance import plane_distance, rotate, rotate_back, support, to_world
from .shapes import BOX, CAPSULE, CYLINDER, ELLIPSOID, MESH, SPHERE

MAX_CONTACTS = 4
"""At most this many contact points per shape and plane (the corners of a patch)."""
CANDIDATES = 64
"""Scratch rows for candidate points: a convex mesh's vertices (``shapes.MAX_VERTICES``),
a box's 8 corners, a cylinder's 8 rim points, a capsule's 2 ends, a sphere's 1."""
OUT = 4
"""Each contact's row in ``out``: ``[x, y, z, d]``, the point on the shape and its signed
distance to the plane (negative: a penetration)."""
CANDIDATE_COLUMNS = OUT + 1
"""A candidate's row: ``OUT``'s, then a scratch column (``reduce_patch``)."""
TILT = 1e-3
"""K22's exchange of height for spread (rad): a candidate's height above the deepest, over
``TILT``, counts against how far it spans the patch. A foot whose sole rests on two of its
hull's vertices at one height and has others a fraction of a millimetre higher is held at
both (each alone would let it rock onto the other, step after step); a face lying flat to
within ``TILT`` is held at its widest corners."""
LEVEL = 1e-6
"""Candidates within this height (m) of the deepest are level with it for K22's exchange
(``TILT``): a face resting on the ground, its corners a fraction of a micrometre apart as
the step corrects its overlap, is held at its widest corners in the same order each step."""
CORNER = 1e-4
"""Distances along the plane (m) within this of each other are a tie in the choice of a
compliant patch's first corner (K22'): a rectangle's four corners, whose distances from its
centre a tilt of a milliradian moves by tens of nanometres."""
TIE = 1e-9
"""Scores of K22 (m) closer than this are a tie, kept in the candidates' order: the corners
of a face, equal but for rounding, come in the same order step after step (each contact's
slot, and so its warm start, stays its own)."""


@core
def _candidate(cand, c, x0, x1, x2, n0, n1, n2, delta, r):
    """Row ``c`` of ``cand``: the point ``x - r n`` of a sphere of radius ``r`` centred at
    ``x`` (``r = 0``: the point ``x``) and its distance ``X · π - r`` (K1, K21)."""
    cand[c, 0] = x0 - r * n0
    cand[c, 1] = x1 - r * n1
    cand[c, 2] = x2 - r * n2
    cand[c, 3] = plane_distance(x0, x1, x2, n0, n1, n2, delta) - r
    return c + 1


@core
def candidates(kind, size, vertices, T, n0, n1, n2, delta, cand, far):
    """The shape's candidate points against the plane ``π = n + δ e∞`` (K21): a sphere's
    lowest point; a capsule's two end spheres' lowest points; a box's eight corners; on
    each of a cylinder's two rims, the lowest point and the three a quarter-turn apart; an
    ellipsoid's lowest point; a
    convex mesh's vertices closer than ``far`` (``inf``: all), each vertex's distance taken
    in the shape's frame against the plane moved there (``M̃ π M``: its normal turned back,
    its offset less the shape's origin's distance), so that only those candidates are
    moved into the world. Returns their number."""
    c = 0
    if kind == SPHERE or kind == CAPSULE:
        h = size[1] if kind == CAPSULE else 0.0
        for s in range(2 if kind == CAPSULE else 1):
            z = h if s == 0 else -h
            x0, x1, x2 = to_world(T, 0.0, 0.0, z)
            c = _candidate(cand, c, x0, x1, x2, n0, n1, n2, delta, size[0])
    elif kind == BOX:
        for s in range(8):
            x0, x1, x2 = to_world(T, size[0] if s & 1 else -size[0],
                                  size[1] if s & 2 else -size[1], size[2] if s & 4 else -size[2])
            c = _candidate(cand, c, x0, x1, x2, n0, n1, n2, delta, 0.0)
    elif kind == CYLINDER:
        l0, l1, _ = rotate_back(T, -n0, -n1, -n2)  # the plane's inward normal, in the shape
        rho = math.sqrt(l0 * l0 + l1 * l1)
        u0, u1 = (l0 / rho, l1 / rho) if rho > 1e-12 else (1.0, 0.0)
        for s in range(2):
            z = size[1] if s == 0 else -size[1]
            for k in range(4):  # u, its quarter turns: the lowest rim point and three more
                a0, a1 = (u0, u1) if k == 0 else (-u1, u0) if k == 1 else \
                    (-u0, -u1) if k == 2 else (u1, -u0)
                x0, x1, x2 = to_world(T, size[0] * a0, size[0] * a1, z)
                c = _candidate(cand, c, x0, x1, x2, n0, n1, n2, delta, 0.0)
    elif kind == ELLIPSOID:  # its lowest point, its support along -n (K6a)
        x0, x1, x2 = support(kind, size, vertices, T, -n0, -n1, -n2)
        c = _candidate(cand, c, x0, x1, x2, n0, n1, n2, delta, 0.0)
    elif kind == MESH:  # the plane moved into the shape's frame, then each vertex's K1
        l0, l1, l2 = rotate_back(T, n0, n1, n2)
        dl = delta - (n0 * T[0, 3] + n1 * T[1, 3] + n2 * T[2, 3])
        for i in range(min(vertices.shape[0], cand.shape[0])):
            d = plane_distance(vertices[i, 0], vertices[i, 1], vertices[i, 2], l0, l1, l2, dl)
            if d < far:
                x0, x1, x2 = to_world(T, vertices[i, 0], vertices[i, 1], vertices[i, 2])
                cand[c, 0], cand[c, 1], cand[c, 2], cand[c, 3] = x0, x1, x2, d
                c += 1
    return c


@core
def _area2(cand, i, j, k, n0, n1, n2):
    """Twice the signed area of the triangle ``(i, j, k)`` seen along the normal ``n``."""
    a0, a1, a2 = cand[j, 0] - cand[i, 0], cand[j, 1] - cand[i, 1], cand[j, 2] - cand[i, 2]
    b0, b1, b2 = cand[k, 0] - cand[i, 0], cand[k, 1] - cand[i, 1], cand[k, 2] - cand[i, 2]
    return (a1 * b2 - a2 * b1) * n0 + (a2 * b0 - a0 * b2) * n1 + (a0 * b1 - a1 * b0) * n2


@core
def _write(out, m, cand, i):
    for j in range(OUT):
        out[m, j] = cand[i, j]
    return m + 1


@inline
def reach(V, k, x0, x1, x2, radius, dt):
    """The farthest a point within ``radius`` of ``x`` may travel in a step of length
    ``dt`` (K21a): ``dt (|v_x| + |ω| radius)(1 + dt |ω|)`` with ``v_x = v + ω × x`` (the
    second factor for the turn of that velocity: a point of a body turning at ``ω``
    accelerates by ``ω × v_x``; ``|v_y| <= |v_x| + |ω| radius`` for ``|y - x| <=
    radius``), at the larger of shape ``k``'s link's two world twists ``V[k, t] = [v, ω]``
    (the velocity at the step's start and the free one). In any direction, not only along
    the normal: the contact impulses of the step turn the velocities (a joint limit's
    impulse swings a leg into the ground)."""
    out = 0.0
    for t in range(2):
        w0, w1, w2 = V[k, t, 3], V[k, t, 4], V[k, t, 5]
        u0, u1, u2 = point_velocity(V[k, t, 0], V[k, t, 1], V[k, t, 2], w0, w1, w2, x0, x1,
                                    x2)
        u = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        w = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        out = max(out, dt * (u + w * radius) * (1.0 + dt * w))
    return out


@inline
def gap_after(cand, i, V, k, dt):
    """Candidate ``i``'s least gap at the end of a step of length ``dt`` (K21a): its
    distance less the way it may travel (``reach`` of the point on shape ``k``; zero
    twists: the distance itself)."""
    return cand[i, 3] - reach(V, k, cand[i, 0], cand[i, 1], cand[i, 2], 0.0, dt)


@inline
def reach_bound(poses, k, radius, V, dt):
    """The farthest any point within ``radius`` of the origin of shape ``k``'s pose
    ``poses[k]`` may travel in a step of ``dt`` at its twists ``V[k]`` (2, 6): ``reach`` of
    that ball."""
    return reach(V, k, poses[k, 0, 3], poses[k, 1, 3], poses[k, 2, 3], radius, dt)


@core
def mark_reach(cand, count, margin, V, k, dt, bound):
    """Column ``OUT`` of the ``count`` candidates of shape ``k``: 1 where the gap less the
    way the point may travel in the step (``gap_after``) is below ``margin`` (K21a), else 0;
    ``bound`` bounds that way for every candidate (``reach_bound``), so a candidate farther
    than ``margin + bound`` is 0 without ``gap_after``. Their number."""
    n = 0
    for i in range(count):
        near = cand[i, 3] - bound < margin and gap_after(cand, i, V, k, dt) < margin
        cand[i, OUT] = 1.0 if near else 0.0
        n += int(near)
    return n


@core
def mark_within(cand, count, margin):
    """Column ``OUT`` of the ``count`` candidates: 1 where the distance is below ``margin``,
    else 0. Their number."""
    k = 0
    for i in range(count):
        cand[i, OUT] = 1.0 if cand[i, 3] < margin else 0.0
        k += int(cand[i, OUT])
    return k


@core
def _apart(cand, i, out, m, patch):
    """Whether candidate ``i`` is farther than ``patch`` (and than 1e-9) from each of the
    ``m`` points kept in ``out`` (K22)."""
    reach = max(patch, 1e-9)
    for k in range(m):
        d0, d1, d2 = cand[i, 0] - out[k, 0], cand[i, 1] - out[k, 1], cand[i, 2] - out[k, 2]
        if d0 * d0 + d1 * d1 + d2 * d2 <= reach * reach:
            return False
    return True


@inline
def _rise(cand, i, deep, soft):
    """Candidate ``i``'s height above the deepest, ``deep``, less ``LEVEL``, over ``TILT``
    (0 within ``LEVEL``): the spread it gives up in K22's choice (``reduce_patch``). On a
    compliant shape (``soft``, K41) 0 for a candidate below the plane: each such point
    presses with its own spring, and the patch is where they are (K22')."""
    if soft and cand[i, 3] < 0.0:
        return 0.0
    return max(0.0, cand[i, 3] - cand[deep, 3] - LEVEL) / TILT


@inline
def _start(cand, count, deep, soft, n0, n1, n2):
    """The first point of K22's choice: the deepest, ``deep``; on a compliant shape sunk
    below the plane, of its candidates below it the one farthest from their centroid along
    the plane (ties within ``CORNER``: the first), a corner of the patch that no tilt moves
    (K22')."""
    if not (soft and cand[deep, 3] < 0.0):
        return deep
    c0 = c1 = c2 = 0.0
    n = 0
    for i in range(count):
        if cand[i, OUT] != 0.0 and cand[i, 3] < 0.0:
            c0, c1, c2, n = c0 + cand[i, 0], c1 + cand[i, 1], c2 + cand[i, 2], n + 1
    c0, c1, c2 = c0 / n, c1 / n, c2 / n
    start, best = deep, -math.inf
    for i in range(count):
        if cand[i, OUT] != 0.0 and cand[i, 3] < 0.0:
            d0, d1, d2 = cand[i, 0] - c0, cand[i, 1] - c1, cand[i, 2] - c2
            h = d0 * n0 + d1 * n1 + d2 * n2
            r = math.sqrt(max(0.0, d0 * d0 + d1 * d1 + d2 * d2 - h * h))
            if r > best + CORNER:
                start, best = i, r
    return start


@inline
def _length(cand, i, j):
    d0, d1, d2 = cand[j, 0] - cand[i, 0], cand[j, 1] - cand[i, 1], cand[j, 2] - cand[i, 2]
    return math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@inline
def _in_order(cand, count, out, i0, i1, i2, i3):
    """The kept candidates ``i0..i3`` (-1: none) into ``out`` in the candidates' order, not
    in the order chosen: the same points keep the same rows (and so their slots and warm
    starts) whichever of them is the deepest at a step. Their number."""
    m = 0
    for i in range(count):
        if i == i0 or i == i1 or i == i2 or i == i3:
            m = _write(out, m, cand, i)
    return m


@core
def reduce_patch(cand, count, patch, n0, n1, n2, out, soft):
    """At most four of the ``count`` candidates marked in column ``OUT`` (``mark_reach``,
    ``mark_within``), spanning the patch (K22): the deepest; the one farthest from it; the
    one farthest from the line of those two; the one farthest outside the triangle's edges;
    each distance less the candidate's height above the deepest over ``TILT``, so that of
    points spanning the patch alike the one the shape touches after the smaller tilt comes
    first (``TIE``); on a compliant shape (``soft``) the points below the plane by their
    spread alone (K22'). A point no farther than ``patch`` (and 1e-9) from one kept, or
    adding no area, is not kept: a patch narrower than ``patch`` is one point. Writes them
    to ``out`` in the candidates' order (``_in_order``) and returns their number."""
    deep = -1
    for i in range(count):
        if cand[i, OUT] != 0.0 and (deep < 0 or cand[i, 3] < cand[deep, 3]):
            deep = i
    if deep < 0:
        return 0
    first = _start(cand, count, deep, soft, n0, n1, n2)
    m = _write(out, 0, cand, first)
    second, best = -1, -math.inf
    for i in range(count):
        if cand[i, OUT] != 0.0 and _apart(cand, i, out, m, patch):
            s = _length(cand, first, i) - _rise(cand, i, deep, soft)
            if s > best + TIE:
                second, best = i, s
    if second < 0:
        return m
    m = _write(out, m, cand, second)
    base = _length(cand, first, second)
    third, best = -1, -math.inf
    for i in range(count):
        if cand[i, OUT] != 0.0 and _apart(cand, i, out, m, patch):
            a = abs(_area2(cand, first, second, i, n0, n1, n2))
            s = a / base - _rise(cand, i, deep, soft)
            if a > 1e-18 and s > best + TIE:
                third, best = i, s
    if third < 0:
        return _in_order(cand, count, out, first, second, -1, -1)
    m = _write(out, m, cand, third)
    sign = 1.0 if _area2(cand, first, second, third, n0, n1, n2) > 0.0 else -1.0
    e12, e23, e31 = base, _length(cand, second, third), _length(cand, third, first)
    fourth, best = -1, -math.inf
    for i in range(count):
        if cand[i, OUT] != 0.0 and _apart(cand, i, out, m, patch):
            # how far a point lies outside each edge of the triangle (counter-clockwise
            # about n after ``sign``): positive only beyond that edge
            a = max(-sign * _area2(cand, first, second, i, n0, n1, n2) / e12,
                    -sign * _area2(cand, second, third, i, n0, n1, n2) / e23,
                    -sign * _area2(cand, third, first, i, n0, n1, n2) / e31)
            s = a - _rise(cand, i, deep, soft)
            if a > 1e-18 and s > best + TIE:
                fourth, best = i, s
    return _in_order(cand, count, out, first, second, third, fourth)


@core
def plane_contacts(kind, size, vertices, T, n0, n1, n2, delta, bound, margin, patch, soft,
                   cand, out, V, k, dt):
    """The contacts of shape ``k``, ``(kind, size, vertices)`` at pose ``T``, with the plane
    ``π = n + δ e∞`` (world frame, ``n`` pointing out of it): at most ``MAX_CONTACTS`` rows
    ``[x, y, z, d]`` in ``out`` (K21, K21a, K22), for the shape moving with the twists
    ``V[k]`` (2, 6) over ``dt``, none of its points travelling farther than ``bound``
    (``reach_bound``, ``inf``: unknown); ``soft``: the shape is compliant (K22'). ``cand``
    has ``CANDIDATE_COLUMNS``. Returns their number."""
    count = candidates(kind, size, vertices, T, n0, n1, n2, delta, cand, margin + bound)
    if mark_reach(cand, count, margin, V, k, dt, bound) == 0:
        return 0
    return reduce_patch(cand, count, patch, n0, n1, n2, out, soft)


@core
def shapes_on_plane(kinds, sizes, vertices, offsets, poses, radii, active, compliance, sb,
                    Tb, margin, patch, cand, out, counts, twists, dt):
    """``plane_contacts`` of every shape ``k`` with ``active[k]`` against the plane of size
    ``sb`` (``n``, ``δ`` in its frame) at pose ``Tb``, each moving with its link's twists
    ``twists[k]`` (2, 6) over ``dt``, into ``out[k]`` (``MAX_CONTACTS`` rows each), their
    number into ``counts[k]``; ``compliance[k]`` its stiffness and damping (K41: a
    compliant shape's patch by K22'). ``radii[k]`` bounds shape ``k`` about its frame's
    origin
    (``pairs.bounding_radii``): a shape whose bounding sphere stays ``margin`` above the
    plane however far its points may travel in the step (``reach_bound``) has no candidate
    within reach (K21a) and none is formed."""
    n0, n1, n2 = rotate(Tb, sb[0], sb[1], sb[2])
    delta = sb[3] + n0 * Tb[0, 3] + n1 * Tb[1, 3] + n2 * Tb[2, 3]
    for k in range(kinds.shape[0]):
        counts[k] = 0
        if not active[k]:
            continue
        bound = math.inf
        if math.isfinite(radii[k]):
            bound = reach_bound(poses, k, radii[k], twists, dt)
            if plane_distance(poses[k, 0, 3], poses[k, 1, 3], poses[k, 2, 3], n0, n1, n2,
                              delta) - radii[k] - bound >= margin:
                continue
        counts[k] = plane_contacts(kinds[k], sizes[k], vertices[offsets[k]:offsets[k + 1]],
                                   poses[k], n0, n1, n2, delta, bound, margin, patch,
                                   compliance[k, 0] != 0.0 or compliance[k, 1] != 0.0,
                                   cand, out[k], twists, k, dt)
