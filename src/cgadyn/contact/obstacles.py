"""Static shapes of the world: a table an arm must not pass through, a step, a wall, an
MJCF's own geoms (docs/contact.md, "The static world", K44).

An ``Obstacle`` is one collision shape fixed in the world at a position and orientation. A
``World(obstacles=[...])`` appends each to the robot's collision model as a shape of the
world (link ``-1``, moved by no joint), so that the pairs' code (K37-K39) finds its
contacts with every moving shape of the robot and of the free bodies, whether or not
``self_collision`` is on; its contact rows are those of a pair whose second shape never
moves. A plane obstacle is a half-space (a wall): it touches every moving shape, its
contacts a patch of the shape's candidates against it (K44a). An MJCF's own static geoms
are such a world (``contact.static_world``). A ``World``
given to a step or a rollout replaces them: ``scene_collisions`` leaves the collision
model's own world shapes out (they touch nothing) and appends the World's obstacles.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, replace

import numpy as np

from .model import Collision, CollisionModel
from .shapes import Shape, three_numbers

__all__ = ["Obstacle", "obstacle_names", "own_world", "placement", "pose_matrix",
           "scene_collisions"]


def placement(who: str, position, orientation, friction, name) -> tuple[tuple, tuple]:
    """The checked ``position`` (three finite numbers) and ``orientation`` (a nonzero
    quaternion ``(x, y, z, w)``, normalised) of a ``Body`` or an ``Obstacle`` named ``who``,
    with its ``friction`` (None or a finite number >= 0) and ``name`` (None or a string)
    checked too; ``ValueError`` names the field and what was expected."""
    p = three_numbers(position, "position", who)
    try:
        quat = np.asarray(orientation, dtype=float)
    except (TypeError, ValueError):
        quat = np.full(1, np.nan)
    if quat.shape != (4,) or not np.all(np.isfinite(quat)) or np.linalg.norm(quat) < 1e-9:
        raise ValueError(f"{who}: orientation must be a nonzero quaternion (x, y, z, w), "
                         f"got {orientation!r}")
    if friction is not None and (isinstance(friction, bool) or not isinstance(
            friction, numbers.Real) or not np.isfinite(friction) or friction < 0):
        raise ValueError(f"{who}: friction must be None or a finite number >= 0, got "
                         f"{friction!r}")
    if name is not None and not isinstance(name, str):
        raise ValueError(f"{who}: name must be a string or None, got {name!r}")
    return tuple(p.tolist()), tuple((quat / np.linalg.norm(quat)).tolist())


def pose_matrix(position, orientation) -> np.ndarray:
    """The 4x4 pose of a frame at ``position`` turned by the unit quaternion
    ``orientation`` ``(x, y, z, w)``."""
    from ..cga.conventions import matrix_from_motor, motor_from_quaternion

    x, y, z, w = orientation
    return matrix_from_motor(motor_from_quaternion((w, x, y, z), position))


@dataclass(frozen=True)
class Obstacle:
    """A collision ``shape`` (a ``Sphere``, ``Box``, ``Capsule``, ``Cylinder``,
    ``Ellipsoid``, ``ConvexMesh``, or a ``Plane``: a wall, the half-space behind it, K44a)
    fixed in the world, its
    frame (the shape's, moved by its own ``placement``, if any) at ``position`` turned by
    ``orientation`` (a quaternion ``(x, y, z, w)``,
    normalised here); ``friction`` (its Coulomb coefficient; None: the World's; a contact
    takes the smaller of its two surfaces', K38), MuJoCo's ``contype`` and ``conaffinity``
    (which of the robot's shapes it touches), and ``name`` (None: ``obstacle<i>`` by its
    place in the World)."""

    shape: Shape
    position: tuple = (0.0, 0.0, 0.0)
    orientation: tuple = (0.0, 0.0, 0.0, 1.0)
    friction: float | None = None
    contype: int = 1
    conaffinity: int = 1
    name: str | None = None

    def __post_init__(self):
        who = f"Obstacle {self.name!r}" if self.name is not None else "Obstacle"
        if not isinstance(self.shape, Shape):
            raise ValueError(f"{who}: shape must be a cgadyn Sphere, Box, Capsule, Cylinder, "
                             f"Ellipsoid, ConvexMesh or Plane, got {self.shape!r}")
        for what in ("contype", "conaffinity"):
            value = getattr(self, what)
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 0:
                raise ValueError(f"{who}: {what} must be an integer bit mask >= 0, got "
                                 f"{value!r}")
        p, quat = placement(who, self.position, self.orientation, self.friction, self.name)
        object.__setattr__(self, "position", p)
        object.__setattr__(self, "orientation", quat)

    @property
    def pose(self) -> np.ndarray:
        """Its 4x4 pose in the world."""
        return pose_matrix(self.position, self.orientation)


def own_world(collisions) -> list[int]:
    """The indices of the shapes of ``collisions`` that are the world's own (link -1: an
    MJCF's geoms of its world body)."""
    return [k for k, c in enumerate(collisions) if c.link < 0]


def scene_collisions(collisions: CollisionModel, world, model=None) -> CollisionModel:
    """The collision model a step or a rollout in ``world`` uses: ``collisions`` with its
    own world shapes touching nothing (the ``World`` replaces them; their indices kept, so
    that a contact names the same shape) and the World's obstacles appended, each a shape
    of the world (link -1) at its pose (K44). ``collisions`` itself where neither
    changes anything."""
    own = own_world(collisions)
    if not own and not world.obstacles:
        return collisions
    shapes = [replace(c, contype=0, conaffinity=0, friction=None) if c.link < 0 else c
              for c in collisions]
    names = obstacle_names(world.obstacles)
    shapes += [Collision(name, o.shape, -1, o.pose, o.contype, o.conaffinity, o.friction)
               for o, name in zip(world.obstacles, names, strict=True)]
    return CollisionModel(shapes, collisions.model if model is None else model)


def obstacle_names(obstacles) -> list[str]:
    """Each obstacle's name: its own, or ``obstacle<i>``."""
    return [o.name if o.name is not None else f"obstacle{i}" for i, o in enumerate(obstacles)]
