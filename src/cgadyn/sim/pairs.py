"""Pair contacts in the compiled rollout loop (docs/contact.md, "Free bodies and pairs",
K37-K39): the additions ``sim.contact.contact_velocity`` calls for the contacts between
shapes of different links, as ``contact.step.contact_step`` makes them from Python.

The world tuple ends with two elements (``pair_world``): the candidate pairs (P, 2)
(``contact.pairs.candidate_pairs``) and the shapes' friction coefficients (K,) (K38); two
None for a rollout without free bodies and without self-collision: every function here
then returns at its first line, and numba prunes the rest (nothing of it is compiled). (Two
elements, not one tuple of two: the parallel loop passes the world's elements on as its own
arguments, which may be arrays or None but not tuples.) The shapes' bounding radii (K39)
come before them, always there (the ground's detection uses them too, K21a). Pair ``p``'s
contacts take the slots ``MAX_CONTACTS (shapes + p) ..`` after the shapes' own (K25's warm
start, the forces kept).
"""

from __future__ import annotations

from .._jit import inline, serial
from ..algorithms import _workspace as ws
from ..constraints.core import _add_columns
from ..contact.distance import WORK
from ..contact.manifold import CANDIDATE_COLUMNS, MAX_CONTACTS, OUT
from ..contact.pairs import PAIR_CANDIDATES, contact_frame, pair_contacts, pair_margin
from ..contact.problem import open_gap

__all__ = ["pair_world"]


def pair_world(model, collisions, world, robot_joints: int) -> tuple:
    """The world tuple's last two elements, the pairs of shapes that may touch and each
    shape's friction, for a model whose joints from ``robot_joints`` on are free bodies;
    two None where no pair of shapes may touch and every shape takes the World's
    friction."""
    from ..contact.pairs import candidate_pairs
    from ..contact.world import shape_friction

    pairs = candidate_pairs(collisions, robot_joints, world.self_collision)
    if len(pairs) == 0 and all(c.friction is None for c in collisions):
        return None, None
    return pairs, shape_friction(collisions, world)


@serial
def pair_count(pairs):
    """The number of candidate pairs P (0 without)."""
    if pairs is None:
        return 0
    return pairs.shape[0]


@serial
def pair_scratch_size(pairs):
    """Floats of the pairs' scratch (``carve_pairs``)."""
    if pairs is None:
        return 0
    P = pairs.shape[0]
    return (P * MAX_CONTACTS * OUT + 3 * P + 2 * P + PAIR_CANDIDATES * CANDIDATE_COLUMNS
            + WORK + 10 + 4 + 16)


@serial
def carve_pairs(pairs, p, o):
    """The pairs' scratch from the buffer at pointer ``p``, offset ``o``: None without
    pairs, else ``(out, counts, normals, status, cand, work, tmp, zero, P)`` (typed
    Optional: unpack it, never index it)."""
    if pairs is None:
        return None
    n = pairs.shape[0]
    out, o = ws.carve(p, o, (n, MAX_CONTACTS, OUT))
    normals, o = ws.carve(p, o, (n, 3))
    counts, o = ws.carve(p, o, (n,))
    status, o = ws.carve(p, o, (n,))
    cand, o = ws.carve(p, o, (PAIR_CANDIDATES, CANDIDATE_COLUMNS))
    work, o = ws.carve(p, o, (WORK,))
    tmp, o = ws.carve(p, o, (10,))
    zero, o = ws.carve(p, o, (4,))
    P, o = ws.carve(p, o, (4, 4))
    for i in range(4):
        zero[i] = 0.0
    return (out, counts, normals, status, cand, work, tmp, zero, P)


@serial
def ground_friction(shape_friction, s, friction):
    """The friction of shape ``s`` on the ground: the smaller of the ground's and the
    shape's (K38)."""
    if shape_friction is None:
        return friction
    return min(friction, shape_friction[s])


@serial
def detect_pairs(pairs, radii, ps, kinds, sizes, vertices, offsets, poses, margin, patch,
                 twists, dt):
    """The pairs' contacts at ``poses`` (``contact.pairs.pair_contacts``, K37, K39) within
    ``pair_margin`` of ``margin`` for the shapes' ``twists`` over ``dt`` (K21a), no two of a
    patch within ``patch`` (K22), into the scratch ``ps``; returns their number. A pair
    whose distance is not computed gets none."""
    if pairs is None:
        return 0
    out, counts, normals, status, cand, work, tmp, zero, P = ps
    pair_contacts(kinds, sizes, vertices, offsets, poses, pairs, radii,
                  pair_margin(margin, radii, poses, twists, dt), patch, zero, P, work, tmp,
                  cand, out, counts, normals, status)
    total = 0
    for p in range(counts.shape[0]):
        total += int(counts[p])
    return total


