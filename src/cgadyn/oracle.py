"""Pinocchio, the oracle: the same robot in both libraries, states in both layouts, the
measure of their difference, and every check as a record.

One place for the Pinocchio side, used by ``cgadyn validate``, ``cgadyn bench``, the
validation scripts and the tests:

- ``models(robot)``: the cgadyn model and the Pinocchio model of one robot name, path or
  URDF text, built alike (a free-flyer root where cgadyn gives one);
- ``pin_configuration``: cgadyn's q in Pinocchio's layout (a continuous joint is one angle
  in cgadyn and (cos, sin) in Pinocchio; a free flyer is the same 7 numbers in both);
- ``cgadyn_configuration``: Pinocchio's q in cgadyn's layout (the inverse);
- ``sample``: random states;
- ``relative_error``: the measure, ``RELATIVE``;
- ``CHECKS``: what ``validate`` compares, each with its cgadyn call, its Pinocchio call and
  whether its tolerance scales with the conditioning of M (``SCALED``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

TINY = 1e-300

RELATIVE = "rel = max|cgadyn - pinocchio| / max|pinocchio|, per sample"
SCALED = ("forward dynamics and M⁻¹ are judged against tolerance × cond(M): both libraries "
          "solve with M, and an error of the result of that order is the rounding of M itself")


def models(robot, floating_base=None, check_inertia: bool = True):
    """``(cgadyn model, pinocchio model)`` of a robot name, a URDF path or URDF text, or an
    MJCF path or text (``registry.resolve`` decides; Pinocchio reads MJCF through
    ``mjcf.pinocchio_model``, the model cgadyn converts)."""
    import pinocchio as pin

    from .multibody import mjcf, mujoco_model, registry

    model = registry.load(robot, floating_base=floating_base, check_inertia=check_inertia)
    kind, value, _ = registry.resolve(robot)
    root = pin.JointModelFreeFlyer() if model.floating_base else None
    if kind == "mjcf" and mujoco_model.available():
        pm = pinocchio_of(model)  # MuJoCo compiled it: the same bodies, in Pinocchio
    elif kind == "mjcf":
        pm = mjcf.pinocchio_model(value, floating_base)
    elif kind == "text":
        pm = (pin.buildModelFromXML(value, root) if root is not None
              else pin.buildModelFromXML(value))
    else:
        path = str(registry.robot_path(value) if kind == "name" else value)
        pm = pin.buildModelFromUrdf(path, root) if root is not None else \
            pin.buildModelFromUrdf(path)
    if tuple(pm.names[1:]) != model.joint_names:
        raise RuntimeError(f"joint order differs from Pinocchio's: {list(pm.names[1:])} vs "
                           f"{list(model.joint_names)}")
    return model, pm


def pinocchio_of(model):
    """A ``pinocchio.Model`` of a cgadyn model: the same joints (each record's general
    Pinocchio type, the last of its ``pinocchio`` names, built with its axis), placements,
    bodies, armature and damping, and a ``BODY`` frame per link. For an MJCF model that
    MuJoCo compiled, Pinocchio's own parser reads other bodies (``multibody.mjcf``): this
    model checks the algorithms on the bodies MuJoCo compiled, and MuJoCo checks those
    (``mujoco_oracle``)."""
    import pinocchio as pin

    from .cga.conventions import motion_from_twist
    from .multibody.joints import TYPES

    pm = pin.Model()
    pm.name = model.name
    turn = [pin.SE3.Identity()] * model.njoints  # Pinocchio's joint frame in cgadyn's
    for j in range(model.njoints):
        record = TYPES[int(model.joint_types[j])]
        kind = getattr(pin, record.pinocchio[-1])
        try:
            if record.axis == "helical":
                motion = motion_from_twist(model.axes[j])
                joint = kind(model.axis_vectors[j], float(motion[:3] @ motion[3:]))
            else:
                joint = kind(model.axis_vectors[j]) if record.axis is not None else kind()
        except TypeError:  # RevoluteUnboundedUnaligned takes no axis in Python: about z,
            joint = getattr(pin, record.pinocchio[-2])()  # in a frame turned onto the axis
            turn[j] = pin.SE3(pin.Quaternion.FromTwoVectors(
                np.array([0.0, 0.0, 1.0]), model.axis_vectors[j]).matrix(), np.zeros(3))
        parent = int(model.parents[j])
        above = turn[parent] if parent >= 0 else pin.SE3.Identity()
        placement = above.inverse() * pin.SE3(model.placement_matrices[j]) * turn[j]
        pm.addJoint(parent + 1, joint, placement, model.joint_names[j])
        body = pin.Inertia(float(model.body_mass[j]), model.body_com[j],
                           model.body_rotational_inertia[j])
        pm.appendBodyToJoint(j + 1, turn[j].actInv(body), pin.SE3.Identity())
    for name, j, T in zip(model.link_names, model.link_joint, model.link_placement_matrices,
                          strict=True):
        above = turn[int(j)] if j >= 0 else pin.SE3.Identity()
        pm.addBodyFrame(name, int(j) + 1, above.inverse() * pin.SE3(T), 0)
    pm.armature = np.array(model.armature)
    pm.damping = np.array(model.damping)
    return pm


def pin_configuration(model, q: np.ndarray) -> np.ndarray:
    """cgadyn's configuration(s) (..., nq) in Pinocchio's layout, joint by joint
    (``multibody.joints``: a continuous joint's angle becomes (cos, sin); every other
    coordinate passes through)."""
    from .multibody.joints import table

    return table.to_pinocchio(model, q)


def cgadyn_configuration(model, qp: np.ndarray) -> np.ndarray:
    """Pinocchio's configuration(s) (..., pinocchio nq) in cgadyn's layout, the inverse of
    ``pin_configuration``: a continuous joint's (cos, sin) becomes the angle
    ``atan2(sin, cos)``; every other coordinate passes through."""
    from .multibody.joints import table

    return table.from_pinocchio(model, qp)


def joint_map(model, pm) -> np.ndarray:
    """int64 (``pm.njoints - 1``,): for each joint of the Pinocchio model ``pm`` that
    ``model`` was converted from (``from_pinocchio``), universe excluded and in Pinocchio's
    order, the cgadyn joint that carries its body: the joint of the same name. A universal
    or spherical ZYX joint is a chain of revolute joints in cgadyn whose last joint has its
    name, its body and its frame (the frame after the joint's whole motion, where Pinocchio
    expresses the joint's ``f_ext`` and places its ``oMi``), so that rows indexed by joint
    move between the libraries by this map: ``placements_pin = placements[map]``,
    ``f_ext[map] = f_ext_pin`` (``cgadyn_wrenches``). Raises ``ValueError`` naming a
    Pinocchio joint that ``model`` does not have (a model converted from another)."""
    names = list(pm.names)[1:]
    missing = [name for name in names if name not in model.joint_names]
    if missing:
        raise ValueError(f"joint_map: the Pinocchio model's joints {missing} are not joints "
                         f"of {model.name!r}; expected the model that "
                         f"cgadyn.from_pinocchio made of it")
    return np.array([model.joint_index(name) for name in names], dtype=np.int64)


def cgadyn_wrenches(model, pm, f_ext_pin) -> np.ndarray:
    """Pinocchio's external wrenches, one per joint of ``pm`` (``(..., pm.njoints - 1,
    6)``, ``[f, τ]`` in each joint's frame, universe excluded), as cgadyn's ``f_ext``
    (``(..., model.njoints, 6)``): each at the joint of ``joint_map``, zero at the joints
    inside a universal or spherical ZYX joint's chain (massless bodies that nothing
    pushes)."""
    f = np.asarray(f_ext_pin, dtype=float)
    nj = pm.njoints - 1
    if f.ndim < 2 or f.shape[-2:] != (nj, 6):
        raise ValueError(f"cgadyn_wrenches: Pinocchio's wrenches must have shape (..., {nj}, "
                         f"6), one [f, tau] per joint of its model, universe excluded; got "
                         f"{f.shape}")
    out = np.zeros(f.shape[:-2] + (model.njoints, 6))
    out[..., joint_map(model, pm), :] = f
    return out


def forces(f_ext: np.ndarray):
    """Pinocchio's list of forces (the universe's first) from cgadyn's (n, 6) ``f_ext``."""
    import pinocchio as pin

    return [pin.Force.Zero()] + [pin.Force(np.asarray(f, dtype=float)) for f in f_ext]


