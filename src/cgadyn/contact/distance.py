"""Signed distances between convex shapes, compiled (docs/contact.md, K1-K9).

``pair_distance`` is the one entry: two shapes, each given as its kind, size, vertices
(``contact.shapes``) and world pose (a 4x4 matrix), a scratch array ``work`` (``WORK``
floats) and the output ``out`` (``OUT`` floats): the signed distance ``d``, the witness
points ``p_a`` and ``p_b`` and the unit normal ``n`` from ``a`` to ``b``, with
``p_b - p_a = d n`` (coal's convention); ``d < 0`` is a penetration of depth ``-d``. It
returns a status (``OK``, ``PENETRATION_UNSUPPORTED``, ``TWO_PLANES``, ``UNKNOWN_KIND``)
and allocates nothing.

Distances are inner products of the conformal model (``up(x) = e0 + x + ½ x² e∞``, with
``e0 · e∞ = -1``): a point against a plane ``π = n + δ e∞`` is ``X · π`` (K1); two points
are apart by ``sqrt(-2 X · Y)`` (K3), evaluated in the frame of one of them (a translation,
which keeps inner products); a sphere or capsule is its core (a point, a segment) swept by
its radius, so its distance is its core's less the radius (K4). Closed forms: every shape
against a plane by its support point (K5, K6), sphere and capsule pairs by the closest
points of two segments (K7), sphere-box and sphere-cylinder by the closest point of the
box or cylinder, capsule-box, where the segment enters the box, by separating axes (K8).
Any other pair of convex shapes: GJK on the cores, and EPA where they overlap (K9); on a
cylinder's or an ellipsoid's curved surface EPA's depth is refined down the support
function and kept where its bounds meet (K9a, ``refine``); an overlap whose depth is not
known so gets ``PENETRATION_UNSUPPORTED``, which Python words.
"""

from __future__ import annotations

import math

from .._jit import serial
from .shapes import BOX, CAPSULE, CYLINDER, ELLIPSOID, MESH, PLANE, SPHERE

OK, PENETRATION_UNSUPPORTED, TWO_PLANES, UNKNOWN_KIND = 0, 1, 2, 3
OUT = 10
"""``out``: ``[d, p_a (3), p_b (3), n (3)]``."""
GJK_ITERATIONS = 128
GJK_TOLERANCE = 1e-14
"""GJK stops when ``|v|² - v · w <= GJK_TOLERANCE |v|²``: the distance is then exact to
about ``GJK_TOLERANCE |v|`` (polytopes terminate exactly)."""


# --- the conformal model (K1, K3) -----------------------------------------------------------


@serial
def up(x0, x1, x2):
    """The conformal point ``X = e0 + x + ½ x² e∞`` as ``(e0, e1, e2, e3, e∞)`` coefficients."""
    return 1.0, x0, x1, x2, 0.5 * (x0 * x0 + x1 * x1 + x2 * x2)


@serial
def inner(a, b):
    """The inner product of two vectors of G(4,1) in the null basis: ``e_i · e_i = 1``,
    ``e0 · e∞ = -1``, ``e0² = e∞² = 0``."""
    return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] - a[0] * b[4] - a[4] * b[0]


@serial
def plane_distance(x0, x1, x2, n0, n1, n2, delta):
    """The signed distance ``X · π = n · x - δ`` of the point ``x`` to the plane
    ``π = n + δ e∞`` (K1): the conformal inner product of ``X = up(x)`` with ``π``, whose
    e0 coefficient is zero, so that the ``½ x²`` of X drops out (``tests/test_shapes``
    checks it against ``inner(up(x), π)``), written out for the hulls' vertex loops."""
    return n0 * x0 + n1 * x1 + n2 * x2 - delta


@serial
def point_distance(x0, x1, x2, y0, y1, y2):
    """``|x - y| = sqrt(-2 X · Y)`` (K3), in the frame of ``y`` (``Y = e0`` there)."""
    return math.sqrt(max(-2.0 * inner(up(x0 - y0, x1 - y1, x2 - y2), (1.0, 0.0, 0.0, 0.0, 0.0)),
                         0.0))


# --- poses ----------------------------------------------------------------------------------


@serial
def to_world(T, p0, p1, p2):
    return (T[0, 0] * p0 + T[0, 1] * p1 + T[0, 2] * p2 + T[0, 3],
            T[1, 0] * p0 + T[1, 1] * p1 + T[1, 2] * p2 + T[1, 3],
            T[2, 0] * p0 + T[2, 1] * p1 + T[2, 2] * p2 + T[2, 3])


@serial
def rotate(T, d0, d1, d2):
    return (T[0, 0] * d0 + T[0, 1] * d1 + T[0, 2] * d2,
            T[1, 0] * d0 + T[1, 1] * d1 + T[1, 2] * d2,
            T[2, 0] * d0 + T[2, 1] * d1 + T[2, 2] * d2)


@serial
def rotate_back(T, d0, d1, d2):
    return (T[0, 0] * d0 + T[1, 0] * d1 + T[2, 0] * d2,
            T[0, 1] * d0 + T[1, 1] * d1 + T[2, 1] * d2,
            T[0, 2] * d0 + T[1, 2] * d1 + T[2, 2] * d2)


@serial
def to_local(T, p0, p1, p2):
    return rotate_back(T, p0 - T[0, 3], p1 - T[1, 3], p2 - T[2, 3])


# --- support points of the cores (K6) ----------------------------------------------------


@serial
def support(kind, size, vertices, T, d0, d1, d2):
    """The point of the shape's core (a sphere's centre, a capsule's segment, the shape
    itself otherwise) farthest along the world direction ``d``, in the world (K6)."""
    l0, l1, l2 = rotate_back(T, d0, d1, d2)
    p0, p1, p2 = 0.0, 0.0, 0.0
    if kind == CAPSULE:
        p2 = size[1] if l2 >= 0.0 else -size[1]
    elif kind == BOX:
        p0 = size[0] if l0 >= 0.0 else -size[0]
        p1 = size[1] if l1 >= 0.0 else -size[1]
        p2 = size[2] if l2 >= 0.0 else -size[2]
    elif kind == CYLINDER:
        rho = math.sqrt(l0 * l0 + l1 * l1)
        if rho > 0.0:
            p0 = size[0] * l0 / rho
            p1 = size[0] * l1 / rho
        p2 = size[1] if l2 >= 0.0 else -size[1]
    elif kind == ELLIPSOID:  # A² l / |A l|, A = diag(radii) (K6a)
        a0, a1, a2 = size[0] * l0, size[1] * l1, size[2] * l2
        norm = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        if norm > 0.0:
            p0, p1, p2 = size[0] * a0 / norm, size[1] * a1 / norm, size[2] * a2 / norm
    elif kind == MESH:
        best = -math.inf
        for i in range(vertices.shape[0]):
            s = vertices[i, 0] * l0 + vertices[i, 1] * l1 + vertices[i, 2] * l2
            if s > best:
                best = s
                p0, p1, p2 = vertices[i, 0], vertices[i, 1], vertices[i, 2]
    return to_world(T, p0, p1, p2)


