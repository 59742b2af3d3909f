"""The collision shapes of a robot: each a shape on a link, placed in the link's frame.

``collision_model(model, source)`` reads them from what the model was loaded from: a URDF's
``<collision>`` elements (sphere, box, cylinder, mesh: a mesh by its convex hull, the file
found as the viewer finds it, ``multibody.meshes``) or an MJCF's geoms, as MuJoCo's compiler
resolved them (sphere, capsule, box, cylinder, plane, mesh; ``contype`` and
``conaffinity`` kept on each). The ``Model`` stays as it was: its links are named once, in
``model.link_names``, and a collision refers to one by index.

``collision_poses(model, collisions, q)`` places every shape in the world at ``q``: the
link frames of ``cgadyn.link_placements`` composed with each shape's placement.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..algorithms._inputs import nonnegative
from . import distance as D
from .api import check_rigid, explain
from .shapes import (
    PLANE,
    Box,
    Capsule,
    ConvexMesh,
    Cylinder,
    Ellipsoid,
    MeshSimplified,
    Plane,
    Shape,
    Sphere,
)

__all__ = ["Collision", "CollisionModel", "collision_distances", "collision_model",
           "collision_poses"]


@dataclass(frozen=True)
class Collision:
    """One collision shape: ``shape`` on link ``link`` (an index of ``model.link_names``;
    ``-1`` for the world, where a link of the model is not one), at ``placement`` (4x4)
    in that link's frame. ``contype`` and ``conaffinity`` are MuJoCo's bit masks (two
    shapes may touch where ``contype_a & conaffinity_b or contype_b & conaffinity_a``);
    URDF shapes take MuJoCo's default, 1 and 1. ``friction``: the Coulomb coefficient of
    the shape's surface (a free ``Body``'s); None: the ``World``'s (K38). ``stiffness``
    (N/m) and ``damping`` (N s/m): each of the shape's contact points with the ground a
    spring and damper along the normal (K41, ``CollisionModel.compliant``); both zero: a
    rigid contact."""

    name: str
    shape: Shape
    link: int
    placement: np.ndarray = field(repr=False)
    contype: int = 1
    conaffinity: int = 1
    friction: float | None = None
    stiffness: float = 0.0
    damping: float = 0.0

    @property
    def pose(self) -> np.ndarray:
        """The shape's frame in its link's: ``placement`` composed with the shape's own
        placement (``Shape.placement``, the identity for shapes read from files)."""
        return np.asarray(self.placement, dtype=float) @ self.shape.placement


class CollisionModel(tuple):
    """The collisions of a model (``model``, whose links they name), a tuple of
    :class:`Collision` with the arrays compiled code reads: ``kinds`` (K,), ``sizes``
    (K, 4), ``vertices`` (every mesh's hull, stacked) and ``offsets`` (K + 1,), ``links``
    (K,), ``placements`` (K, 4, 4, each ``Collision.pose``); ``bodies`` (K,), the joint
    moving each shape;
    ``compliance`` (K, 2), each shape's normal stiffness and damping (K41)."""

    def __new__(cls, collisions=(), model=None):
        self = super().__new__(cls, collisions)
        self.model = model
        self.link_names = () if model is None else tuple(model.link_names)
        # the joint moving each shape's link (-1: the world), and each joint's parent
        self.bodies = np.array([-1 if model is None or c.link < 0 else
                                int(model.link_joint[c.link]) for c in self], dtype=np.int64)
        self.parents = np.array([] if model is None else model.parents, dtype=np.int64)
        for c in self:
            if not isinstance(c, Collision):
                raise TypeError(f"a CollisionModel holds Collision records, not "
                                f"{type(c).__name__}")
        self.kinds = np.array([c.shape.kind for c in self], dtype=np.int64)
        self.sizes = np.array([c.shape.packed_size for c in self]).reshape(len(self), 4)
        verts = [c.shape.packed_vertices for c in self]
        self.offsets = np.concatenate([[0], np.cumsum([len(v) for v in verts])]).astype(
            np.int64)
        self.vertices = np.ascontiguousarray(np.concatenate([np.zeros((0, 3)), *verts]))
        self.links = np.array([c.link for c in self], dtype=np.int64)
        self.placements = np.array([c.pose for c in self]).reshape(len(self), 4, 4)
        self.compliance = np.array([[c.stiffness, c.damping] for c in self],
                                   dtype=float).reshape(len(self), 2)
        return self

    def compliant(self, stiffness: float, damping: float = 0.0, links=None
                  ) -> CollisionModel:
        """A copy whose shapes on ``links`` (names or indices; None: every shape) touch the
        ground through a spring of ``stiffness`` (N/m) and a damper of ``damping`` (N s/m)
        at each contact point, along its normal (K41): a soft sole, which sinks by its
        load over its stiffness and settles on its outermost points, where a rigid one
        rocks on the highest bumps of its mesh. ``stiffness = damping = 0``: rigid again."""
        k = nonnegative(stiffness, "compliant: stiffness")
        c = nonnegative(damping, "compliant: damping")
        chosen = None
        if links is not None:
            names = [links] if isinstance(links, (str, int, np.integer)) else list(links)
            chosen = set()
            for li in names:
                if isinstance(li, str):
                    if li not in self.link_names:
                        raise ValueError(f"compliant: no link {li!r} in the model (links: "
                                         f"{', '.join(self.link_names[:8])} ...)")
                    li = self.link_names.index(li)
                chosen.add(int(li))
            missing = chosen - {int(x.link) for x in self}
            if missing:
                raise ValueError(f"compliant: link(s) {sorted(missing)} carry no collision "
                                 f"shape")
        return CollisionModel([replace(x, stiffness=k, damping=c)
                               if chosen is None or x.link in chosen else x for x in self],
                              self.model)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self)

    @property
    def shapes(self) -> dict[str, tuple[Shape, ...]]:
        """Each link's shapes (link name → shapes, the world's under ``"world"`` where the
        model has no link of that name), each placed in its link's frame
        (``Shape.placement``: ``Collision.pose``)."""
        out: dict[str, list] = {}
        for c in self:
            name = self.link_names[c.link] if c.link >= 0 else "world"
            out.setdefault(name, []).append(c.shape.at(c.pose))
        return {name: tuple(shapes) for name, shapes in out.items()}

    def with_shapes(self, shapes: dict, replace: bool = True) -> CollisionModel:
        """A copy with hand-made ``shapes`` on links (``{link name or index: [shapes]}``,
        each placed in its link's frame by its own ``placement``: ``Sphere(r,
        center=...)``, ``Capsule(r, a, b)``, ``Box(h, placement=...)``): with ``replace``,
        the shapes the links had (their meshes' hulls, say) are dropped; else the new ones
        are added to them. Each new shape is named ``<link>:<i>`` and touches what MuJoCo's
        default filter lets it (``contype = conaffinity = 1``); a plane is refused (the
        ground is the World's). Raises ``ValueError`` naming an unknown link or a bad
        shape."""
        if not isinstance(shapes, dict):
            raise ValueError(f"with_shapes: shapes must be a dict {{link: [shapes]}}, got "
                             f"{shapes!r}")
        if self.model is None:
            raise ValueError("with_shapes: this collision model has no robot model; make it "
                             "with cgadyn.collision_model(model, ...)")
        added, links = [], set()
        for key, given in shapes.items():
            if isinstance(key, str):
                if key not in self.link_names:
                    raise ValueError(f"with_shapes: no link {key!r} in {self.model.name!r} "
                                     f"(links: {', '.join(self.link_names[:8])} ...)")
                li = self.link_names.index(key)
            elif isinstance(key, (int, np.integer)) and 0 <= key < len(self.link_names):
                li = int(key)
            else:
                raise ValueError(f"with_shapes: {key!r} is not a link of "
                                 f"{self.model.name!r} (a name or an index)")
            given = [given] if isinstance(given, Shape) else list(given)
            for i, shape in enumerate(given):
                if not isinstance(shape, Shape) or shape.kind == PLANE:
                    raise ValueError(f"with_shapes: the shapes of link "
                                     f"{self.link_names[li]!r} must be cgadyn shapes other "
                                     f"than a plane (the ground is the World's), got {shape!r}")
                added.append(Collision(f"{self.link_names[li]}:{i}", shape, li, np.eye(4)))
            links.add(li)
        kept = [c for c in self if not (replace and c.link in links)]
        return CollisionModel([*kept, *added], self.model)

    def on(self, link: str | int) -> CollisionModel:
        """The collisions of one link (by name or index)."""
        li = self.link_names.index(link) if isinstance(link, str) else int(link)
        return CollisionModel([c for c in self if c.link == li], self.model)

    def adjacent(self, i: int, j: int) -> bool:
        """Whether shapes ``i`` and ``j`` move with the same body or with a parent and its
        child (MuJoCo leaves such pairs out of its contacts; a world body is adjacent to
        nothing, as in MuJoCo)."""
        a, b = int(self.bodies[i]), int(self.bodies[j])
        if a == b:
            return True
        return (a >= 0 and b >= 0 and (self.parents[a] == b or self.parents[b] == a))

    def can_touch(self, i: int, j: int) -> bool:
        """MuJoCo's filter: ``contype_i & conaffinity_j or contype_j & conaffinity_i``."""
        a, b = self[i], self[j]
        return bool(a.contype & b.conaffinity or b.contype & a.conaffinity)

    def __repr__(self):
        return f"CollisionModel({len(self)} shapes: {', '.join(self.names[:6])}" \
               f"{' ...' if len(self) > 6 else ''})"