@dataclass(frozen=True)
class States:
    """A batch of random states, ``(B, nq)`` and ``(B, nv)`` each."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray


def sample(model, samples: int, seed) -> States:
    """Random states: q by ``random_configuration`` (joints uniform in their limits, [-π, π]
    where unbounded; free flyers in the unit box with a uniformly random rotation), v, a,
    τ standard normal."""
    from .algorithms.configuration import random_configuration

    rng = np.random.default_rng(seed)
    q = np.array([random_configuration(model, rng) for _ in range(samples)]).reshape(
        samples, model.nq)
    shape = (samples, model.nv)
    return States(q, rng.standard_normal(shape), rng.standard_normal(shape),
                  rng.standard_normal(shape))


def relative_error(mine, reference) -> np.ndarray:
    """Per sample, ``max|mine - reference| / max|reference|`` (``RELATIVE``): a relative
    error of the largest entry, whatever the scale of the quantity."""
    ref = np.asarray(reference, dtype=float)
    samples = ref.shape[0]
    diff = np.abs(np.asarray(mine, dtype=float) - ref).reshape(samples, -1)
    scale = np.abs(ref).reshape(samples, -1).max(axis=1, initial=0.0)
    return diff.max(axis=1, initial=0.0) / np.maximum(scale, TINY)


def symmetric(H: np.ndarray) -> np.ndarray:
    """The full symmetric matrix of one whose upper triangle Pinocchio filled."""
    return np.triu(H) + np.triu(H, 1).T


@dataclass(frozen=True)
class Check:
    """One quantity compared: ``mine(model, states, links)`` returns the batch in cgadyn;
    ``theirs(pm, data, qp, states, i, frames)`` one sample in Pinocchio (None: see
    ``fk_reference``). ``scaled``: judged against tolerance × cond(M)."""

    key: str
    label: str
    mine: Callable
    theirs: Callable
    scaled: bool = False


def _pin():
    import pinocchio

    return pinocchio


def _frames(pm, names):
    pin = _pin()
    return [pm.getFrameId(n, pin.BODY) for n in names]


def _six_by_nv(pm, x) -> np.ndarray:
    """A Pinocchio 6 x nv result in its documented shape: the bindings return a matrix of
    one column as a vector (6,), which would not compare with cgadyn's (6, 1)."""
    return np.array(x, dtype=float).reshape(6, pm.nv)