@serial
def write(out, d, a0, a1, a2, b0, b1, b2, n0, n1, n2):
    out[0] = d
    out[1], out[2], out[3] = a0, a1, a2
    out[4], out[5], out[6] = b0, b1, b2
    out[7], out[8], out[9] = n0, n1, n2


@serial
def inflate(out, ra, rb):
    """From the cores' distance to the shapes': each witness point moves out by its radius
    along the normal, and the distance shrinks by both (K4)."""
    n0, n1, n2 = out[7], out[8], out[9]
    out[0] -= ra + rb
    out[1] += ra * n0
    out[2] += ra * n1
    out[3] += ra * n2
    out[4] -= rb * n0
    out[5] -= rb * n1
    out[6] -= rb * n2


# --- against a plane (K5) ------------------------------------------------------------------


@serial
def against_plane(ka, sa, va, Ta, sb, Tb, out):
    """Shape ``a`` against the half-space ``b``: its deepest point is its core's support
    point along ``-n`` (for a capsule, the lower end of its segment), at ``X · π`` from the
    plane (K1, K5), less its radius."""
    n0, n1, n2 = rotate(Tb, sb[0], sb[1], sb[2])
    delta = sb[3] + n0 * Tb[0, 3] + n1 * Tb[1, 3] + n2 * Tb[2, 3]
    p0, p1, p2 = support(ka, sa, va, Ta, -n0, -n1, -n2)
    s = plane_distance(p0, p1, p2, n0, n1, n2, delta)
    write(out, s, p0, p1, p2, p0 - s * n0, p1 - s * n1, p2 - s * n2, -n0, -n1, -n2)
    inflate(out, sa[0] if (ka == SPHERE or ka == CAPSULE) else 0.0, 0.0)
    return OK


# --- spheres and capsules (K7) ----------------------------------------------------------


@serial
def segment(kind, size, T):
    """The core of a sphere (a point: both ends at its centre) or a capsule (its segment),
    in the world."""
    h = size[1] if kind == CAPSULE else 0.0
    a0, a1, a2 = to_world(T, 0.0, 0.0, -h)
    b0, b1, b2 = to_world(T, 0.0, 0.0, h)
    return a0, a1, a2, b0, b1, b2


@serial
def _clamp01(x):
    return min(max(x, 0.0), 1.0)


@serial
def closest_on_segments(p0, p1, p2, q0, q1, q2, r0, r1, r2, t0, t1, t2):
    """The parameters ``(s, t)`` in [0, 1] of the closest points ``p + s (q - p)`` and
    ``r + t (t - r)`` of two segments, either of which may be a point (Ericson's clamped
    solution, Real-Time Collision Detection 5.1.9)."""
    d10, d11, d12 = q0 - p0, q1 - p1, q2 - p2
    d20, d21, d22 = t0 - r0, t1 - r1, t2 - r2
    w0, w1, w2 = p0 - r0, p1 - r1, p2 - r2
    a = d10 * d10 + d11 * d11 + d12 * d12
    e = d20 * d20 + d21 * d21 + d22 * d22
    f = d20 * w0 + d21 * w1 + d22 * w2
    s, t = 0.0, 0.0
    if a > 0.0 or e > 0.0:
        if a == 0.0:
            t = _clamp01(f / e)
        else:
            c = d10 * w0 + d11 * w1 + d12 * w2
            if e == 0.0:
                s = _clamp01(-c / a)
            else:
                b = d10 * d20 + d11 * d21 + d12 * d22
                denom = a * e - b * b
                s = _clamp01((b * f - c * e) / denom) if denom > 1e-14 * a * e else 0.0
                t = (b * s + f) / e
                if t < 0.0:
                    t = 0.0
                    s = _clamp01(-c / a)
                elif t > 1.0:
                    t = 1.0
                    s = _clamp01((b - c) / a)
    return s, t


@serial
def swept(ka, sa, Ta, kb, sb, Tb, out):
    """Spheres and capsules: the closest points ``c_a``, ``c_b`` of their cores (two
    segments, Ericson's clamped solution), apart by ``sqrt(-2 C_a · C_b)`` (K3), less both
    radii (K4, K7)."""
    p0, p1, p2, q0, q1, q2 = segment(ka, sa, Ta)
    r0, r1, r2, t0, t1, t2 = segment(kb, sb, Tb)
    s, t = closest_on_segments(p0, p1, p2, q0, q1, q2, r0, r1, r2, t0, t1, t2)
    d10, d11, d12 = q0 - p0, q1 - p1, q2 - p2
    d20, d21, d22 = t0 - r0, t1 - r1, t2 - r2
    c0, c1, c2 = p0 + s * d10, p1 + s * d11, p2 + s * d12
    k0, k1, k2 = r0 + t * d20, r1 + t * d21, r2 + t * d22
    dist = point_distance(k0, k1, k2, c0, c1, c2)
    if dist > 0.0:
        n0, n1, n2 = (k0 - c0) / dist, (k1 - c1) / dist, (k2 - c2) / dist
    else:  # concentric: any direction separates them
        n0, n1, n2 = 0.0, 0.0, 1.0
    write(out, dist, c0, c1, c2, k0, k1, k2, n0, n1, n2)
    inflate(out, sa[0], sb[0])
    return OK


# --- a sphere against a box (K8) -----------------------------------------------------------