def collision_model(model, source=None, max_vertices: int = 64) -> CollisionModel:
    """The collision shapes of ``model``, read from ``source`` (the URDF or MJCF it was
    loaded from: a path, text, a registered name or a ``mujoco.MjModel``; by default the
    registry's file for ``model.name``). Meshes become their convex hulls of at most
    ``max_vertices`` vertices (one ``MeshSimplified`` warning names those simplified).
    Raises ``ValueError`` naming a geometry it cannot read, ``FileNotFoundError`` a missing
    mesh file."""
    try:
        import mujoco
        if isinstance(source, mujoco.MjModel):
            return _from_mujoco(model, source, max_vertices)
    except ImportError:  # pragma: no cover - mujoco is optional
        pass
    from ..multibody.meshes import model_source

    kind, value, path = model_source(model, source)
    if kind == "mjcf":
        from ..multibody.mujoco_model import mujoco_model

        return _from_mujoco(model, mujoco_model(value), max_vertices)
    return _from_urdf(model, value, path, max_vertices)


def _link(model, name: str) -> int:
    return model.link_names.index(name) if name in model.link_names else -1


def _meshes(max_vertices: int):
    """A cache of hulls by file and scale, and the names of those simplified."""
    simplified: list[str] = []
    cache: dict = {}

    def hull(key, make):
        if key not in cache:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", MeshSimplified)
                cache[key] = make()
            if caught:
                simplified.append(getattr(key[0], "name", str(key[0])))
        return cache[key]

    return hull, simplified