def _jacobians(pm, d, qp, frames, reference):
    pin = _pin()
    pin.computeJointJacobians(pm, d, qp)
    pin.updateFramePlacements(pm, d)
    return np.stack([_six_by_nv(pm, pin.getFrameJacobian(pm, d, f, reference))
                     for f in frames])


def _cg():
    import cgadyn

    return cgadyn


CHECKS = (
    Check("rnea", "inverse dynamics (rnea)",
          lambda m, s, L: _cg().rnea(m, s.q, s.v, s.a),
          lambda pm, d, qp, s, i, F: _pin().rnea(pm, d, qp, s.v[i], s.a[i]).copy()),
    Check("aba", "forward dynamics (aba)",
          lambda m, s, L: _cg().aba(m, s.q, s.v, s.tau),
          lambda pm, d, qp, s, i, F: _pin().aba(pm, d, qp, s.v[i], s.tau[i]).copy(),
          scaled=True),
    Check("crba", "mass matrix (crba)",
          lambda m, s, L: _cg().crba(m, s.q),
          lambda pm, d, qp, s, i, F: symmetric(_pin().crba(pm, d, qp))),
    Check("gravity", "gravity torques g(q)",
          lambda m, s, L: _cg().gravity_torques(m, s.q),
          lambda pm, d, qp, s, i, F: _pin().computeGeneralizedGravity(pm, d, qp).copy()),
    Check("jacobian_world", "Jacobians, world frame",
          lambda m, s, L: np.stack([_cg().jacobian(m, s.q, link) for link in L], 1),
          lambda pm, d, qp, s, i, F: _jacobians(pm, d, qp, F, _pin().WORLD)),
    Check("jacobian_local", "Jacobians, local frame",
          lambda m, s, L: np.stack([_cg().jacobian(m, s.q, link, "local") for link in L], 1),
          lambda pm, d, qp, s, i, F: _jacobians(pm, d, qp, F, _pin().LOCAL)),
    Check("fk", "forward kinematics (all links)",
          lambda m, s, L: _cg().link_placements(m, s.q),
          None),
    Check("rnea_derivatives", "∂τ/∂q, ∂τ/∂v (rnea derivatives)",
          lambda m, s, L: np.stack(_cg().rnea_derivatives(m, s.q, s.v, s.a)[:2], 1),
          lambda pm, d, qp, s, i, F: np.stack(
              [x.copy() for x in _pin().computeRNEADerivatives(pm, d, qp, s.v[i], s.a[i])[:2]])),
    Check("aba_derivatives", "∂q̈/∂q, ∂q̈/∂v (aba derivatives)",
          lambda m, s, L: np.stack(_cg().aba_derivatives(m, s.q, s.v, s.tau)[:2], 1),
          lambda pm, d, qp, s, i, F: np.stack(
              [x.copy() for x in _pin().computeABADerivatives(pm, d, qp, s.v[i], s.tau[i])[:2]]),
          scaled=True),
    Check("minverse", "inverse mass matrix M⁻¹",
          lambda m, s, L: _cg().minverse(m, s.q),
          lambda pm, d, qp, s, i, F: symmetric(_pin().computeMinverse(pm, d, qp)),
          scaled=True),
    Check("centroidal", "centroidal momentum matrix (ccrba)",
          lambda m, s, L: _cg().centroidal_momentum_matrix(m, s.q),
          lambda pm, d, qp, s, i, F: _six_by_nv(pm, _pin().ccrba(pm, d, qp, s.v[i]))),
    Check("com", "centre of mass, velocity, acceleration",
          lambda m, s, L: np.stack(_cg().center_of_mass(m, s.q, s.v, s.a), 1),
          lambda pm, d, qp, s, i, F: (_pin().centerOfMass(pm, d, qp, s.v[i], s.a[i]),
                                      np.stack([d.com[0], d.vcom[0], d.acom[0]]))[1]),
    Check("manifold", "integrate, difference (manifold)",
          lambda m, s, L: np.concatenate(
              [pin_configuration(m, _cg().integrate(m, s.q, s.v)),
               _cg().difference(m, s.q, _cg().integrate(m, s.q, 0.3 * s.v))], 1),
          lambda pm, d, qp, s, i, F: np.concatenate(
              [_pin().integrate(pm, qp, s.v[i]), _pin().difference(
                  pm, qp, _pin().integrate(pm, qp, 0.3 * s.v[i]))])),
)