@serial
def sphere_box(sa, Ta, sb, Tb, out):
    """The closest point of the box to the sphere's centre ``c`` (``c`` clamped to the box,
    in its frame) when ``c`` is outside; inside, the nearest face, whose normal is the
    normal (K8). Then less the radius (K4)."""
    c0, c1, c2 = Ta[0, 3], Ta[1, 3], Ta[2, 3]
    x0, x1, x2 = to_local(Tb, c0, c1, c2)
    h0, h1, h2 = sb[0], sb[1], sb[2]
    y0, y1, y2 = min(max(x0, -h0), h0), min(max(x1, -h1), h1), min(max(x2, -h2), h2)
    if y0 != x0 or y1 != x1 or y2 != x2:
        b0, b1, b2 = to_world(Tb, y0, y1, y2)
        dist = point_distance(b0, b1, b2, c0, c1, c2)
        n0, n1, n2 = (b0 - c0) / dist, (b1 - c1) / dist, (b2 - c2) / dist
    else:
        g0, g1, g2 = h0 - abs(x0), h1 - abs(x1), h2 - abs(x2)
        m0, m1, m2 = 0.0, 0.0, 0.0
        if g0 <= g1 and g0 <= g2:
            dist = -g0
            m0 = -1.0 if x0 >= 0.0 else 1.0
            y0 = h0 if x0 >= 0.0 else -h0
        elif g1 <= g2:
            dist = -g1
            m1 = -1.0 if x1 >= 0.0 else 1.0
            y1 = h1 if x1 >= 0.0 else -h1
        else:
            dist = -g2
            m2 = -1.0 if x2 >= 0.0 else 1.0
            y2 = h2 if x2 >= 0.0 else -h2
        n0, n1, n2 = rotate(Tb, m0, m1, m2)
        b0, b1, b2 = to_world(Tb, y0, y1, y2)
    write(out, dist, c0, c1, c2, b0, b1, b2, n0, n1, n2)
    inflate(out, sa[0], 0.0)
    return OK


@serial
def sphere_cylinder(sa, Ta, sb, Tb, out):
    """The sphere's centre ``c`` in the cylinder's frame: outside, the cylinder's closest
    point (its radial part clamped to the radius, its height to the caps); inside, the
    nearer of the side and the cap, whose outward normal is the normal (K8), less the
    radius (K4)."""
    c0, c1, c2 = Ta[0, 3], Ta[1, 3], Ta[2, 3]
    x0, x1, x2 = to_local(Tb, c0, c1, c2)
    r, h = sb[0], sb[1]
    rho = math.sqrt(x0 * x0 + x1 * x1)
    u0, u1 = (x0 / rho, x1 / rho) if rho > 0.0 else (1.0, 0.0)
    if rho > r or abs(x2) > h:
        k = min(rho, r)
        b0, b1, b2 = to_world(Tb, k * u0, k * u1, min(max(x2, -h), h))
        dist = point_distance(b0, b1, b2, c0, c1, c2)
        n0, n1, n2 = (b0 - c0) / dist, (b1 - c1) / dist, (b2 - c2) / dist
    else:
        side, cap = r - rho, h - abs(x2)
        top = h if x2 >= 0.0 else -h
        if cap <= side:
            dist = -cap
            n0, n1, n2 = rotate(Tb, 0.0, 0.0, -top / h)
            b0, b1, b2 = to_world(Tb, x0, x1, top)
        else:
            dist = -side
            n0, n1, n2 = rotate(Tb, -u0, -u1, 0.0)
            b0, b1, b2 = to_world(Tb, r * u0, r * u1, x2)
    write(out, dist, c0, c1, c2, b0, b1, b2, n0, n1, n2)
    inflate(out, sa[0], 0.0)
    return OK


# --- a capsule against a box, overlapping (K8) ----------------------------------------------


@serial
def _axis_depth(m0, m1, m2, p0, p1, p2, q0, q1, q2, Tb, sb):
    """How far the box must move along ``+m`` (first) or ``-m`` (second) to clear the
    segment ``p q``: the overlap of their projections on the unit axis ``m``."""
    cb = m0 * Tb[0, 3] + m1 * Tb[1, 3] + m2 * Tb[2, 3]
    rb = 0.0
    for i in range(3):
        rb += sb[i] * abs(m0 * Tb[0, i] + m1 * Tb[1, i] + m2 * Tb[2, i])
    s0 = m0 * p0 + m1 * p1 + m2 * p2
    s1 = m0 * q0 + m1 * q1 + m2 * q2
    return max(s0, s1) - (cb - rb), (cb + rb) - min(s0, s1)


@serial
def capsule_box_overlap(sa, Ta, sb, Tb, out):
    """A capsule whose segment ``p q`` enters the box: the separating axes of a segment and
    a box are the box's three face normals and the three crossings of the segment with the
    box's edges; the least overlap of the projections on them is the cores' penetration
    depth and its axis the normal (K8). The capsule's deepest point is its segment's support
    along the normal, or, on an edge axis, the segment's point closest to that box edge."""
    p0, p1, p2, q0, q1, q2 = segment(CAPSULE, sa, Ta)
    e0, e1, e2 = q0 - p0, q1 - p1, q2 - p2
    depth, n0, n1, n2, edge = math.inf, 0.0, 0.0, 1.0, -1
    for k in range(6):
        i = k % 3
        u0, u1, u2 = Tb[0, i], Tb[1, i], Tb[2, i]
        if k >= 3:  # the segment crossed with edge direction i
            u0, u1, u2 = e1 * u2 - e2 * u1, e2 * u0 - e0 * u2, e0 * u1 - e1 * u0
            norm = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
            if norm <= 1e-9 * math.sqrt(e0 * e0 + e1 * e1 + e2 * e2):
                continue
            u0, u1, u2 = u0 / norm, u1 / norm, u2 / norm
        plus, minus = _axis_depth(u0, u1, u2, p0, p1, p2, q0, q1, q2, Tb, sb)
        if plus < depth:
            depth, n0, n1, n2, edge = plus, u0, u1, u2, (i if k >= 3 else -1)
        if minus < depth:
            depth, n0, n1, n2, edge = minus, -u0, -u1, -u2, (i if k >= 3 else -1)
    if edge < 0:  # a face: the segment's end deepest along n
        if n0 * e0 + n1 * e1 + n2 * e2 >= 0.0:
            c0, c1, c2 = q0, q1, q2
        else:
            c0, c1, c2 = p0, p1, p2
    else:  # an edge of the box, parallel to its axis ``edge``, deepest along -n
        l0, l1, l2 = rotate_back(Tb, -n0, -n1, -n2)
        y0 = sb[0] if l0 >= 0.0 else -sb[0]
        y1 = sb[1] if l1 >= 0.0 else -sb[1]
        y2 = sb[2] if l2 >= 0.0 else -sb[2]
        if edge == 0:
            a0, a1, a2 = to_world(Tb, -sb[0], y1, y2)
            b0, b1, b2 = to_world(Tb, sb[0], y1, y2)
        elif edge == 1:
            a0, a1, a2 = to_world(Tb, y0, -sb[1], y2)
            b0, b1, b2 = to_world(Tb, y0, sb[1], y2)
        else:
            a0, a1, a2 = to_world(Tb, y0, y1, -sb[2])
            b0, b1, b2 = to_world(Tb, y0, y1, sb[2])
        s, _ = closest_on_segments(p0, p1, p2, q0, q1, q2, a0, a1, a2, b0, b1, b2)
        c0, c1, c2 = p0 + s * e0, p1 + s * e1, p2 + s * e2
    r = sa[0]
    d = -depth - r
    a0, a1, a2 = c0 + r * n0, c1 + r * n1, c2 + r * n2
    write(out, d, a0, a1, a2, a0 + d * n0, a1 + d * n1, a2 + d * n2, n0, n1, n2)
    return OK


