"""The world a robot touches: a ground plane, which may be tilted, its friction, and free
bodies.

``World`` says where the ground is and which free bodies lie about (``bodies.Body``);
``ground_contacts(model, collisions, q, world)`` finds where the robot's collision shapes
touch the ground (``manifold``, K21-K22): for each contact the shape and its link, the point
on the shape, the ground's normal and the signed distance. ``world_contacts`` adds the
contacts between shapes of different links (``pairs``, K37-K39).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..algorithms._inputs import nonnegative
from . import manifold as C
from .shapes import Plane

__all__ = ["Contacts", "World", "ground_contacts", "shape_friction",
           "shape_twists", "touches_ground", "world_contacts"]


@dataclass(frozen=True)
class World:
    """A ground plane through the point ``(0, 0, ground_height)`` with the unit normal
    ``ground_normal`` (normalised here; it points out of the ground), and its Coulomb
    friction coefficient ``friction`` (also every shape's that carries none: the robot's;
    a contact's coefficient is the smaller of its two surfaces', K38). ``ground=False``: no
    ground. ``bodies``: free rigid bodies (``cgadyn.Body``) appended to the robot's model as
    free-flyer roots (``contact.bodies.with_bodies``), touching the ground, the robot and
    each other; ``self_collision``: the robot's shapes touch each other too (never those on
    one body, or on a parent and its child); ``obstacles``: shapes fixed in the world
    (``cgadyn.Obstacle``: a table, a step, a wall) that the robot's moving shapes and the
    bodies touch (``contact.obstacles``, K44). A World given to a step or a rollout replaces
    an MJCF's own static geoms (``contact.static_world``)."""

    ground: bool = True
    ground_normal: tuple = (0.0, 0.0, 1.0)
    ground_height: float = 0.0
    friction: float = 1.0
    bodies: tuple = ()
    self_collision: bool = False
    obstacles: tuple = ()

    def __post_init__(self):
        from .bodies import Body
        from .obstacles import Obstacle

        for what, kind in (("bodies", Body), ("obstacles", Obstacle)):
            object.__setattr__(self, what, _records(getattr(self, what), what, kind))
        if not isinstance(self.self_collision, bool):
            raise ValueError(f"World: self_collision must be True or False, got "
                             f"{self.self_collision!r}")
        n = np.asarray(self.ground_normal, dtype=float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or np.linalg.norm(n) < 1e-9:
            raise ValueError(f"World: ground_normal must be a finite nonzero 3-vector, got "
                             f"{self.ground_normal!r}")
        for what in ("ground_height", "friction"):
            value = getattr(self, what)
            if not isinstance(value, (int, float, np.floating, np.integer)) or \
                    not np.isfinite(value):
                raise ValueError(f"World: {what} must be a finite number, got {value!r}")
        if self.friction < 0:
            raise ValueError(f"World: friction must be >= 0, got {self.friction!r}")
        object.__setattr__(self, "ground_normal", tuple((n / np.linalg.norm(n)).tolist()))
        object.__setattr__(self, "ground_height", float(self.ground_height))
        object.__setattr__(self, "friction", float(self.friction))

    @property
    def plane(self) -> Plane:
        """The ground as a ``Plane``: ``π = n + δ e∞`` with ``δ = n · (0, 0, h)`` (K1)."""
        n = np.asarray(self.ground_normal)
        return Plane(n, n[2] * self.ground_height)


def _records(value, what: str, kind: type) -> tuple:
    """``value`` as a tuple of ``kind`` records; ``ValueError`` naming the World's field
    ``what`` else."""
    try:
        records = tuple(value)
    except TypeError:
        raise ValueError(f"World: {what} must be a list of cgadyn.{kind.__name__}, got "
                         f"{value!r}") from None
    for r in records:
        if not isinstance(r, kind):
            raise ValueError(f"World: {what} must be cgadyn.{kind.__name__} records, got {r!r}")
    return records


@dataclass(frozen=True)
class Contacts:
    """Contacts with the ground at one configuration, one row each: ``collision`` (the
    index of the shape in its ``CollisionModel``), ``link`` (an index of
    ``model.link_names``), ``point`` (K, 3) on the shape in the world, ``normal`` (K, 3)
    the ground's (out of it), ``distance`` (K,) signed (negative: a penetration), and
    ``friction`` (K,). A contact between two shapes (K37) also names the other shape
    (``other``, -1 for the ground), its link (``other_link``, -1 for the ground or the
    world) and its point ``other_point`` (K, 3) (the ground's: the point itself); its
    ``normal`` points from the other shape to this one."""

    collision: np.ndarray
    link: np.ndarray
    point: np.ndarray = field(repr=False)
    normal: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    friction: np.ndarray = field(repr=False)
    other: np.ndarray = field(repr=False, default=None)
    other_link: np.ndarray = field(repr=False, default=None)
    other_point: np.ndarray = field(repr=False, default=None)

    def __post_init__(self):
        n = self.collision.size
        for name, value in (("other", np.full(n, -1, dtype=np.int64)),
                            ("other_link", np.full(n, -1, dtype=np.int64)),
                            ("other_point", self.point)):
            if getattr(self, name) is None:
                object.__setattr__(self, name, value)

    def __len__(self) -> int:
        return int(self.collision.size)

    @property
    def acting(self) -> np.ndarray:
        """(K, 3) the point of each contact's link at which its rows are taken (K42): for a
        contact with the ground the plane's point under the shape's, ``point - distance ·
        normal``; for a pair's (K37) the point on its shape."""
        ground = (self.other < 0)[:, None]
        return np.where(ground, self.point - self.distance[:, None] * self.normal, self.point)


def touches_ground(model, collisions, world: World) -> np.ndarray:
    """Which shapes may touch the ground of ``world`` (K,): MuJoCo's filter with the
    ground's ``contype = conaffinity = 1``, and only shapes that move. A shape fixed in the
    world never does: one of the world itself (an MJCF's own floor, link -1), or one on a
    link welded to the world (a fixed base, ``link_joint`` -1), which no force can move
    and whose contact rows would be zero."""
    return np.array([world.ground and c.link >= 0 and model.link_joint[c.link] >= 0
                     and bool(c.contype & 1 or c.conaffinity & 1) for c in collisions],
                    dtype=np.bool_)


def shape_twists(model, collisions, q, v=None, v_free=None) -> np.ndarray:
    """(K, 2, 6): the world twist ``[v, ω]`` (Pinocchio's WORLD: ``v`` the velocity of the
    point at the world's origin) of each shape's link at the velocities ``v`` and
    ``v_free`` (default ``v``); zeros for ``v`` None and for shapes that do not move."""
    from ..algorithms import jacobian

    twists = np.zeros((len(collisions), 2, 6))
    if v is None:
        return twists
    pair = []
    for name, x in (("v", v), ("v_free", v if v_free is None else v_free)):
        x = np.asarray(x, dtype=float)
        if x.shape != (model.nv,) or not np.all(np.isfinite(x)):
            raise ValueError(f"{name}: expected a finite array of shape ({model.nv},) for "
                             f"{model.name!r}, got {x.shape}")
        pair.append(x)
    seen = {}
    for k, c in enumerate(collisions):
        if c.link < 0 or model.link_joint[c.link] < 0:
            continue
        if c.link not in seen:
            J = jacobian(model, q, int(c.link), "world")
            seen[c.link] = np.stack([J @ pair[0], J @ pair[1]])
        twists[k] = seen[c.link]
    return twists


def checked_world(world, caller: str) -> World:
    """``world`` (None: ``World()``, a ground and no bodies), checked (``contact.inputs``:
    the checks of every entry that takes a world)."""
    if world is None:
        return World()
    if not isinstance(world, World):
        raise ValueError(f"{caller}: world must be a cgadyn.World, got {world!r}")
    return world


def ground_contacts(model, collisions, q, world: World | None = None,
                    margin: float = 0.0, v=None, v_free=None, dt: float = 0.0,
                    patch: float = 0.0) -> Contacts:
    """The contacts of ``model``'s collision shapes (``collision_model``) at ``q`` with the
    ground of ``world`` (default: ``World()``): for each shape allowed to touch it (MuJoCo's
    filter with the ground's ``contype = conaffinity = 1``; shapes fixed in the world never:
    ``touches_ground``), at most four points spanning the shape's contact patch (K21,
    K22) whose gap is below ``margin``; with velocities ``v`` (and ``v_free``, default
    ``v``), the gap less the way each point may travel in a step of ``dt`` (K21a), as the
    contact step finds its contacts; no two closer than ``patch`` (K22,
    ``ContactSettings.patch`` in the step)."""
    from .api import check_rigid
    from .model import _collisions, collision_poses
    from .pairs import bounding_radii

    world = checked_world(world, "ground_contacts")
    nonnegative(margin, "margin")
    cm = _collisions(collisions, model)
    q = np.asarray(q, dtype=float)
    if q.shape != (model.nq,):
        raise ValueError(f"q: expected shape ({model.nq},) for {model.name!r}, got {q.shape}")
    poses = np.ascontiguousarray(collision_poses(model, cm, q))
    check_rigid(poses, "collision poses")
    active = touches_ground(model, cm, world)
    K = len(cm)
    twists = shape_twists(model, cm, q, v, v_free)
    for name, x in (("dt", dt), ("patch", patch)):
        nonnegative(x, name)
    out = np.empty((K, C.MAX_CONTACTS, C.OUT))
    counts = np.zeros(K)  # float, as the rollouts' scratch holds it: one compiled variant
    C.shapes_on_plane(cm.kinds, cm.sizes, cm.vertices, cm.offsets, poses,
                      bounding_radii(cm), active, cm.compliance, world.plane.packed_size,
                      np.eye(4),
                      float(margin), float(patch),
                      np.empty((C.CANDIDATES, C.CANDIDATE_COLUMNS)), out, counts, twists,
                      float(dt))
    rows = [(k, j) for k in range(K) for j in range(int(counts[k]))]
    which = np.array([k for k, _ in rows], dtype=np.int64)
    found = out[which, [j for _, j in rows]] if rows else np.empty((0, C.OUT))
    n = len(rows)
    return Contacts(which, cm.links[which], found[:, :3].copy(),
                    np.tile(np.asarray(world.ground_normal), (n, 1)), found[:, 3].copy(),
                    np.minimum(shape_friction(cm, world)[which], world.friction))


def shape_friction(collisions, world: World) -> np.ndarray:
    """(K,) each shape's friction coefficient: its own (a free body's), else the World's;
    a contact takes the smaller of its two surfaces' (K38)."""
    return np.array([world.friction if c.friction is None else float(c.friction)
                     for c in collisions], dtype=float).reshape(len(collisions))


def world_contacts(model, collisions, q, world: World, margin: float, pairs, v=None,
                   v_free=None, dt: float = 0.0, patch: float = 0.0) -> Contacts:
    """The contacts of ``ground_contacts`` (with ``v``, ``v_free``, ``dt`` and ``patch``)
    followed by those of the shapes' ``pairs`` ((P, 2), ``pairs.candidate_pairs``) within
    ``pairs.pair_margin`` of ``margin`` (K21a, K37-K39), each pair's points on its first
    shape ``a``, the normal from ``b`` to ``a``."""
    from .model import _collisions, collision_poses
    from .pairs import bounding_radii, pair_margin, pair_rows

    cm = _collisions(collisions, model)
    ground = ground_contacts(model, cm, q, world, margin, v, v_free, dt, patch)
    if len(pairs) == 0:
        return ground
    poses = np.ascontiguousarray(collision_poses(model, cm, q))
    reach = pair_margin(float(margin), bounding_radii(cm), poses,
                        shape_twists(model, cm, q, v, v_free), float(dt))
    which, xa, xb, normal, d = pair_rows(model, cm, poses, pairs, reach, patch)
    a, b = pairs[which, 0], pairs[which, 1]
    mu = shape_friction(cm, world)
    cat = np.concatenate
    return Contacts(cat([ground.collision, a]), cat([ground.link, cm.links[a]]),
                    cat([ground.point, xa]), cat([ground.normal, normal]),
                    cat([ground.distance, d]), cat([ground.friction,
                                                    np.minimum(mu[a], mu[b])]),
                    cat([ground.other, b]), cat([ground.other_link, cm.links[b]]),
                    cat([ground.other_point, xb]))
