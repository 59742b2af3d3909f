"""A rollout with free bodies (``simulate(..., world=World(bodies=[...]))``): the robot's
inputs carried over to the model with the bodies appended (``contact.bodies.with_bodies``,
docs/contact.md, "Free bodies and pairs").

``q0`` and ``v0`` are the robot's (each body then starts at its ``position`` and
``orientation``, at rest) or the whole model's (robot then bodies, 7 and 6 per body);
``tau``, ``f_ext`` and a ``PD``'s gains and references given for the robot get zeros (or
the bodies' start) for the bodies, which no controller and no torque ever moves.
"""

from __future__ import annotations

import numpy as np

from .controllers import PD

__all__ = ["robot_and_bodies"]


def _extend(x, size: int, tail: np.ndarray):
    """``x`` (..., size) with ``tail`` appended on its last axis; anything else unchanged
    (checked later against the whole model)."""
    if x is None:
        return None
    a = np.asarray(x)
    if a.ndim == 0 or a.shape[-1] != size or a.dtype.kind not in "biuf":
        return x
    return np.concatenate([a, np.broadcast_to(tail, a.shape[:-1] + tail.shape)], axis=-1)


def robot_and_bodies(model, world, collisions, q0, v0, tau, f_ext, controller):
    """``(model', collisions', q0', v0', tau', f_ext', controller', robot_joints)`` with
    the bodies of ``world`` appended (the module's docstring); the inputs unchanged where
    the world has none."""
    from ..contact.bodies import check_start, world_model
    from ..contact.model import Collision
    from ..contact.world import World

    n = model.njoints
    if not isinstance(world, World):  # None, or a bad world: named later
        return model, collisions, q0, v0, tau, f_ext, controller, n
    if not world.bodies:  # the obstacles alone: shapes of the world (K44)
        if isinstance(collisions, (list, tuple)) and all(
                isinstance(c, Collision) and c.link < model.nlinks for c in collisions):
            # (anything else is named by the world's checks, checked_collisions)
            collisions = world_model(model, collisions, world)[1]
        return model, collisions, q0, v0, tau, f_ext, controller, n
    check_start(world)
    robot = model
    model, collisions, qb = world_model(robot, collisions, world)
    nb = len(world.bodies)
    zeros = np.zeros(6 * nb)
    q0, v0 = _extend(q0, robot.nq, qb), _extend(v0, robot.nv, zeros)
    tau = _extend(tau, robot.nv, zeros)
    if f_ext is not None:
        f = np.asarray(f_ext, dtype=float)
        if f.ndim >= 2 and f.shape[-2:] == (n, 6):
            f_ext = np.concatenate([f, np.zeros(f.shape[:-2] + (nb, 6))], axis=-2)
    if isinstance(controller, PD):
        gains = [_extend(g, robot.nv, zeros) if np.ndim(g) else g
                 for g in (controller.kp, controller.kd)]
        controller = PD(*gains, _extend(controller.q_ref, robot.nq, qb),
                        _extend(controller.v_ref, robot.nv, zeros),
                        controller.gravity_compensation)
    return model, collisions, q0, v0, tau, f_ext, controller, n