# --- GJK on the cores (K9) ----------------------------------------------------------------


@serial
def _triangle(W, i, j, k):
    """Barycentric weights of the point of triangle ``W[i], W[j], W[k]`` (rows' first three
    floats) closest to the origin (Ericson, Real-Time Collision Detection, 5.1.5)."""
    a0, a1, a2 = W[i, 0], W[i, 1], W[i, 2]
    b0, b1, b2 = W[j, 0], W[j, 1], W[j, 2]
    c0, c1, c2 = W[k, 0], W[k, 1], W[k, 2]
    ab0, ab1, ab2 = b0 - a0, b1 - a1, b2 - a2
    ac0, ac1, ac2 = c0 - a0, c1 - a1, c2 - a2
    d1 = -(ab0 * a0 + ab1 * a1 + ab2 * a2)
    d2 = -(ac0 * a0 + ac1 * a1 + ac2 * a2)
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0
    d3 = -(ab0 * b0 + ab1 * b1 + ab2 * b2)
    d4 = -(ac0 * b0 + ac1 * b1 + ac2 * b2)
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        return 1.0 - v, v, 0.0
    d5 = -(ab0 * c0 + ab1 * c1 + ab2 * c2)
    d6 = -(ac0 * c0 + ac1 * c1 + ac2 * c2)
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        return 1.0 - w, 0.0, w
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - w, w
    denom = 1.0 / (va + vb + vc)
    v = vb * denom
    w = vc * denom
    return 1.0 - v - w, v, w


@serial
def _outside(W, i, j, k, m):
    """Whether the origin lies on the other side of face ``i j k`` than vertex ``m`` (or
    the tetrahedron is flat)."""
    ab0, ab1, ab2 = W[j, 0] - W[i, 0], W[j, 1] - W[i, 1], W[j, 2] - W[i, 2]
    ac0, ac1, ac2 = W[k, 0] - W[i, 0], W[k, 1] - W[i, 1], W[k, 2] - W[i, 2]
    n0 = ab1 * ac2 - ab2 * ac1
    n1 = ab2 * ac0 - ab0 * ac2
    n2 = ab0 * ac1 - ab1 * ac0
    sp = -(n0 * W[i, 0] + n1 * W[i, 1] + n2 * W[i, 2])
    sd = n0 * (W[m, 0] - W[i, 0]) + n1 * (W[m, 1] - W[i, 1]) + n2 * (W[m, 2] - W[i, 2])
    return sd == 0.0 or sp * sd < 0.0


@serial
def _flat(W):
    """Whether the tetrahedron ``W[:4]`` is flat to rounding: its volume (times six) at most
    1e-12 of its longest edge from ``W[0]`` cubed. Then no sign of a face tells on which
    side the origin lies (a cylinder's rim gives GJK support points a few nanometres apart),
    and the origin is taken as outside: the nearest of its faces is the answer."""
    a0, a1, a2 = W[1, 0] - W[0, 0], W[1, 1] - W[0, 1], W[1, 2] - W[0, 2]
    b0, b1, b2 = W[2, 0] - W[0, 0], W[2, 1] - W[0, 1], W[2, 2] - W[0, 2]
    c0, c1, c2 = W[3, 0] - W[0, 0], W[3, 1] - W[0, 1], W[3, 2] - W[0, 2]
    volume = a0 * (b1 * c2 - b2 * c1) + a1 * (b2 * c0 - b0 * c2) + a2 * (b0 * c1 - b1 * c0)
    edge = math.sqrt(max(a0 * a0 + a1 * a1 + a2 * a2, b0 * b0 + b1 * b1 + b2 * b2,
                         c0 * c0 + c1 * c1 + c2 * c2))
    return abs(volume) <= 1e-12 * edge * edge * edge


@serial
def _set_weights(W, i, j, k, u, v, w):
    W[i, 9] = u
    W[j, 9] = v
    W[k, 9] = w


@serial
def _closest(W, n):
    """The point of the simplex ``W[:n]`` closest to the origin: its barycentric weights in
    ``W[:, 9]``; the simplex is then cut to the vertices of positive weight. Returns the new
    size, 0 where the origin lies inside a tetrahedron."""
    for i in range(4):
        W[i, 9] = 0.0
    if n == 1:
        W[0, 9] = 1.0
    elif n == 2:
        e0, e1, e2 = W[1, 0] - W[0, 0], W[1, 1] - W[0, 1], W[1, 2] - W[0, 2]
        ee = e0 * e0 + e1 * e1 + e2 * e2
        t = _clamp01(-(W[0, 0] * e0 + W[0, 1] * e1 + W[0, 2] * e2) / ee) if ee > 0.0 else 0.0
        W[0, 9] = 1.0 - t
        W[1, 9] = t
    elif n == 3:
        u, v, w = _triangle(W, 0, 1, 2)
        _set_weights(W, 0, 1, 2, u, v, w)
    else:
        best = math.inf
        inside = not _flat(W)
        faces = ((0, 1, 2, 3), (0, 2, 3, 1), (0, 3, 1, 2), (1, 3, 2, 0))
        for f in faces:  # the nearest of the four faces' nearest points: no sign decides
            i, j, k, m = f
            if _outside(W, i, j, k, m):
                inside = False
            if True:
                u, v, w = _triangle(W, i, j, k)
                x0 = u * W[i, 0] + v * W[j, 0] + w * W[k, 0]
                x1 = u * W[i, 1] + v * W[j, 1] + w * W[k, 1]
                x2 = u * W[i, 2] + v * W[j, 2] + w * W[k, 2]
                dd = x0 * x0 + x1 * x1 + x2 * x2
                if dd < best:
                    best = dd
                    for q in range(4):
                        W[q, 9] = 0.0
                    _set_weights(W, i, j, k, u, v, w)
        if inside:
            return 0
    kept = 0
    for i in range(n):
        if W[i, 9] > 0.0:
            if kept != i:
                for c in range(10):
                    W[kept, c] = W[i, c]
            kept += 1
    return kept


