"""The world of an MJCF's own static geoms (docs/contact.md, "The static world", K44).

MuJoCo's world body holds a model's floor and its static geoms; ``collision_model`` keeps
them as shapes of no link (link -1). ``static_world(collisions)`` makes a ``World`` of
them, its plane facing up the ground and every other shape an ``Obstacle`` (another
plane a wall); ``default_world`` is the
world a step or a rollout takes given such collisions and no ``world=``.
"""

from __future__ import annotations

from .obstacles import Obstacle
from .shapes import PLANE
from .world import World

__all__ = ["default_world", "static_world"]


def static_world(collisions, friction: float | None = None) -> World:
    """The ``World`` of an MJCF's own static geoms, the shapes of ``collisions`` on no link
    (``collision_model`` reads them from MuJoCo's world body): the plane facing most nearly
    up is the ground (the plane through the geom's origin, normal to its z axis, K1), its
    friction the plane's (``friction`` overrides it); every other shape an ``Obstacle`` at
    its placement with its own friction and filter, the other planes (an arena's walls)
    half-spaces (K44a). No plane facing up: no ground."""
    from ..cga.conventions import motor_from_matrix, quaternion_from_motor

    own = [c for c in collisions if c.link < 0]
    up = [c for c in own if c.shape.kind == PLANE and c.pose[2, 2] > 1e-6]
    ground = max(up, key=lambda c: c.pose[2, 2]) if up else None  # the first of ties
    obstacles = []
    for c in own:
        if c is ground:
            continue
        T = c.pose
        w, x, y, z = quaternion_from_motor(motor_from_matrix(T))
        obstacles.append(Obstacle(c.shape.at(None), tuple(T[:3, 3]), (x, y, z, w),
                                  c.friction, c.contype, c.conaffinity, c.name))
    if ground is None:
        return World(ground=False, obstacles=tuple(obstacles))
    n, point = ground.pose[:3, 2], ground.pose[:3, 3]
    mu = ground.friction if friction is None else friction
    return World(ground_normal=tuple(n), ground_height=float(n @ point / n[2]),
                 friction=1.0 if mu is None else float(mu), obstacles=tuple(obstacles))


def default_world(collisions) -> World | None:
    """The world of a step or a rollout given ``collisions`` and no world: the static world
    of their own world shapes (an MJCF's floor and geoms, ``obstacles.static_world``), or
    None where they hold none (or are not a collision model: named by the caller's
    checks)."""
    from .model import Collision
    from .obstacles import own_world

    try:
        shapes = list(collisions) if collisions is not None else []
    except TypeError:
        return None
    if not shapes or not all(isinstance(c, Collision) for c in shapes) or \
            not own_world(shapes):
        return None
    return static_world(shapes)