@serial
def failed_pair(pairs, ps):
    """The first pair whose distance ``detect_pairs`` did not compute (its status not OK),
    or -1: a step stops there rather than go on without that pair's contact."""
    if pairs is None:
        return -1
    _, _, _, status, _, _, _, _, _ = ps  # unpacked: ps may be typed Optional
    for p in range(status.shape[0]):
        if status[p] != 0.0:
            return p
    return -1


@serial
def pair_rows(pairs, friction, ps, m, Sw, links, J, mu, lam, prev, had, c, shapes):
    """The rows ``(t₁, t₂, n)`` of each pair contact from row ``3 c`` of ``J``: ``J_a(x_a)
    - J_b(x_b)`` turned into the contact's frame (K37), its friction (K38) into ``mu``,
    ``lam`` warm-started from its slot's λ of the previous step (K25). Returns the next
    contact and whether any row was warm-started."""
    warm = False
    if pairs is None:
        return c, warm
    out, counts, normals, _, _, _, tmp, _, F = ps
    for p in range(pairs.shape[0]):
        a, b = pairs[p, 0], pairs[p, 1]
        ja = m.link_joint[links[a]] if links[a] >= 0 else -1
        jb = m.link_joint[links[b]] if links[b] >= 0 else -1
        contact_frame(normals[p, 0], normals[p, 1], normals[p, 2], F)
        for j in range(int(counts[p])):
            r0 = 3 * c
            d = out[p, j, 3]
            for i in range(3):
                tmp[i] = out[p, j, i] - d * normals[p, i]  # x_b = x_a - d n
            _add_columns(Sw, m.parents, m.iv, ja, 1.0, out[p, j], 3, r0, J, F, False)
            _add_columns(Sw, m.parents, m.iv, jb, -1.0, tmp, 3, r0, J, F, False)
            for k in range(m.nv):
                x, y, z = J[r0, k], J[r0 + 1, k], J[r0 + 2, k]
                for i in range(3):
                    J[r0 + i, k] = F[i, 0] * x + F[i, 1] * y + F[i, 2] * z
            mu[c] = min(friction[a], friction[b])
            slot = MAX_CONTACTS * (shapes + p) + j
            for i in range(3):
                lam[r0 + i] = prev[slot, i] if had[slot] != 0.0 else 0.0
            if had[slot] != 0.0:
                warm = True
            c += 1
    return c, warm


@serial
def pair_gaps(pairs, ps, g, depth, c, dt):
    """The gap's term (K23) on each pair contact's normal row, from contact ``c``, and the
    contact's signed distance into ``depth[c]`` (K43)."""
    if pairs is None:
        return
    out, counts, _, _, _, _, _, _, _ = ps  # unpacked: ps may be typed Optional
    for p in range(counts.shape[0]):
        for j in range(int(counts[p])):
            g[3 * c + 2] += open_gap(out[p, j, 3], dt)
            depth[c] = out[p, j, 3]
            c += 1


@inline
def keep_slot(slot, lam, c, F, dt, prev, had, force):
    """Contact ``c``'s impulse ``λ`` (rows ``3c ..``, in its frame ``F``'s rows ``(t₁, t₂,
    n)``) into its slot for the next step's warm start (K25), and its world-frame force
    ``Fᵀ λ / dt`` into ``force``."""
    had[slot] = 1.0
    for i in range(3):
        prev[slot, i] = lam[3 * c + i]
        force[slot, i] = (F[0, i] * lam[3 * c] + F[1, i] * lam[3 * c + 1]
                          + F[2, i] * lam[3 * c + 2]) / dt


@serial
def keep_pairs(pairs, ps, lam, prev, had, force, c, shapes, dt):
    """Each pair contact's λ into its slot (K25) and its force on shape ``a`` (world frame,
    λ / dt) into ``force``, from contact ``c``."""
    if pairs is None:
        return
    out, counts, normals, _, _, _, _, _, F = ps
    for p in range(counts.shape[0]):
        contact_frame(normals[p, 0], normals[p, 1], normals[p, 2], F)
        for j in range(int(counts[p])):
            keep_slot(MAX_CONTACTS * (shapes + p) + j, lam, c, F, dt, prev, had, force)
            c += 1