@serial
def _add(W, n, ka, sa, va, Ta, kb, sb, vb, Tb, d0, d1, d2):
    """Append ``w = s_a(d) - s_b(-d)``, a support point of the Minkowski difference of the
    cores along ``d``, to the simplex."""
    a0, a1, a2 = support(ka, sa, va, Ta, d0, d1, d2)
    b0, b1, b2 = support(kb, sb, vb, Tb, -d0, -d1, -d2)
    W[n, 0], W[n, 1], W[n, 2] = a0 - b0, a1 - b1, a2 - b2
    W[n, 3], W[n, 4], W[n, 5] = a0, a1, a2
    W[n, 6], W[n, 7], W[n, 8] = b0, b1, b2
    W[n, 9] = 0.0


@serial
def _point(W, n, c):
    """The weighted sum of column ``c .. c+2`` of the simplex."""
    x0, x1, x2 = 0.0, 0.0, 0.0
    for i in range(n):
        x0 += W[i, 9] * W[i, c]
        x1 += W[i, 9] * W[i, c + 1]
        x2 += W[i, 9] * W[i, c + 2]
    return x0, x1, x2


@serial
def gjk(ka, sa, va, Ta, kb, sb, vb, Tb, work, out):
    """The distance of the cores of two convex shapes by GJK (Gilbert, Johnson and Keerthi
    1988; K9): ``v``, the point of the Minkowski difference ``A - B`` closest to the
    origin, is approached by simplices of support points; then ``p_a``, ``p_b`` are the
    same weights of the vertices' points of ``A`` and ``B``. Returns 0 when it wrote the
    distance into ``out``; where the cores overlap, the size of the simplex left in
    ``work`` (4: a tetrahedron around the origin; fewer: the origin on it), for EPA."""
    W = work[:40].reshape((4, 10))
    previous = work[40:80]
    _add(W, 0, ka, sa, va, Ta, kb, sb, vb, Tb,
         Tb[0, 3] - Ta[0, 3] + 1e-3, Tb[1, 3] - Ta[1, 3], Tb[2, 3] - Ta[2, 3])
    W[0, 9] = 1.0
    n = 1
    v0, v1, v2 = W[0, 0], W[0, 1], W[0, 2]
    for _ in range(GJK_ITERATIONS):
        vv = v0 * v0 + v1 * v1 + v2 * v2
        if vv <= 1e-28:
            return n
        _add(W, n, ka, sa, va, Ta, kb, sb, vb, Tb, -v0, -v1, -v2)
        vw = v0 * W[n, 0] + v1 * W[n, 1] + v2 * W[n, 2]
        if vv - vw <= GJK_TOLERANCE * vv:
            break
        duplicate = False
        for i in range(n):
            if W[i, 0] == W[n, 0] and W[i, 1] == W[n, 1] and W[i, 2] == W[n, 2]:
                duplicate = True
        if duplicate:
            break
        for i in range(40):
            previous[i] = work[i]
        m = _closest(W, n + 1)
        if m == 0:
            return 4
        u0, u1, u2 = _point(W, m, 0)
        if u0 * u0 + u1 * u1 + u2 * u2 >= vv:  # no progress (rounding): keep the last v
            for i in range(40):
                work[i] = previous[i]
            break
        n = m
        v0, v1, v2 = u0, u1, u2
    a0, a1, a2 = _point(W, n, 3)
    b0, b1, b2 = _point(W, n, 6)
    dist = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    if dist <= 1e-14:
        return n
    write(out, dist, a0, a1, a2, b0, b1, b2, -v0 / dist, -v1 / dist, -v2 / dist)
    return 0



# --- EPA: the depth of overlapping cores (K9) ------------------------------------------------

EPA_VERTICES = 128
EPA_FACES = 2 * EPA_VERTICES + 64  # a closed polytope of V vertices has 2V - 4 faces
EPA_EDGES = 128
EPA_TOLERANCE = 1e-12
_V0 = 80
_F0 = _V0 + 9 * EPA_VERTICES
_E0 = _F0 + 8 * EPA_FACES
WORK = _E0 + 2 * EPA_EDGES
"""The scratch ``work`` of ``pair_distance``: GJK's simplex (four vertices, each ``w = a - b,
a, b`` and its weight) and its copy, then EPA's vertices, faces (three vertices, the unit
normal, the distance, alive) and horizon edges."""


@serial
def _face(V, F, f, i, j, k):
    """Face ``f`` of the polytope on vertices ``i j k`` (counter-clockwise seen from
    outside): its unit normal and its distance from the origin. False if degenerate."""
    ab0, ab1, ab2 = V[j, 0] - V[i, 0], V[j, 1] - V[i, 1], V[j, 2] - V[i, 2]
    ac0, ac1, ac2 = V[k, 0] - V[i, 0], V[k, 1] - V[i, 1], V[k, 2] - V[i, 2]
    n0 = ab1 * ac2 - ab2 * ac1
    n1 = ab2 * ac0 - ab0 * ac2
    n2 = ab0 * ac1 - ab1 * ac0
    norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if norm <= 0.0:
        return False
    F[f, 0], F[f, 1], F[f, 2] = i, j, k
    F[f, 3], F[f, 4], F[f, 5] = n0 / norm, n1 / norm, n2 / norm
    F[f, 6] = (n0 * V[i, 0] + n1 * V[i, 1] + n2 * V[i, 2]) / norm
    F[f, 7] = 1.0
    return True


