"""Convert a Pinocchio model into a cgadyn :class:`~cgadyn.multibody.model.Model`.

``from_pinocchio(pin_model)`` reads what Pinocchio already built, whatever built it: a
model made in code (``pin.Model().addJoint``, ``appendBodyToJoint``, ``addBodyFrame``),
parsed from URDF, or parsed from MJCF (``pinocchio.buildModelFromMJCF``). It keeps
Pinocchio's joints, their order and so the order of ``v``; bodies welded by fixed joints
are already merged into their joint's inertia by Pinocchio, as cgadyn's URDF loader merges
them, and every ``BODY`` frame becomes a link of the model.

The joint types converted (``SUPPORTED``): revolute about any axis (``JointModelRX``,
``RY``, ``RZ``, ``RevoluteUnaligned``), unbounded revolute (``RUBX``, ``RUBY``, ``RUBZ``,
``RevoluteUnboundedUnaligned``), prismatic (``PX``, ``PY``, ``PZ``,
``PrismaticUnaligned``), spherical (``Spherical``, anywhere in the tree: q its quaternion
``(x, y, z, w)`` as Pinocchio's), planar (``Planar``: q ``(x, y, cos θ, sin θ)``),
translation (``Translation``), helical (``HX``, ``HY``, ``HZ``, ``HelicalUnaligned``, with
their pitch) and free flyers (``FreeFlyer``), each the root of a tree (a child of the
universe: a robot's floating base, a free object beside it). A universal
(``Universal``) or spherical ZYX (``SphericalZYX``) joint, whose motion subspace turns with
q, becomes the chain of revolute joints it is (``CHAINS``): one per coordinate, through
massless bodies, the last named after the joint and carrying its body, the others
``<name>.axis1``, ``<name>.axis2``; q and v are Pinocchio's, the joints one or two more.
Any other joint (composite, mimic, ...) is refused by name.

Configurations: an unbounded revolute joint takes two numbers ``(cos θ, sin θ)`` in
Pinocchio's q and one angle θ in cgadyn's, so for a model with such joints ``nq`` differs
and q converts with ``cgadyn.oracle.cgadyn_configuration`` (Pinocchio's q to cgadyn's) and
``cgadyn.oracle.pin_configuration`` (back). Every other coordinate, and all of v, a, τ, is
the same in both.
"""

from __future__ import annotations

import numpy as np

from cgadyn.multibody.joints import TYPES, of_kind
from cgadyn.multibody.joints.table import PINOCCHIO
from cgadyn.multibody.model import Model, build_model
from cgadyn.multibody.packed import DEFAULT_GRAVITY

SUPPORTED = {name: record.kind for name, record in PINOCCHIO.items()}
"""Pinocchio's joint types that cgadyn models, and the joint kind each becomes (each joint
type's record, ``multibody.joints``, names its Pinocchio types)."""

CHAINS = {"JointModelUniversal": 2, "JointModelSphericalZYX": 3}
"""Pinocchio's joints whose motion subspace turns with q (``S(q)`` in the child frame, and
a bias acceleration ``Ṡ(q) q̇``), with how many coordinates each has. Each is the chain of
revolute joints it composes, ``M_J(q) = exp(q1 B1 / 2) exp(q2 B2 / 2) ...`` (eq. 6: the
universal joint's two axes, the Z, Y, X axes of the ZYX Euler angles), and converts to that
chain: one revolute joint per coordinate, through massless bodies, the axes the columns of
``S`` at q = 0. Its q and v are Pinocchio's (both joints' v is q̇, their configuration
space a vector space); the chain's velocity-product terms are the joint's bias ``Ṡ q̇``."""

_SUPPORTED_TEXT = ", ".join(
    f"{r.label} ({', '.join(r.pinocchio)}){' as the root of a tree' if r.floating else ''}"
    for r in TYPES) + ", and as chains of revolute joints " + ", ".join(CHAINS)

_HUGE = 1e300  # Pinocchio's "no limit" is ±DBL_MAX


def _subspace(joint, q0: np.ndarray, c: int = 0) -> np.ndarray:
    """Column c of a joint's motion subspace ``S = [linear, angular]`` (6,) at ``q0``, as
    Pinocchio computes it (the Python bindings do not expose every joint's axis,
    ``RevoluteUnboundedUnaligned``'s among them). ``q0``: the model's neutral
    configuration (where a joint of ``CHAINS`` has its chain's axes as columns)."""
    data = joint.createData()
    joint.calc(data, q0)
    return np.asarray(data.S, dtype=float).reshape(6, -1)[:, c]