def _warn_simplified(simplified: list[str], max_vertices: int) -> None:
    if simplified:
        warnings.warn(f"{len(simplified)} collision meshes have convex hulls of more than "
                      f"{max_vertices} vertices and were simplified to {max_vertices}: "
                      f"{', '.join(simplified[:4])}{' ...' if len(simplified) > 4 else ''}",
                      MeshSimplified, stacklevel=4)


def _from_urdf(model, xml: bytes, path, max_vertices: int) -> CollisionModel:
    from ..multibody.meshes import resolve_mesh
    from ..multibody.urdf import _parse

    robot = _parse(xml, repr(str(path)) if path else "the URDF text")
    hull, simplified = _meshes(max_vertices)
    out = []
    for link in robot.links:
        li = _link(model, link.name)
        if li < 0:
            continue
        for k, col in enumerate(link.collisions):
            name = col.name or f"{link.name}_{k}"
            origin = np.eye(4) if col.origin is None else np.asarray(col.origin, float)
            geo = col.geometry
            where = f"collision {name!r} of link {link.name!r}"
            try:
                if geo.sphere is not None:
                    shape = Sphere(geo.sphere.radius)
                elif geo.box is not None:
                    shape = Box(0.5 * np.asarray(geo.box.size, float))
                elif geo.cylinder is not None:
                    shape = Cylinder(geo.cylinder.radius, geo.cylinder.length)
                elif geo.mesh is not None:
                    file = resolve_mesh(geo.mesh.filename, path)
                    scale = (1.0, 1.0, 1.0) if geo.mesh.scale is None else tuple(
                        np.broadcast_to(np.asarray(geo.mesh.scale, float), (3,)))
                    shape = hull((file, scale), lambda f=file, s=scale: ConvexMesh.from_file(
                        f, s, max_vertices))
                else:
                    raise ValueError("no geometry (sphere, box, cylinder, mesh)")
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
            out.append(Collision(name, shape, li, origin))
    _warn_simplified(simplified, max_vertices)
    return CollisionModel(out, model)