BY_KEY = {c.key: c for c in CHECKS}


def fk_reference(pm, d, qp, link_names) -> np.ndarray:
    """Pinocchio's world placements of the named links."""
    pin = _pin()
    pin.forwardKinematics(pm, d, qp)
    pin.updateFramePlacements(pm, d)
    return np.stack([d.oMf[f].homogeneous for f in _frames(pm, link_names)])


def conditioning(model, q: np.ndarray) -> np.ndarray:
    """cond(M(q)) per sample (2-norm)."""
    from .algorithms.api import crba

    return np.linalg.cond(crba(model, q))


def finite_or_none(x: float):
    """A number for standard JSON: ``None`` for NaN and inf."""
    return float(x) if math.isfinite(x) else None


def pin_constraints(model, pm, constraints):
    """Pinocchio's ``(StdVec_RigidConstraintModel, StdVec_RigidConstraintData)`` of cgadyn
    ``Constraint``s: each end on the joint that carries its link's ``BODY`` frame in ``pm``
    (joint 0, the world, for a world anchor or a link fixed to the world), its placement in
    that joint's frame (through the frame's, which holds any turn between the libraries'
    joint frames: ``pinocchio_of``), the same reference frame and Baumgarte gains."""
    pin = _pin()
    kinds = {"point": pin.ContactType.CONTACT_3D, "frame": pin.ContactType.CONTACT_6D}
    frames = {"local": pin.LOCAL, "local_world_aligned": pin.LOCAL_WORLD_ALIGNED}

    def end(link, placement):
        if link is None:
            return 0, pin.SE3(placement)
        frame = pm.frames[pm.getFrameId(model.link_names[link], pin.BODY)]  # the link's
        return int(frame.parentJoint), frame.placement * pin.SE3(placement)  # Pinocchio frame

    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for c in constraints:
        j1, P1 = end(c.link, c.placement)
        j2, P2 = end(c.other, c.other_placement)
        cm = pin.RigidConstraintModel(kinds[c.kind], pm, j1, P1, j2, P2, frames[c.frame])
        cm.setBaumgarteCorrectorParameters(pin.BaumgarteCorrectorParameters(*c.corrector))
        models.append(cm)
        datas.append(cm.createData())
    return models, datas