@serial
def _edge(E, ne, a, b):
    """Add the horizon edge ``a b``, or remove ``b a`` where a visible face had it."""
    for e in range(ne):
        if E[e, 0] == b and E[e, 1] == a:
            E[e, 0], E[e, 1] = E[ne - 1, 0], E[ne - 1, 1]
            return ne - 1
    if ne < EPA_EDGES:
        E[ne, 0], E[ne, 1] = a, b
        return ne + 1
    return -1


@serial
def _known(V, nv, W, tol):
    """Whether the support point ``W[0]`` is within ``tol`` of a vertex of the polytope."""
    for v in range(nv):
        x0, x1, x2 = V[v, 0] - W[0, 0], V[v, 1] - W[0, 1], V[v, 2] - W[0, 2]
        if x0 * x0 + x1 * x1 + x2 * x2 <= tol * tol:
            return True
    return False


@serial
def epa(ka, sa, va, Ta, kb, sb, vb, Tb, n, work, out):
    """The penetration depth of overlapping cores: the expanding polytope algorithm (van
    den Bergen 2001). From GJK's simplex around the origin (blown up to a tetrahedron by
    support points along the axes where GJK stopped on it), the face of the Minkowski
    difference nearest the origin is pushed out by the support point along its normal until
    it no longer moves: its normal ``n`` is the direction that separates the cores fastest,
    its distance ``δ`` the depth, ``p_a - p_b = δ n``. Exact on polytopes (points, segments,
    boxes, convex meshes); on a cylinder's or an ellipsoid's curved surface a lower bound,
    which ``refine`` polishes. Returns False where it cannot build or grow the polytope."""
    W = work[:40].reshape((4, 10))
    V = work[_V0:_F0].reshape((EPA_VERTICES, 9))
    F = work[_F0:_E0].reshape((EPA_FACES, 8))
    E = work[_E0:WORK].reshape((EPA_EDGES, 2))
    for i in range(n):
        for c in range(9):
            V[i, c] = W[i, c]
    axis = 0
    while n < 4 and axis < 6:  # blow the simplex up to a tetrahedron
        d = 1.0 if axis < 3 else -1.0
        _add(W, 0, ka, sa, va, Ta, kb, sb, vb, Tb, d if axis % 3 == 0 else 0.0,
             d if axis % 3 == 1 else 0.0, d if axis % 3 == 2 else 0.0)
        axis += 1
        x0, x1, x2 = W[0, 0] - V[0, 0], W[0, 1] - V[0, 1], W[0, 2] - V[0, 2]
        if n == 1:
            grows = x0 * x0 + x1 * x1 + x2 * x2 > 1e-20
        else:
            e0, e1, e2 = V[1, 0] - V[0, 0], V[1, 1] - V[0, 1], V[1, 2] - V[0, 2]
            c0, c1, c2 = e1 * x2 - e2 * x1, e2 * x0 - e0 * x2, e0 * x1 - e1 * x0
            if n == 2:
                grows = c0 * c0 + c1 * c1 + c2 * c2 > 1e-20
            else:
                f0, f1, f2 = V[2, 0] - V[0, 0], V[2, 1] - V[0, 1], V[2, 2] - V[0, 2]
                grows = abs(c0 * f0 + c1 * f1 + c2 * f2) > 1e-15
        if grows:
            for c in range(9):
                V[n, c] = W[0, c]
            n += 1
    if n < 4:
        return False
    nf = 0
    for f in range(4):  # the tetrahedron's faces, turned outwards
        i, j, k, m = (0, 1, 2, 3) if f == 0 else (0, 3, 1, 2) if f == 1 else \
            (0, 2, 3, 1) if f == 2 else (1, 3, 2, 0)
        if not _face(V, F, nf, i, j, k):
            return False
        side = F[nf, 3] * (V[m, 0] - V[i, 0]) + F[nf, 4] * (V[m, 1] - V[i, 1]) + \
            F[nf, 5] * (V[m, 2] - V[i, 2])
        if side > 0.0:
            _face(V, F, nf, i, k, j)
        nf += 1
    nv = 4
    m0 = m1 = m2 = depth = 0.0
    i = j = k = 0
    for _ in range(EPA_VERTICES):
        best = -1
        for f in range(nf):
            if F[f, 7] > 0.0 and (best < 0 or F[f, 6] < F[best, 6]):
                best = f
        if best < 0:
            return False
        # the nearest face, kept: its slot may take a new face below
        m0, m1, m2, depth = F[best, 3], F[best, 4], F[best, 5], F[best, 6]
        i, j, k = int(F[best, 0]), int(F[best, 1]), int(F[best, 2])
        if nv == EPA_VERTICES:
            break
        _add(W, 0, ka, sa, va, Ta, kb, sb, vb, Tb, m0, m1, m2)
        reach = m0 * W[0, 0] + m1 * W[0, 1] + m2 * W[0, 2]
        tol = EPA_TOLERANCE * max(1.0, abs(depth))
        if reach - depth <= tol:
            break
        if _known(V, nv, W, tol):  # a vertex already there: a flat patch, no progress
            break
        for c in range(9):
            V[nv, c] = W[0, c]
        ne = 0
        for f in range(nf):  # the faces that see the new vertex go; their rim stays
            if F[f, 7] > 0.0:
                a, b, e = int(F[f, 0]), int(F[f, 1]), int(F[f, 2])
                if F[f, 3] * (V[nv, 0] - V[a, 0]) + F[f, 4] * (V[nv, 1] - V[a, 1]) + \
                        F[f, 5] * (V[nv, 2] - V[a, 2]) > tol:  # coplanar ones stay
                    F[f, 7] = 0.0
                    ne = _edge(E, ne, a, b)
                    if ne >= 0:
                        ne = _edge(E, ne, b, e)
                    if ne >= 0:
                        ne = _edge(E, ne, e, a)
                    if ne < 0:
                        return False
        alive = 0
        for f in range(nf):
            alive += F[f, 7] > 0.0
        if ne == 0 or alive + ne > EPA_FACES:
            break
        slot, closed = 0, True  # the new faces fill the slots of dead ones, then the end
        for h in range(ne):
            while slot < nf and F[slot, 7] > 0.0:
                slot += 1
            if slot == nf:
                F[nf, 7] = 0.0
                nf += 1
            closed = _face(V, F, slot, int(E[h, 0]), int(E[h, 1]), nv) and closed
        if not closed:  # a degenerate face would leave a hole: the last polytope's answer
            break
        nv += 1
    if not depth >= -EPA_TOLERANCE:  # the origin outside the polytope: not grown right
        return False
    depth = max(depth, 0.0)  # the origin on a face, to rounding: the cores touch
    # barycentric weights of δ n, the face's point nearest the origin
    x0, x1, x2 = depth * m0 - V[i, 0], depth * m1 - V[i, 1], depth * m2 - V[i, 2]
    ab0, ab1, ab2 = V[j, 0] - V[i, 0], V[j, 1] - V[i, 1], V[j, 2] - V[i, 2]
    ac0, ac1, ac2 = V[k, 0] - V[i, 0], V[k, 1] - V[i, 1], V[k, 2] - V[i, 2]
    d00 = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
    d01 = ab0 * ac0 + ab1 * ac1 + ab2 * ac2
    d11 = ac0 * ac0 + ac1 * ac1 + ac2 * ac2
    d20 = x0 * ab0 + x1 * ab1 + x2 * ab2
    d21 = x0 * ac0 + x1 * ac1 + x2 * ac2
    det = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / det
    w = (d00 * d21 - d01 * d20) / det
    u = 1.0 - v - w
    a0 = u * V[i, 3] + v * V[j, 3] + w * V[k, 3]
    a1 = u * V[i, 4] + v * V[j, 4] + w * V[k, 4]
    a2 = u * V[i, 5] + v * V[j, 5] + w * V[k, 5]
    b0 = u * V[i, 6] + v * V[j, 6] + w * V[k, 6]
    b1 = u * V[i, 7] + v * V[j, 7] + w * V[k, 7]
    b2 = u * V[i, 8] + v * V[j, 8] + w * V[k, 8]
    write(out, -depth, a0, a1, a2, b0, b1, b2, m0, m1, m2)
    return True