_MJ_GEOMS = {0: "plane", 2: "sphere", 3: "capsule", 4: "ellipsoid", 5: "cylinder", 6: "box",
             7: "mesh"}
"""MuJoCo's ``mjtGeom`` codes that are shapes here (1 hfield and 8 sdf are not)."""
_MJ_NAMES = {1: "hfield", 8: "sdf"}


def _from_mujoco(model, mj, max_vertices: int) -> CollisionModel:
    """The geoms of a compiled MuJoCo model: each on the link of its body (the body's name
    in ``model.link_names``), at ``geom_pos``/``geom_quat`` in the body frame, which is the
    link frame (``multibody.mujoco_model``). The geoms of the world body and of the bodies
    welded to it (MuJoCo's ``body_weldid`` 0: no joint between them and the world, as
    dm_control's manipulator's cups) are the world's, as MuJoCo counts them: shapes of no
    link, at their place in the world. A geom of a type cgadyn has no shape for is
    refused by name on a moving body, and left out with a warning on the world (a terrain's
    height field: a ``World`` given to ``simulate`` replaces the static geoms anyway). The
    world's geoms are the model's own static world (``contact.static_world``, K44), each
    with its friction; a model whose MJCF turns contacts off (``<flag contact="disable">``
    or ``constraint="disable"``, as dm_control's cartpole, whose cart slides inside its
    rails) has none: they are left out, with a warning, and a ``World`` says what the
    robot touches."""
    import mujoco

    from ..multibody.mujoco_model import _pose, _rotation

    hull, simplified = _meshes(max_vertices)
    out, left_out = [], []
    off = int(mj.opt.disableflags) & int(mujoco.mjtDisableBit.mjDSBL_CONTACT
                                         | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    dropped = []
    data = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, data)  # a static body's pose, which no qpos changes
    for g in range(mj.ngeom):
        gtype = int(mj.geom_type[g])
        name = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_GEOM, g) or f"geom{g}"
        body = int(mj.geom_bodyid[g])
        bname = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_BODY, body) or f"body{body}"
        where = f"geom {name!r} of body {bname!r}"
        static = int(mj.body_weldid[body]) == 0  # the world body, or one welded to it
        if off and static:  # no static world where MuJoCo computes no contact
            dropped.append(repr(name))
            continue
        if gtype not in _MJ_GEOMS and static:  # the world's: warned of, below
            left_out.append(f"{name!r} ({_MJ_NAMES.get(gtype, gtype)})")
            continue
        if gtype not in _MJ_GEOMS:
            raise ValueError(f"{where}: geom type {_MJ_NAMES.get(gtype, gtype)!r} is not a "
                             f"collision shape of cgadyn; expected one of "
                             f"{sorted(_MJ_GEOMS.values())}")
        size = np.asarray(mj.geom_size[g], float)
        kind = _MJ_GEOMS[gtype]
        try:
            if kind == "plane":
                shape = Plane((0.0, 0.0, 1.0), 0.0)
            elif kind == "sphere":
                shape = Sphere(size[0])
            elif kind == "capsule":
                shape = Capsule(size[0], 2.0 * size[1])
            elif kind == "ellipsoid":
                shape = Ellipsoid(size[:3])
            elif kind == "cylinder":
                shape = Cylinder(size[0], 2.0 * size[1])
            elif kind == "box":
                shape = Box(size[:3])
            else:
                m = int(mj.geom_dataid[g])
                start, count = int(mj.mesh_vertadr[m]), int(mj.mesh_vertnum[m])
                verts = np.array(mj.mesh_vert[start:start + count], float)
                shape = hull((f"mesh {m}", name), lambda v=verts: ConvexMesh(v, max_vertices))
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        li = -1 if static else _link(model, bname)  # the world's: -1
        placement = _pose(mj.geom_pos[g], _rotation(mj.geom_quat[g]))
        if static:  # at its place in the world
            placement = _pose(data.xpos[body], data.xmat[body].reshape(3, 3)) @ placement
        elif li < 0:
            raise ValueError(f"{where}: its body is not a link of {model.name!r}")
        out.append(Collision(name, shape, li, placement, int(mj.geom_contype[g]),
                             int(mj.geom_conaffinity[g]),
                             # the world's friction: its floor's, an obstacle's own (K44)
                             float(mj.geom_friction[g, 0]) if li < 0 else None))
    if left_out:
        warnings.warn(f"{model.name!r}: the world's geoms {', '.join(left_out)} are not "
                      f"collision shapes of cgadyn (expected one of "
                      f"{sorted(_MJ_GEOMS.values())}) and are left out of its static world",
                      stacklevel=3)
    if dropped:
        warnings.warn(f"{model.name!r}: its MJCF turns contacts off, so its world's geoms "
                      f"{', '.join(dropped)} are left out of its collision shapes (it has no "
                      f"static world); pass a cgadyn.World for what it should touch",
                      stacklevel=3)
    _warn_simplified(simplified, max_vertices)
    return CollisionModel(out, model)