def _axis(joint, axis: str, q0: np.ndarray, c: int = 0) -> np.ndarray:
    """The unit axis of a one-dof joint (or of coordinate c of a joint of ``CHAINS``) in its
    joint frame: the angular (revolute, helical) or linear (prismatic) part of its motion
    subspace ``S``."""
    S = _subspace(joint, q0, c)
    return S[:3].copy() if axis == "prismatic" else S[3:].copy()


def _pitch(joint, q0: np.ndarray) -> float:
    """A helical joint's pitch h, from its ``S = [h a, a]``."""
    S = _subspace(joint, q0)
    return float(S[:3] @ S[3:] / (S[3:] @ S[3:]))


_UNIT = 1e-12
"""How far from 1 a joint axis's norm may be for Pinocchio's model to count as unit."""


def _checked_axis(name: str, shortname: str, kind: str, axis: np.ndarray) -> np.ndarray:
    """A one-dof joint's axis, as cgadyn holds it. A revolute axis must be a unit vector:
    Pinocchio's revolute joints (``RevoluteUnaligned``) turn by a matrix that is a rotation
    only for a unit axis, so with another its model is not a rigid body's (refused, naming
    the joint). A prismatic axis may have any length: Pinocchio moves the body by ``q``
    times it, and so does cgadyn (the axis is kept as it is, not normalised)."""
    norm = float(np.linalg.norm(axis))
    if kind == "prismatic" or abs(norm - 1.0) <= _UNIT:
        return axis
    raise ValueError(f"joint {name!r} is a {shortname} about the axis {axis.tolist()} of norm "
                     f"{norm:.17g}; Pinocchio's revolute joints turn by a matrix that is a "
                     f"rotation only for a unit axis, so this model is not a rigid body's; "
                     f"expected a unit axis (build the joint with axis / norm(axis))")


def _unbounded(values) -> np.ndarray:
    """Pinocchio's ±DBL_MAX ("no limit") as ±inf."""
    out = np.array(values, dtype=float).reshape(-1)
    out[out >= _HUGE] = np.inf
    out[out <= -_HUGE] = -np.inf
    return out


def _kinds(pm) -> list[tuple[int, str, int, int]]:
    """``(Pinocchio's joint index, cgadyn joint kind, c, count)`` of every cgadyn joint: one
    per joint of ``pm`` (universe excluded), or ``count`` revolute joints ``c = 0, 1, ...``
    for a joint of ``CHAINS``; a ``ValueError`` names the first joint that cgadyn cannot
    model."""
    kinds = []
    for i in range(1, pm.njoints):
        shortname = pm.joints[i].shortname()
        if shortname in CHAINS:
            kinds += [(i, "revolute", c, CHAINS[shortname]) for c in range(CHAINS[shortname])]
            continue
        kind = SUPPORTED.get(shortname)
        if kind is None:
            raise ValueError(f"joint {pm.names[i]!r} is a {shortname}, which cgadyn does not "
                             f"support; supported joints: {_SUPPORTED_TEXT}")
        if of_kind(kind).floating and pm.parents[i] != 0:
            raise ValueError(f"joint {pm.names[i]!r} is a {shortname} whose parent is not "
                             f"the universe; cgadyn supports a {of_kind(kind).label} joint "
                             f"only as the root of a tree (a child of the universe)")
        kinds.append((i, kind, 0, 1))
    return kinds


def _check_dynamics(pm) -> None:
    """Refuse what Pinocchio's dynamics would include and cgadyn's model cannot hold."""
    gravity = np.asarray(pm.gravity.linear, dtype=float)
    if not np.allclose(gravity, DEFAULT_GRAVITY, rtol=0.0, atol=1e-12) or np.any(
            np.asarray(pm.gravity.angular) != 0.0):
        raise ValueError(f"the Pinocchio model's gravity is {gravity.tolist()}, but a cgadyn "
                         f"model uses {list(DEFAULT_GRAVITY)} unless a call passes gravity=; "
                         f"set pin_model.gravity to that and pass your gravity to the calls")