REFINE_ITERATIONS = 60
"""The most steps of each descent of ``refine``."""
DEPTH_GAP = 1e-7
"""Metres: the largest gap between EPA's depth, a lower bound on a curved shape, and the
refined one, an upper bound, that ``refine`` accepts (its answer's error is at most that)."""
DEPTH_SLACK = 0.05
"""Where EPA's polytope stops short of a curved surface, its depth is a loose lower bound:
the refined depth is kept if the gap is at most this fraction of it (its error at most
that; ``tests/test_shapes.py`` measures it)."""
CREASE = 1e-2
"""How near (in ``|n · e|``) a normal that stops descending must lie to a crease of the
support function (``n`` orthogonal to a box's axis ``e`` or a cylinder's) to be put on it."""


@serial
def _project(A, na, n0, n1, n2):
    """``n`` with its components along the orthonormal rows ``A[:na]`` removed."""
    for i in range(na):
        c = n0 * A[i, 0] + n1 * A[i, 1] + n2 * A[i, 2]
        n0, n1, n2 = n0 - c * A[i, 0], n1 - c * A[i, 1], n2 - c * A[i, 2]
    return n0, n1, n2


@serial
def _descend(ka, sa, va, Ta, kb, sb, vb, Tb, W, A, na, lower, n0, n1, n2):
    """Steps ``n - α g`` down the support function ``f`` of the difference from the unit
    ``n``, kept orthogonal to the rows ``A[:na]`` (a crease, K9a), until ``f`` is within
    ``DEPTH_GAP`` of ``lower`` or stops falling: returns the last ``n`` and ``f``, with
    ``W[0]`` its support point."""
    _add(W, 0, ka, sa, va, Ta, kb, sb, vb, Tb, n0, n1, n2)
    f = n0 * W[0, 0] + n1 * W[0, 1] + n2 * W[0, 2]
    g0, g1, g2 = _project(A, na, W[0, 0] - f * n0, W[0, 1] - f * n1, W[0, 2] - f * n2)
    alpha = 1.0
    for _ in range(REFINE_ITERATIONS):
        if f - lower <= DEPTH_GAP:
            break
        gg = g0 * g0 + g1 * g1 + g2 * g2
        moved = False
        f1 = f
        m0, m1, m2 = n0, n1, n2
        for _ in range(40):  # halve α until f falls
            m0, m1, m2 = _project(A, na, n0 - alpha * g0, n1 - alpha * g1, n2 - alpha * g2)
            r = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
            m0, m1, m2 = m0 / r, m1 / r, m2 / r
            _add(W, 1, ka, sa, va, Ta, kb, sb, vb, Tb, m0, m1, m2)
            f1 = m0 * W[1, 0] + m1 * W[1, 1] + m2 * W[1, 2]
            if f1 < f - 1e-4 * alpha * gg:
                moved = True
                break
            alpha *= 0.5
        if not moved:
            break
        h0, h1, h2 = _project(A, na, W[1, 0] - f1 * m0, W[1, 1] - f1 * m1,
                              W[1, 2] - f1 * m2)
        d0, d1, d2 = m0 - n0, m1 - n1, m2 - n2
        y0, y1, y2 = h0 - g0, h1 - g1, h2 - g2
        dy = d0 * y0 + d1 * y1 + d2 * y2
        alpha = (d0 * d0 + d1 * d1 + d2 * d2) / dy if dy > 0.0 else 2.0 * alpha
        n0, n1, n2, f, g0, g1, g2 = m0, m1, m2, f1, h0, h1, h2
        for c in range(9):
            W[0, c] = W[1, c]
    return n0, n1, n2, f


@serial
def _creases(k, T, A, na, n0, n1, n2):
    """Add to the orthonormal rows ``A[:na]`` each axis ``e`` of shape ``k`` (a box's three,
    a cylinder's) on whose crease ``n`` nearly lies (``|n · e| < CREASE``), made orthogonal
    to those before; returns the new count (at most 2: then ``n`` is fixed)."""
    axes = 3 if k == BOX else 1 if k == CYLINDER else 0
    for j in range(axes):
        c = 2 if k == CYLINDER else j
        e0, e1, e2 = T[0, c], T[1, c], T[2, c]
        if na >= 2 or abs(n0 * e0 + n1 * e1 + n2 * e2) >= CREASE:
            continue
        e0, e1, e2 = _project(A, na, e0, e1, e2)
        r = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        if r > 1e-9:
            A[na, 0], A[na, 1], A[na, 2] = e0 / r, e1 / r, e2 / r
            na += 1
    return na