def _collisions(collisions, model=None) -> CollisionModel:
    if isinstance(collisions, CollisionModel):
        return collisions
    return CollisionModel(list(collisions), model)


def collision_poses(model, collisions, q) -> np.ndarray:
    """World 4x4 poses of every shape at ``q`` (..., K, 4, 4): ``link_placements(model,
    q)`` of each shape's link (the identity for the world) times its placement (K10)."""
    from ..algorithms.api import link_placements

    cm = _collisions(collisions, model)
    if np.any(cm.links >= model.nlinks):
        raise ValueError("collisions refer to links the model does not have; read them "
                         "with collision_model(model, ...)")
    links = link_placements(model, q)
    frames = np.concatenate([links, np.broadcast_to(np.eye(4), links.shape[:-3] + (1, 4, 4))],
                            axis=-3)
    return frames[..., cm.links, :, :] @ cm.placements  # link -1: the identity appended


def collision_distances(collisions, poses, pairs=None, overlap: str = "raise"):
    """The signed distances of ``pairs`` ((P, 2) indices; by default every pair that
    MuJoCo would test: allowed by contype/conaffinity, not on one body nor on a parent and
    its child (``CollisionModel.adjacent``), not two planes) at ``poses`` (K, 4, 4) from
    :func:`collision_poses`: ``(pairs, distance (P,), point_a (P, 3), point_b (P, 3),
    normal (P, 3))`` in one compiled call. Overlapping shapes whose penetration depth is
    not computed (a few overlaps in a hundred of a cylinder with a box or a mesh, K9a) raise
    ``ValueError`` naming them, or with
    ``overlap="nan"`` get NaN (distance, points and normal); two planes always raise."""
    if overlap not in ("raise", "nan"):
        raise ValueError(f"overlap must be 'raise' or 'nan', got {overlap!r}")
    cm = _collisions(collisions)
    poses = np.ascontiguousarray(np.asarray(poses, dtype=float))
    if poses.shape != (len(cm), 4, 4):
        raise ValueError(f"poses: expected shape ({len(cm)}, 4, 4), got {poses.shape}")
    check_rigid(poses, "poses")
    if pairs is None:
        pairs = [(i, j) for i in range(len(cm)) for j in range(i + 1, len(cm))
                 if not cm.adjacent(i, j) and cm.can_touch(i, j)
                 and not (cm.kinds[i] == cm.kinds[j] == PLANE)]
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if pairs.size and (pairs.min() < 0 or pairs.max() >= len(cm)):
        raise ValueError(f"pairs: indices must lie in [0, {len(cm)})")
    out = np.empty((len(pairs), D.OUT))
    status = np.zeros(len(pairs), dtype=np.int64)
    D.distances(cm.kinds, cm.sizes, cm.vertices, cm.offsets, poses, pairs, np.empty(D.WORK),
                out, status)
    if overlap == "nan":
        out[status == D.PENETRATION_UNSUPPORTED] = np.nan
        status[status == D.PENETRATION_UNSUPPORTED] = D.OK
    bad = np.flatnonzero(status)
    if bad.size:
        k = int(bad[0])
        i, j = pairs[k]
        hint = " (overlap='nan' gives NaN for such pairs)" \
            if status[k] == D.PENETRATION_UNSUPPORTED else ""
        raise ValueError(f"collisions {cm[i].name!r} and {cm[j].name!r}: "
                         f"{explain(int(status[k]), cm[i].shape, cm[j].shape)}{hint}")
    return pairs, out[:, 0].copy(), out[:, 1:4].copy(), out[:, 4:7].copy(), out[:, 7:10].copy()
