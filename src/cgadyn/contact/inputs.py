"""A world's inputs, checked once for every entry that takes them (``contact_step``,
``ground_contacts``, ``simulate``): the world, the robot's collision model in it, the
contact settings. Each error names the caller, the problem and what was expected; all are
``ValueError``, which the command line reports as a user's mistake."""

from __future__ import annotations

import numpy as np

from .model import CollisionModel, _collisions
from .settings import ContactSettings
from .world import World, checked_world

__all__ = ["checked_collisions", "checked_settings", "checked_world"]


def checked_settings(contact, caller: str) -> ContactSettings:
    """``contact`` (None: the defaults), checked."""
    if contact is None:
        return ContactSettings()
    if not isinstance(contact, ContactSettings):
        raise ValueError(f"{caller}: contact must be a cgadyn.ContactSettings, got "
                         f"{contact!r}")
    return contact


def checked_collisions(model, collisions, world: World, caller: str) -> CollisionModel:
    """The collision model of ``model`` in ``world``: ``collisions`` (a ``CollisionModel``
    or a list of ``Collision``) on links of ``model``; none at all only where the world has
    no ground (joint limits alone) or the model does not move (a world of free bodies)."""
    cm = CollisionModel([], model) if collisions is None else _collisions(collisions, model)
    if not isinstance(cm, CollisionModel):
        raise ValueError(f"{caller}: collisions must be cgadyn.collision_model(model, ...), "
                         f"got {collisions!r}")
    if world.ground and len(cm) == 0 and model.nv > 0:  # a robot that would fall through
        what = "is None" if collisions is None else "hold no shape"
        raise ValueError(f"{caller}: collisions {what} but the world has a ground: a world "
                         "needs the robot's collision shapes; pass "
                         "collisions=cgadyn.collision_model(model, ...), or "
                         "World(ground=False) for joint limits alone")
    if np.any(cm.links >= model.nlinks):
        raise ValueError(f"{caller}: collisions refer to links the model does not have; read "
                         "them with collision_model(model, ...)")
    return cm