@serial
def refine(ka, sa, va, Ta, kb, sb, vb, Tb, work, out):
    """Polish EPA's answer in ``out`` where a shape is curved (a cylinder, an ellipsoid), on
    which EPA's inscribed polytope approaches the surface slowly (K9a): the depth is the
    least value of the support function ``f(n) = h_A(n) + h_B(-n)`` of the Minkowski
    difference over unit ``n``, whose gradient on the sphere is ``g = s(n) - f(n) n``
    (``s`` the support point along ``n``); from EPA's normal, steps ``n - α g`` (α by
    Barzilai and Borwein, halved until ``f`` falls) bring ``f`` down to the depth. ``f`` has
    creases (``n`` orthogonal to a box's axis, where two faces meet, or to a cylinder's,
    where its side meets a rim), on which the least value often lies (a cylinder's side on
    a face, a box's edge across a cylinder): a descent that stops near one goes on along
    it. EPA's depth is a lower bound on the depth (its polytope lies inside the
    difference), each ``f(n)`` an upper bound: the answer is kept where the two meet within
    ``DEPTH_GAP`` (or ``DEPTH_SLACK`` of the depth, where EPA stopped short), with the
    support points along the last ``n`` as witnesses. Returns False otherwise (the depth
    is then not known to that accuracy)."""
    W = work[:40].reshape((4, 10))
    A = work[40:46].reshape((2, 3))  # the creases followed (GJK's copy is not needed here)
    lower = -out[0]
    n0, n1, n2, f = _descend(ka, sa, va, Ta, kb, sb, vb, Tb, W, A, 0, lower,
                             out[7], out[8], out[9])
    if f - lower > DEPTH_GAP:  # stopped short: on a crease?
        na = _creases(kb, Tb, A, _creases(ka, Ta, A, 0, n0, n1, n2), n0, n1, n2)
        if na > 0:
            m0, m1, m2 = _project(A, na, n0, n1, n2)
            r = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
            m0, m1, m2, f1 = _descend(ka, sa, va, Ta, kb, sb, vb, Tb, W, A, na, lower,
                                      m0 / r, m1 / r, m2 / r)
            if f1 < f:
                n0, n1, n2, f = m0, m1, m2, f1
            else:
                _add(W, 0, ka, sa, va, Ta, kb, sb, vb, Tb, n0, n1, n2)
    a0, a1, a2 = W[0, 3], W[0, 4], W[0, 5]
    write(out, -f, a0, a1, a2, a0 - f * n0, a1 - f * n1, a2 - f * n2, n0, n1, n2)
    return f - lower <= DEPTH_GAP + DEPTH_SLACK * f and f >= lower - DEPTH_GAP


# --- the entry ------------------------------------------------------------------------------


@serial
def ordered_distance(ka, sa, va, Ta, kb, sb, vb, Tb, work, out):
    """``pair_distance`` for ``kb`` not a plane unless ``ka`` is one, a box second against
    a sphere or capsule, a cylinder second against a sphere."""
    if ka > ELLIPSOID or kb > ELLIPSOID or ka < 0 or kb < 0:
        return UNKNOWN_KIND
    if ka == PLANE:
        return TWO_PLANES
    if kb == PLANE:
        return against_plane(ka, sa, va, Ta, sb, Tb, out)
    if (ka == SPHERE or ka == CAPSULE) and (kb == SPHERE or kb == CAPSULE):
        return swept(ka, sa, Ta, kb, sb, Tb, out)
    if ka == SPHERE and kb == BOX:
        return sphere_box(sa, Ta, sb, Tb, out)
    if ka == SPHERE and kb == CYLINDER:
        return sphere_cylinder(sa, Ta, sb, Tb, out)
    overlap = gjk(ka, sa, va, Ta, kb, sb, vb, Tb, work, out)
    if overlap:
        if ka == CAPSULE and kb == BOX:
            return capsule_box_overlap(sa, Ta, sb, Tb, out)
        if not epa(ka, sa, va, Ta, kb, sb, vb, Tb, overlap, work, out):
            return PENETRATION_UNSUPPORTED
        curved = ka == CYLINDER or kb == CYLINDER or ka == ELLIPSOID or kb == ELLIPSOID
        if curved and not refine(ka, sa, va, Ta, kb, sb, vb, Tb, work, out):
            return PENETRATION_UNSUPPORTED
    ra = sa[0] if (ka == SPHERE or ka == CAPSULE) else 0.0
    rb = sb[0] if (kb == SPHERE or kb == CAPSULE) else 0.0
    inflate(out, ra, rb)
    return OK


@serial
def pair_distance(ka, sa, va, Ta, kb, sb, vb, Tb, work, out):
    """The signed distance, witness points and normal of shapes ``a`` and ``b`` into
    ``out`` (see the module's docstring); returns a status."""
    swap = ka == PLANE and kb != PLANE or ka == BOX and (kb == SPHERE or kb == CAPSULE) or \
        ka == CYLINDER and kb == SPHERE
    if not swap:
        return ordered_distance(ka, sa, va, Ta, kb, sb, vb, Tb, work, out)
    status = ordered_distance(kb, sb, vb, Tb, ka, sa, va, Ta, work, out)
    for c in range(1, 4):
        out[c], out[c + 3] = out[c + 3], out[c]
        out[c + 6] = -out[c + 6]
    return status


@serial
def distances(kinds, sizes, vertices, offsets, poses, pairs, work, out, status):
    """``pair_distance`` of each pair ``pairs[k] = (i, j)`` of shapes given by their kinds,
    sizes, vertices (``vertices[offsets[i]:offsets[i + 1]]``) and poses, into ``out[k]``,
    its status into ``status[k]``."""
    for k in range(pairs.shape[0]):
        i, j = pairs[k, 0], pairs[k, 1]
        status[k] = pair_distance(kinds[i], sizes[i], vertices[offsets[i]:offsets[i + 1]],
                                  poses[i], kinds[j], sizes[j],
                                  vertices[offsets[j]:offsets[j + 1]], poses[j], work, out[k])