def _check_finite(joint: str, mass: float, com, rotational) -> None:
    """Refuse a body whose mass, centre of mass or rotational inertia is not finite, naming
    its joint (Pinocchio holds NaN without complaint)."""
    for what, value in (("mass", mass), ("centre of mass (lever)", com),
                        ("rotational inertia", rotational)):
        if not np.all(np.isfinite(value)):
            raise ValueError(f"the body of joint {joint!r} has a {what} that is not finite: "
                             f"{np.asarray(value).tolist()}; expected finite numbers")


def _check_inertia(joint: str, mass: float, rotational) -> None:
    """Refuse a body whose mass is negative or whose rotational inertia about its centre of
    mass is not positive semi-definite, naming its joint."""
    eig = np.linalg.eigvalsh(0.5 * (rotational + rotational.T))
    if mass < 0.0 or eig.min() < -1e-12 * max(1.0, float(np.abs(eig).max())):
        raise ValueError(f"the body of joint {joint!r} has mass {mass} and rotational "
                         f"inertia eigenvalues {eig.tolist()}; expected a physical inertia "
                         f"(mass >= 0, positive semi-definite; convert with "
                         f"check_inertia=False to accept it, as Pinocchio does)")


def _links(pm, last: dict[int, int]):
    """``(names, joint, placements, root)`` of the links: Pinocchio's ``BODY`` frames, each
    in the frame of its parent joint (``-1``: the world; ``last``: the cgadyn joint of each
    Pinocchio joint, the last of a chain's); ``None`` when there is none."""
    import pinocchio as pin

    bodies = [f for f in pm.frames if f.type == pin.FrameType.BODY]
    if not bodies:
        return None
    names = [f.name for f in bodies]
    joint = [last.get(int(f.parentJoint), -1) for f in bodies]
    placements = np.array([f.placement.homogeneous for f in bodies]).reshape(-1, 4, 4)
    first = PINOCCHIO.get(pm.joints[1].shortname()) if pm.njoints > 1 else None
    root_joint = 0 if first is not None and first.floating else -1
    root = next((f.name for f, j in zip(bodies, joint, strict=True) if j == root_joint),
                "universe")
    return names, joint, placements, root


