"""Random Pinocchio models of given joints, shared by the joint-type tests
(``test_joint_types.py``, ``test_spherical.py``): each is checked against Pinocchio."""

from __future__ import annotations

import numpy as np
import pinocchio as pin


def random_inertia(rng) -> pin.Inertia:
    """A random mass (0.5-2 kg), centre of mass and positive definite rotational inertia."""
    A = rng.normal(size=(3, 3))
    return pin.Inertia(rng.uniform(0.5, 2.0), rng.normal(size=3) * 0.2,
                       A @ A.T + 0.1 * np.eye(3))


def random_model(name: str, joints, seed: int) -> pin.Model:
    """A Pinocchio model of ``joints`` ``(parent index, JointModel)`` (0: the universe, i:
    the i-th joint), random placements and inertias, a ``BODY`` frame per joint and one for
    the world (``base``)."""
    rng = np.random.default_rng(seed)
    pm = pin.Model()
    pm.name = name
    pm.addBodyFrame("base", 0, pin.SE3.Identity(), 0)
    for i, (parent, joint) in enumerate(joints):
        X = pin.SE3(pin.exp3(rng.normal(size=3)), rng.normal(size=3) * 0.3)
        j = pm.addJoint(parent, joint, X, f"j{i}")
        pm.appendBodyToJoint(j, random_inertia(rng), pin.SE3.Identity())
        pm.addBodyFrame(f"b{i}", j, pin.SE3(pin.exp3(rng.normal(size=3)),
                                            rng.normal(size=3) * 0.2), 0)
    return pm
