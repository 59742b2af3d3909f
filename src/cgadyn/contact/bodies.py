"""Free rigid bodies in the world: a box, a ball, a capsule a robot can touch and push
(docs/contact.md, "Free bodies and pairs", K36-K37).

A ``Body`` is one collision shape with a mass and an inertia. ``with_bodies(model,
collisions, bodies)`` appends each as a free-flyer root of the model (a joint with parent
``-1`` after the robot's, Pinocchio's layout ``[x, y, z, qx, qy, qz, qw]`` and ``[v, ω]`` in
the body frame), its link named after it and its shape a collision of that link: every
algorithm, the manifold integration and the compiled rollouts then handle the bodies as the
links they are, without a special case.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field, replace

import numpy as np

from .model import Collision, CollisionModel, _collisions
from .obstacles import placement, pose_matrix, scene_collisions
from .shapes import BOX, CAPSULE, CYLINDER, ELLIPSOID, MESH, PLANE, SPHERE, Shape

__all__ = ["Body", "check_start", "empty_model", "shape_inertia", "with_bodies", "world_model"]

_NEUTRAL = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
"""A free flyer's neutral configuration (Pinocchio's layout)."""


def shape_inertia(shape: Shape, mass: float) -> tuple[np.ndarray, np.ndarray]:
    """``(com, inertia about com)`` of the solid ``shape`` of uniform density and ``mass``,
    in the shape's frame (K36): a sphere ``2/5 m r²``; an ellipsoid ``m/5 (r_j² + r_k²)``; a
    box ``m/3 (h_j² + h_k²)``; a
    cylinder ``m (3 r² + L²) / 12`` across, ``m r² / 2`` along z; a capsule its cylinder and
    its two half balls (each ``2/5 m_h r²`` about the axis, ``83/320 m_h r²`` across about
    its centroid ``3r/8`` from its flat face, moved to the centre by Steiner's rule); a
    convex mesh its hull split into tetrahedra from an
    interior point (each tetrahedron's exact second moment)."""
    kind, s = shape.kind, shape.packed_size
    if kind == SPHERE:
        return np.zeros(3), 0.4 * mass * s[0] ** 2 * np.eye(3)
    if kind == ELLIPSOID:
        r2 = s[:3] ** 2
        return np.zeros(3), mass / 5.0 * np.diag([r2[1] + r2[2], r2[0] + r2[2], r2[0] + r2[1]])
    if kind == BOX:
        h2 = s[:3] ** 2
        return np.zeros(3), mass / 3.0 * np.diag([h2[1] + h2[2], h2[0] + h2[2], h2[0] + h2[1]])
    if kind == CYLINDER:
        r, L = s[0], 2.0 * s[1]
        across = mass * (3.0 * r * r + L * L) / 12.0
        return np.zeros(3), np.diag([across, across, 0.5 * mass * r * r])
    if kind == CAPSULE:
        r, L = s[0], 2.0 * s[1]
        vc, vs = np.pi * r * r * L, 4.0 / 3.0 * np.pi * r ** 3  # cylinder, both half balls
        mc, ms = mass * vc / (vc + vs), mass * vs / (vc + vs)
        # a half ball about its centroid (3r/8 from the flat face), across the axis:
        # 83/320 m r²; its centroid lies L/2 + 3r/8 from the capsule's centre
        across_half = 83.0 / 320.0 * 0.5 * ms * r * r + 0.5 * ms * (0.5 * L + 3.0 * r / 8) ** 2
        across = mc * (3.0 * r * r + L * L) / 12.0 + 2.0 * across_half
        return np.zeros(3), np.diag([across, across, 0.5 * mc * r * r + 0.4 * ms * r * r])
    if kind == MESH:
        return _hull_inertia(np.asarray(shape.packed_vertices), mass)
    raise ValueError(f"no inertia for a {shape.name}: a body's shape must be a sphere, box, "
                     f"capsule, cylinder, ellipsoid or convex mesh")


def _hull_inertia(vertices: np.ndarray, mass: float) -> tuple[np.ndarray, np.ndarray]:
    """The convex hull of ``vertices`` as tetrahedra ``(o, a, b, c)`` from its mean vertex:
    volume ``V = det[a-o, b-o, c-o] / 6``, centroid the corners' mean, second moment
    ``∫ x xᵀ = V/20 (Σ x_i x_iᵀ + (Σ x_i)(Σ x_i)ᵀ)`` over the four corners."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(vertices)
    o = vertices.mean(axis=0)
    volume, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for face in hull.simplices:
        corners = np.vstack([o, vertices[face]])
        v = abs(np.linalg.det(corners[1:] - o)) / 6.0
        total = corners.sum(axis=0)
        volume += v
        first += v * total / 4.0
        second += v / 20.0 * (corners.T @ corners + np.outer(total, total))
    com = first / volume
    about = second / volume - np.outer(com, com)  # per unit mass, about the centroid
    return com, mass * (np.trace(about) * np.eye(3) - about)


@dataclass(frozen=True)
class Body:
    """A free rigid body: ``shape`` (a ``Sphere``, ``Box``, ``Capsule``, ``Cylinder`` or
    ``ConvexMesh``, centred on the body's frame), ``mass`` (kg, > 0), ``inertia`` (3x3 about
    the centre of mass, body axes; None: the solid shape of uniform density, K36, whose
    centre of mass is the shape's centroid), its start ``position`` and ``orientation``
    (a quaternion ``(x, y, z, w)``, normalised here), ``friction`` (its Coulomb
    coefficient; None: the World's) and ``name`` (None: ``body<i>`` by its place in the
    World). It starts at rest; only gravity and contacts move it (never a controller)."""

    shape: Shape
    mass: float
    inertia: np.ndarray | None = field(default=None, repr=False)
    position: tuple = (0.0, 0.0, 0.0)
    orientation: tuple = (0.0, 0.0, 0.0, 1.0)
    friction: float | None = None
    name: str | None = None

    def __post_init__(self):
        who = f"Body {self.name!r}" if self.name is not None else "Body"
        if not isinstance(self.shape, Shape) or self.shape.kind == PLANE:
            raise ValueError(f"{who}: shape must be a cgadyn Sphere, Box, Capsule, Cylinder or "
                             f"ConvexMesh, got {self.shape!r}")
        if self.shape.placed:
            raise ValueError(f"{who}: a body's shape is centred on the body (it carries no "
                             f"placement); give the body's position and orientation instead")
        if isinstance(self.mass, bool) or not isinstance(self.mass, numbers.Real) or \
                not np.isfinite(self.mass) or self.mass <= 0:
            raise ValueError(f"{who}: mass must be a finite number > 0 (kg), got {self.mass!r}")
        com, inertia = shape_inertia(self.shape, float(self.mass))
        if self.inertia is not None:
            inertia = np.asarray(self.inertia, dtype=float)
            if inertia.shape != (3, 3) or not np.all(np.isfinite(inertia)) or \
                    not np.allclose(inertia, inertia.T) or np.linalg.eigvalsh(inertia)[0] <= 0:
                raise ValueError(f"{who}: inertia must be a symmetric positive definite 3x3 "
                                 f"matrix (about the centre of mass), got {self.inertia!r}")
            com = np.zeros(3) if self.shape.kind != MESH else com
        p, quat = placement(who, self.position, self.orientation, self.friction, self.name)
        object.__setattr__(self, "mass", float(self.mass))
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "com", com)
        object.__setattr__(self, "position", p)
        object.__setattr__(self, "orientation", quat)

    @property
    def q(self) -> np.ndarray:
        """Its start configuration, ``[x, y, z, qx, qy, qz, qw]``."""
        return np.array([*self.position, *self.orientation])


def body_names(bodies) -> list[str]:
    """Each body's name: its own, or ``body<i>``."""
    return [b.name if b.name is not None else f"body{i}" for i, b in enumerate(bodies)]


def with_bodies(model, collisions, bodies) -> tuple[object, CollisionModel, np.ndarray]:
    """``(model', collisions', q_bodies)``: ``model`` with each of ``bodies`` appended as a
    free-flyer root (joint and link named after the body), ``collisions`` (None: none) with
    each body's shape on its link (its ``friction`` kept on the collision), and the bodies'
    start coordinates ``q_bodies`` (7 per body) to append to the robot's q. Raises
    ``ValueError`` naming a body whose name a joint or link of ``model`` already has."""
    from ..cga.conventions import inertia_from_parameters, motor_from_matrix
    from ..multibody.joints.table import of_kind

    bodies = list(bodies)
    names = body_names(bodies)
    cm = CollisionModel([], model) if collisions is None else _collisions(collisions, model)
    for b, name in zip(bodies, names, strict=True):
        if not isinstance(b, Body):
            raise ValueError(f"bodies must be cgadyn.Body records, got {b!r}")
        if name in model.joint_names or name in model.link_names or names.count(name) > 1:
            raise ValueError(f"Body {name!r}: the name is taken (a joint or link of "
                             f"{model.name!r}, or another body); give each body its own name")
    if not bodies:
        return model, cm, np.zeros(0)
    n, nb = model.njoints, len(bodies)
    record = of_kind("free_flyer")
    eye = np.broadcast_to(np.eye(4), (nb, 4, 4))
    identity = motor_from_matrix(np.eye(4))
    lower, upper = record.limits(np.full(7, -np.inf), np.full(7, np.inf))
    nv = 6 * nb

    def cat(a, b):
        return np.concatenate([np.asarray(a), np.asarray(b)])

    extended = replace(
        model,
        joint_names=(*model.joint_names, *names),
        joint_kinds=(*model.joint_kinds, *(["free_flyer"] * nb)),
        joint_types=cat(model.joint_types, [record.code] * nb),
        parents=cat(model.parents, [-1] * nb),
        placements=cat(model.placements, np.tile(identity, (nb, 1))),
        axes=cat(model.axes, np.zeros((nb, 6))),
        inertias=cat(model.inertias, [inertia_from_parameters(b.mass, b.com, b.inertia)
                                      for b in bodies]),
        body_mass=cat(model.body_mass, [b.mass for b in bodies]),
        body_com=cat(model.body_com, [b.com for b in bodies]),
        body_rotational_inertia=cat(model.body_rotational_inertia, [b.inertia for b in bodies]),
        lower=cat(model.lower, np.tile(lower, nb)),
        upper=cat(model.upper, np.tile(upper, nb)),
        velocity_limit=cat(model.velocity_limit, np.full(nv, np.inf)),
        effort_limit=cat(model.effort_limit, np.full(nv, np.inf)),
        link_names=(*model.link_names, *names),
        link_joint=cat(model.link_joint, n + np.arange(nb)),
        link_placements=cat(model.link_placements, np.tile(identity, (nb, 1))),
        placement_matrices=cat(model.placement_matrices, eye),
        axis_vectors=cat(model.axis_vectors, np.zeros((nb, 3))),
        link_placement_matrices=cat(model.link_placement_matrices, eye),
        mimic=(*model.mimic, *([None] * nb)),
        armature=cat(model.armature, np.zeros(nv)),
        damping=cat(model.damping, np.zeros(nv)),
        friction=cat(model.friction, np.zeros(nv)),
        stiffness=cat(model.stiffness, np.zeros(nv)),
        spring_reference=cat(model.spring_reference, np.tile(_NEUTRAL, nb)),
        home=cat(model.home, np.concatenate([b.q for b in bodies])),
        cone_limit=cat(model.cone_limit, np.full(nb, np.inf)),
        tendon_coefficients=np.hstack([model.tendon_coefficients,
                                       np.zeros((len(model.tendon_names), nv))]),
        coupling_coefficients=np.hstack([model.coupling_coefficients,
                                         np.zeros((len(model.coupling_names), nv))]),
    )
    links = model.nlinks + np.arange(nb)
    shapes = [*cm, *(Collision(name, b.shape, int(li), np.eye(4), friction=b.friction)
                     for b, name, li in zip(bodies, names, links, strict=True))]
    return extended, CollisionModel(shapes, extended), np.concatenate([b.q for b in bodies])


_EXTENDED: dict = {}
"""``with_bodies``' results by the ids of its arguments (kept alive with them), so that a
loop of ``contact_step`` calls builds the model once."""


def world_model(model, collisions, world) -> tuple[object, CollisionModel, np.ndarray]:
    """``with_bodies(model, scene, world.bodies)`` where ``scene`` is ``collisions`` (None:
    none) with the world's obstacles in place of their own world shapes
    (``obstacles.scene_collisions``, K44): the model, the collision model and the bodies'
    start coordinates of a step or a rollout in ``world``, built once per model, collisions,
    bodies and obstacles (a cache of the last few)."""
    key = (id(model), id(collisions), tuple(id(b) for b in world.bodies),
           tuple(id(o) for o in world.obstacles))
    hit = _EXTENDED.get(key)
    if hit is None:
        if len(_EXTENDED) >= 8:
            _EXTENDED.pop(next(iter(_EXTENDED)))
        cm = CollisionModel([], model) if collisions is None else _collisions(collisions, model)
        hit = (with_bodies(model, scene_collisions(cm, world, model), world.bodies), model,
               collisions, world.bodies, world.obstacles)
        _EXTENDED[key] = hit
    return hit[0]


INSIDE_GROUND = 1e-3
"""How deep (m) a body may start inside the ground before ``check_start`` refuses it."""


def check_start(world) -> None:
    """Raise ``ValueError`` naming a body of ``world`` that starts more than
    ``INSIDE_GROUND`` inside its ground (a penetration the step would throw it out of): its
    deepest point against the ground's plane (``distance.against_plane``, K5)."""
    from .distance import OUT, against_plane

    if not world.ground:
        return
    out = np.empty(OUT)
    for b, name in zip(world.bodies, body_names(world.bodies), strict=True):
        pose = pose_matrix(b.position, b.orientation)
        against_plane(b.shape.kind, b.shape.packed_size, b.shape.packed_vertices, pose,
                      world.plane.packed_size, np.eye(4), out)
        if out[0] < -INSIDE_GROUND:
            raise ValueError(f"Body {name!r} starts {-out[0]:.4g} m inside the ground (more "
                             f"than {INSIDE_GROUND:g} m); raise its position")


def empty_model(name: str = "world"):
    """A model without joints (the world alone, a fixed root link): a robot for scenes of
    free bodies only, ``World(bodies=[...])`` with ``q0`` and ``v0`` empty."""
    from ..multibody.model import build_model

    return build_model(name, [], [], [], np.zeros((0, 4, 4)), np.zeros((0, 3)), np.zeros(0),
                       np.zeros((0, 3)), np.zeros((0, 3, 3)), root_link=name)
