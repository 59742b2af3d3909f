"""The world a robot touches: a ground plane, which may be tilted, and its friction.

``World`` says where the ground is; ``ground_contacts(model, collisions, q, world)`` finds
where the robot's collision shapes touch it (``manifold``, K21-K22): for each contact the
shape and its link, the point on the shape, the ground's normal and the signed distance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import manifold as C
from .shapes import Plane

__all__ = ["Contacts", "World", "ground_contacts", "touches_ground"]


@dataclass(frozen=True)
class World:
    """A ground plane through the point ``(0, 0, ground_height)`` with the unit normal
    ``ground_normal`` (normalised here; it points out of the ground), and its Coulomb
    friction coefficient ``friction`` (a contact's coefficient is the ground's: the shapes
    carry none yet). ``ground=False``: no ground."""

    ground: bool = True
    ground_normal: tuple = (0.0, 0.0, 1.0)
    ground_height: float = 0.0
    friction: float = 1.0

    def __post_init__(self):
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


@dataclass(frozen=True)
class Contacts:
    """Contacts with the ground at one configuration, one row each: ``collision`` (the
    index of the shape in its ``CollisionModel``), ``link`` (an index of
    ``model.link_names``), ``point`` (K, 3) on the shape in the world, ``normal`` (K, 3)
    the ground's (out of it), ``distance`` (K,) signed (negative: a penetration), and
    ``friction`` (K,)."""

    collision: np.ndarray
    link: np.ndarray
    point: np.ndarray = field(repr=False)
    normal: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    friction: np.ndarray = field(repr=False)

    def __len__(self) -> int:
        return int(self.collision.size)


def touches_ground(model, collisions, world: World) -> np.ndarray:
    """Which shapes may touch the ground of ``world`` (K,): MuJoCo's filter with the
    ground's ``contype = conaffinity = 1``, and only shapes that move. A shape fixed in the
    world never does: one of the world itself (an MJCF's own floor, link -1), or one on a
    link welded to the world (a fixed base, ``link_joint`` -1), which no force can move
    and whose contact rows would be zero."""
    return np.array([world.ground and c.link >= 0 and model.link_joint[c.link] >= 0
                     and bool(c.contype & 1 or c.conaffinity & 1) for c in collisions],
                    dtype=np.bool_)


def ground_contacts(model, collisions, q, world: World | None = None,
                    margin: float = 0.0) -> Contacts:
    """The contacts of ``model``'s collision shapes (``collision_model``) at ``q`` with the
    ground of ``world`` (default: ``World()``): for each shape allowed to touch it (MuJoCo's
    filter with the ground's ``contype = conaffinity = 1``; shapes fixed in the world never:
    ``touches_ground``), at most four points closer than ``margin`` spanning the
    shape's contact patch (K21, K22)."""
    from .api import check_rigid
    from .model import _collisions, collision_poses

    world = World() if world is None else world
    if not isinstance(world, World):
        raise TypeError(f"world must be a cgadyn.World, got {type(world).__name__}")
    if not (isinstance(margin, (int, float)) and np.isfinite(margin) and margin >= 0):
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    cm = _collisions(collisions, model)
    q = np.asarray(q, dtype=float)
    if q.shape != (model.nq,):
        raise ValueError(f"q: expected shape ({model.nq},) for {model.name!r}, got {q.shape}")
    poses = np.ascontiguousarray(collision_poses(model, cm, q))
    check_rigid(poses, "collision poses")
    active = touches_ground(model, cm, world)
    K = len(cm)
    out = np.empty((K, C.MAX_CONTACTS, C.OUT))
    counts = np.zeros(K, dtype=np.int64)
    C.shapes_on_plane(cm.kinds, cm.sizes, cm.vertices, cm.offsets, poses, active,
                      world.plane.packed_size, np.eye(4), float(margin),
                      np.empty((C.CANDIDATES, C.OUT)), out, counts)
    rows = [(k, j) for k in range(K) for j in range(int(counts[k]))]
    which = np.array([k for k, _ in rows], dtype=np.int64)
    found = out[which, [j for _, j in rows]] if rows else np.empty((0, C.OUT))
    n = len(rows)
    return Contacts(which, cm.links[which], found[:, :3].copy(),
                    np.tile(np.asarray(world.ground_normal), (n, 1)), found[:, 3].copy(),
                    np.full(n, world.friction))