def from_pinocchio(pin_model, name: str | None = None, check_inertia: bool = True) -> Model:
    """The cgadyn :class:`Model` of a Pinocchio model (``pinocchio.Model``).

    Joints (``pin_model.names[1:]``), their order, parents, placements
    (``jointPlacements``), axes and bodies (``inertias``, fixed bodies already merged in)
    are Pinocchio's, so ``v``, ``a``, ``τ`` and the Jacobians' columns are laid out alike;
    q too, except that an unbounded revolute joint takes one angle (see the module's
    docstring). Position, velocity and effort limits are Pinocchio's (``±DBL_MAX`` becomes
    ``±inf``). The links are the ``BODY`` frames (their names, parent joints and
    placements); a model without any gets one link per joint, named after it, and the
    root link ``universe``. ``name`` defaults to ``pin_model.name``.

    The rotor inertias ``armature`` and the viscous ``damping`` (nv each) are Pinocchio's
    (``Model.armature``, ``Model.damping``).

    Raises ``ValueError`` naming a joint that cgadyn does not support (its name, its
    Pinocchio type and what is supported), a free flyer whose parent is not the universe, joints
    not in depth-first order, a negative armature or damping, a gravity other than
    cgadyn's default,
    and (with ``check_inertia``) a body whose inertia is not physically valid.
    """
    try:
        import pinocchio as pin
    except ImportError:  # pragma: no cover - pinocchio is a test dependency
        raise ImportError("from_pinocchio needs Pinocchio: pip install pin") from None
    if not isinstance(pin_model, pin.Model):
        raise ValueError(f"from_pinocchio expects a pinocchio.Model, got "
                         f"{type(pin_model).__name__}")
    pm = pin_model
    pieces = _kinds(pm)
    kinds = [kind for _, kind, _, _ in pieces]
    _check_dynamics(pm)
    n = len(kinds)
    last = {i: j for j, (i, _, _, _) in enumerate(pieces)}  # a chain's last joint
    names, parents, placements = [], [], np.zeros((n, 4, 4))
    lower, upper = _unbounded(pm.lowerPositionLimit), _unbounded(pm.upperPositionLimit)
    velocity, effort = _unbounded(pm.velocityLimit), _unbounded(pm.effortLimit)
    axes = np.zeros((n, 3))
    pitch = np.zeros(n)
    q0 = pin.neutral(pm)
    q_lower, q_upper = [], []
    body_mass = np.zeros(n)
    body_com = np.zeros((n, 3))
    body_rot = np.zeros((n, 3, 3))
    for j, (k, kind, c, count) in enumerate(pieces):
        joint, i, record = pm.joints[k], pm.idx_qs[k] + c, of_kind(kind)
        nq = record.pinocchio_nq if count == 1 else 1
        names.append(pm.names[k] if c == count - 1 else f"{pm.names[k]}.axis{c + 1}")
        parents.append(j - 1 if c > 0 else last.get(int(pm.parents[k]), -1))
        placements[j] = pm.jointPlacements[k].homogeneous if c == 0 else np.eye(4)
        if record.pinocchio_nq != record.nq:  # (cos, sin) in Pinocchio, one angle in cgadyn
            q_lower += [-np.inf] * record.nq
            q_upper += [np.inf] * record.nq
        else:
            q_lower += lower[i:i + nq].tolist()
            q_upper += upper[i:i + nq].tolist()
        if record.axis is not None:
            axes[j] = _checked_axis(pm.names[k], joint.shortname(), record.axis,
                                    _axis(joint, record.axis, q0, c))
        if record.axis == "helical":
            pitch[j] = _pitch(joint, q0)
        if c < count - 1:
            continue  # a massless body inside a chain
        inertia = pm.inertias[k]
        body_mass[j], body_com[j], body_rot[j] = inertia.mass, inertia.lever, inertia.inertia
        _check_finite(pm.names[k], body_mass[j], body_com[j], body_rot[j])
        if check_inertia:
            _check_inertia(pm.names[k], body_mass[j], body_rot[j])
    links = _links(pm, last)
    link_args = {} if links is None else dict(
        link_names=links[0], link_joint=links[1], link_placement_matrices=links[2],
        root_link=links[3])
    if links is None:
        link_args["root_link"] = "universe"
    try:
        model = build_model(
            name=pm.name if name is None else name,
            joint_names=names,
            joint_kinds=kinds,
            parents=parents,
            placement_matrices=placements,
            axis_vectors=axes,
            body_mass=body_mass,
            body_com=body_com,
            body_rotational_inertia=body_rot,
            lower=q_lower,
            upper=q_upper,
            velocity_limit=velocity,
            effort_limit=effort,
            check_inertia=check_inertia,
            armature=np.asarray(pm.armature, dtype=float),
            damping=np.asarray(pm.damping, dtype=float),
            friction=np.asarray(pm.friction, dtype=float),
            pitch=pitch,
            **link_args,
        )
    except ValueError as exc:
        raise ValueError(f"Pinocchio model {pm.name!r}: {exc}") from None
    return _scaled_prismatic_axes(model, axes)


def _scaled_prismatic_axes(model: Model, axes: np.ndarray) -> Model:
    """``model`` with its prismatic joints' axes as long as Pinocchio's (``build_model``
    normalises every axis, as URDF's parsers do). A ``PrismaticUnaligned`` joint built with
    the axis ``a`` moves its body by ``q a``: with ``a`` normalised, q, v, τ and so rnea,
    crba and the placements would differ by the factor ``|a|``. The prismatic motion
    subspace ``S = (a, 0)`` enters the recursions linearly (a translator
    ``1 - q/2 e∞ a``), so a non-unit one is exact."""
    import dataclasses

    from cgadyn.cga.conventions import twist_from_motion

    direction = np.array([of_kind(k).axis == "prismatic" for k in model.joint_kinds],
                         dtype=bool).reshape(-1)
    prismatic = np.flatnonzero(direction & (np.abs(np.linalg.norm(axes, axis=1) - 1.0) > _UNIT))
    if prismatic.size == 0:
        return model
    twists, vectors = np.array(model.axes), np.array(model.axis_vectors)
    for j in prismatic:
        vectors[j] = axes[j]
        twists[j] = twist_from_motion(np.concatenate([axes[j], np.zeros(3)]))
    return dataclasses.replace(model, axes=twists, axis_vectors=vectors)
