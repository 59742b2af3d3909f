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


def ik_reaches_poses(pm: pin.Model, link: str = "b3"):
    """Inverse kinematics (Levenberg-Marquardt on the manifold) from the neutral
    configuration to three reachable poses of ``link`` of ``cgadyn.from_pinocchio(pm)``,
    each judged by Pinocchio's log6 at the configuration found; returns the model and the
    result."""
    import cgadyn
    from cgadyn import oracle
    from cgadyn.tasks import inverse_kinematics

    model = cgadyn.from_pinocchio(pm)
    s = oracle.sample(model, 3, 16)
    T = cgadyn.link_placements(model, s.q)[:, model.link_index(link)]
    res = inverse_kinematics(model, link, T)
    assert res.converged.all() and (res.error <= 1e-10).all()
    data = pm.createData()
    for b in range(3):
        pin.framesForwardKinematics(pm, data, oracle.pin_configuration(model, res.q[b]))
        M = data.oMf[pm.getFrameId(link, pin.BODY)]
        assert np.linalg.norm(pin.log6(pin.SE3(T[b]).actInv(M)).vector) <= 1e-9
    return model, res
