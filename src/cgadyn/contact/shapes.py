"""Collision shapes, each a CGA object in its own frame (docs/contact.md).

A sphere is the dual vector ``S = C - ½ r² e∞`` of its centre ``C`` (K2), a capsule the
segment of its axis swept by such a sphere (K4), a plane the dual vector ``π = n + δ e∞``
bounding the half-space ``X · π <= 0`` (K1); boxes, cylinders, ellipsoids and convex meshes
are given by their support points (K6). Every shape is centred on its frame's origin, with
its axis (a capsule's, a cylinder's) along the frame's z; a shape made for a link
(``CollisionModel.with_shapes``) may carry a ``placement`` of that frame in the link's
(``placement=``, a sphere's ``center=``, a capsule between two points ``a`` and ``b``).

Compiled code sees a shape as three things: its ``kind`` (an integer, the constants below),
``size`` (four floats) and ``vertices`` ((V, 3), empty but for a convex mesh).
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["BOX", "CAPSULE", "CYLINDER", "ELLIPSOID", "KIND_NAMES", "MAX_VERTICES", "MESH",
           "PLANE", "SPHERE", "Box", "Capsule", "ConvexMesh", "Cylinder", "Ellipsoid",
           "MeshSimplified", "Plane", "Shape", "Sphere"]

SPHERE, CAPSULE, BOX, CYLINDER, PLANE, MESH, ELLIPSOID = range(7)
KIND_NAMES = ("sphere", "capsule", "box", "cylinder", "plane", "convex mesh", "ellipsoid")

MAX_VERTICES = 64
"""A convex mesh keeps at most this many vertices of its hull (its support point is a loop
over them)."""


class MeshSimplified(UserWarning):
    """A convex hull had more than ``MAX_VERTICES`` vertices and was simplified."""


def _positive(value, what: str, shape: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{shape}: the {what} must be a number, got {value!r}") from None
    if not (np.isfinite(x) and x > 0.0):
        raise ValueError(f"{shape}: the {what} must be finite and > 0, got {value!r}")
    return x


class Shape:
    """A convex collision shape in its own frame (see the module's docstring), placed by
    ``placement`` (4x4, rigid; default the identity) in the frame of what carries it."""

    kind: int = -1

    def __init__(self, size=(0.0, 0.0, 0.0, 0.0), vertices=None, placement=None):
        size = np.zeros(4) if size is None else np.asarray(size, dtype=float)
        # the arrays compiled code reads (writable, so that every shape has one numba type)
        self.packed_size = np.concatenate([size, np.zeros(4 - size.size)])
        self.packed_vertices = np.zeros((0, 3)) if vertices is None else \
            np.array(vertices, dtype=float, order="C")
        self.placement = _placement(placement, type(self).__name__)
        self.placement.flags.writeable = False

    @property
    def placed(self) -> bool:
        """Whether its placement is not the identity."""
        return not np.array_equal(self.placement, np.eye(4))

    def at(self, placement) -> Shape:
        """A copy of the shape with ``placement`` (4x4) in place of its own."""
        out = object.__new__(type(self))
        out.__dict__.update(self.__dict__)
        out.placement = _placement(placement, type(self).__name__)
        out.placement.flags.writeable = False
        return out

    @property
    def size(self) -> np.ndarray:
        """The four floats compiled code reads (see each shape)."""
        out = self.packed_size.view()
        out.flags.writeable = False
        return out

    @property
    def vertices(self) -> np.ndarray:
        """A convex mesh's hull vertices (V, 3); (0, 3) for the other shapes."""
        out = self.packed_vertices.view()
        out.flags.writeable = False
        return out

    @property
    def name(self) -> str:
        return KIND_NAMES[self.kind]

    @property
    def radius(self) -> float:
        """The radius a sphere or capsule adds around its core (a point, a segment); 0 for
        shapes that are their own core."""
        return float(self.size[0]) if self.kind in (SPHERE, CAPSULE) else 0.0

    def __eq__(self, other):
        return (type(other) is type(self) and np.array_equal(self.size, other.size)
                and np.array_equal(self.vertices, other.vertices)
                and np.array_equal(self.placement, other.placement))

    def __hash__(self):
        return hash((self.kind, self.size.tobytes(), self.vertices.tobytes(),
                     self.placement.tobytes()))


def _placement(placement, shape: str) -> np.ndarray:
    """``placement`` (None: the identity) as a rigid 4x4 matrix, checked."""
    if placement is None:
        return np.eye(4)
    try:
        T = np.array(placement, dtype=float)
    except (TypeError, ValueError):
        T = np.full(1, np.nan)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)) or \
            not np.allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-9) or \
            np.linalg.det(T[:3, :3]) < 0 or not np.allclose(T[3], [0, 0, 0, 1]):
        raise ValueError(f"{shape}: placement must be a rigid 4x4 homogeneous matrix "
                         f"(a rotation and a translation), got {placement!r}")
    return T


def three_numbers(x, what: str, shape: str) -> np.ndarray:
    """``x`` as three finite floats; ``ValueError`` naming ``shape``'s ``what`` else."""
    try:
        p = np.asarray(x, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        p = np.full(1, np.nan)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise ValueError(f"{shape}: {what} must be three finite numbers, got {x!r}")
    return p


class Sphere(Shape):
    """A ball of ``radius`` about the origin: the dual sphere ``S = e0 - ½ r² e∞`` (K2)."""

    kind = SPHERE

    def __init__(self, radius: float, center=None, placement=None):
        """``center``: where its centre lies in the carrier's frame (a placement's
        translation; not with ``placement``)."""
        if center is not None:
            if placement is not None:
                raise ValueError("Sphere: give center or placement, not both")
            placement = np.eye(4)
            placement[:3, 3] = three_numbers(center, "center", "Sphere")
        super().__init__([_positive(radius, "radius", "Sphere")], placement=placement)

    def __repr__(self):
        return f"Sphere(radius={self.size[0]:g})"


class Capsule(Shape):
    """The segment from ``-length/2`` to ``length/2`` on the z axis swept by a ball of
    ``radius`` (K4). ``length`` is the segment's, the caps not counted (URDF's and coal's
    ``Capsule(radius, length)``; MuJoCo's ``size`` is ``(radius, length/2)``)."""

    kind = CAPSULE

    def __init__(self, radius: float, length, b=None, placement=None):
        """``Capsule(radius, length)``, or ``Capsule(radius, a, b)``: the segment from the
        point ``a`` to the point ``b`` of the carrier's frame (its placement then puts the
        segment's middle at ``(a + b) / 2`` and its z along ``b - a``)."""
        if b is not None:
            if placement is not None:
                raise ValueError("Capsule: give the points a and b or a placement, not both")
            a, b = three_numbers(length, "a", "Capsule"), three_numbers(b, "b", "Capsule")
            axis = b - a
            length = float(np.linalg.norm(axis))
            if not length > 0.0:
                raise ValueError(f"Capsule: the points a and b must differ, got {a} twice")
            placement = frame_along(axis / length, 0.5 * (a + b))
        super().__init__([_positive(radius, "radius", "Capsule"),
                          0.5 * _positive(length, "length", "Capsule")], placement=placement)

    @property
    def length(self) -> float:
        return 2.0 * float(self.size[1])

    def __repr__(self):
        return f"Capsule(radius={self.size[0]:g}, length={self.length:g})"


class Box(Shape):
    """The box ``|x_i| <= h_i`` of ``half_extents`` ``h`` (MuJoCo's ``size``; URDF's and
    coal's box take the full sides ``2 h``)."""

    kind = BOX

    def __init__(self, half_extents, placement=None):
        h = np.asarray(half_extents, dtype=float).reshape(-1)
        if h.shape != (3,):
            raise ValueError(f"Box: half_extents must be three numbers, got {half_extents!r}")
        super().__init__([_positive(x, "half extent", "Box") for x in h], placement=placement)

    @property
    def half_extents(self) -> np.ndarray:
        return self.size[:3].copy()

    def __repr__(self):
        return f"Box(half_extents={self.size[:3].tolist()})"


class Cylinder(Shape):
    """The solid cylinder of ``radius`` about the z axis, from ``-length/2`` to
    ``length/2`` (URDF's and coal's ``Cylinder(radius, length)``; MuJoCo's ``size`` is
    ``(radius, length/2)``)."""

    kind = CYLINDER

    def __init__(self, radius: float, length: float, placement=None):
        super().__init__([_positive(radius, "radius", "Cylinder"),
                          0.5 * _positive(length, "length", "Cylinder")], placement=placement)

    @property
    def length(self) -> float:
        return 2.0 * float(self.size[1])

    def __repr__(self):
        return f"Cylinder(radius={self.size[0]:g}, length={self.length:g})"


class Ellipsoid(Shape):
    """The solid ellipsoid ``Σ (x_i / r_i)² <= 1`` of semi-axes ``radii`` along its frame's
    axes (MuJoCo's ellipsoid ``size``, coal's ``Ellipsoid(radii)``): the unit ball stretched
    by ``A = diag(r)``, so its support point along a direction l of its frame is
    ``A² l / |A l|`` (K6a)."""

    kind = ELLIPSOID

    def __init__(self, radii, placement=None):
        r = np.asarray(radii, dtype=float).reshape(-1)
        if r.shape != (3,):
            raise ValueError(f"Ellipsoid: radii must be three numbers, got {radii!r}")
        super().__init__([_positive(x, "radius", "Ellipsoid") for x in r], placement=placement)

    @property
    def radii(self) -> np.ndarray:
        return self.size[:3].copy()

    def __repr__(self):
        return f"Ellipsoid(radii={self.size[:3].tolist()})"


class Plane(Shape):
    """The half-space ``n · x <= offset`` (coal's ``Halfspace(n, offset)``): the dual plane
    ``π = n + δ e∞`` with ``|n| = 1`` and ``δ = offset``, whose inner product with a point,
    ``X · π = n · x - δ``, is the point's signed distance (K1). ``normal`` is normalised;
    MuJoCo's plane geom is ``Plane((0, 0, 1), 0)`` in the geom's frame."""

    kind = PLANE

    def __init__(self, normal=(0.0, 0.0, 1.0), offset: float = 0.0):
        n = np.asarray(normal, dtype=float).reshape(-1)
        if n.shape != (3,) or not np.all(np.isfinite(n)):
            raise ValueError(f"Plane: the normal must be three finite numbers, got {normal!r}")
        norm = float(np.linalg.norm(n))
        if norm < 1e-12:
            raise ValueError("Plane: the normal must not be zero")
        if not np.isfinite(float(offset)):
            raise ValueError(f"Plane: the offset must be finite, got {offset!r}")
        super().__init__([*(n / norm), float(offset)])

    @property
    def normal(self) -> np.ndarray:
        return self.size[:3].copy()

    @property
    def offset(self) -> float:
        return float(self.size[3])

    def __repr__(self):
        return f"Plane(normal={self.size[:3].tolist()}, offset={self.size[3]:g})"


class ConvexMesh(Shape):
    """The convex hull of ``vertices`` ((V, 3), at least four not in one plane), by
    trimesh. A hull of more than ``max_vertices`` vertices is simplified to the
    farthest-point subset of its vertices, then their hull) and says so
    with a ``MeshSimplified`` warning: the shape is then slightly smaller than the mesh."""

    kind = MESH

    def __init__(self, vertices, max_vertices: int = MAX_VERTICES, name: str = "mesh",
                 placement=None):
        v = np.asarray(vertices, dtype=float)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 4:
            raise ValueError(f"ConvexMesh: vertices must be an array (V >= 4, 3), got shape "
                             f"{v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError("ConvexMesh: vertices contain NaN or inf")
        if max_vertices < 4:
            raise ValueError(f"ConvexMesh: max_vertices must be >= 4, got {max_vertices}")
        hull = _hull(v, name)
        if len(hull) > max_vertices:
            kept = _farthest_points(hull, max_vertices)
            warnings.warn(f"{name}: its convex hull has {len(hull)} vertices; simplified to "
                          f"{len(kept)} (ConvexMesh's max_vertices = {max_vertices})",
                          MeshSimplified, stacklevel=2)
            hull = _hull(kept, name)
        super().__init__(None, hull, placement=placement)

    @classmethod
    def from_file(cls, path, scale=(1.0, 1.0, 1.0), max_vertices: int = MAX_VERTICES):
        """The hull of a mesh file (STL, OBJ, DAE, ... what trimesh reads), each axis scaled."""
        import trimesh

        mesh = trimesh.load(str(path), force="mesh", process=False)
        scale = np.broadcast_to(np.asarray(scale, dtype=float), (3,))
        return cls(np.asarray(mesh.vertices, dtype=float) * scale, max_vertices,
                   name=f"mesh {str(path)!r}")

    def __repr__(self):
        return f"ConvexMesh({len(self.vertices)} vertices)"


def frame_along(z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """A frame at ``origin`` whose z axis is the unit vector ``z``."""
    x = np.cross(z, [1.0, 0.0, 0.0] if abs(z[0]) < 0.9 else [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = origin
    return T


def _hull(v: np.ndarray, name: str) -> np.ndarray:
    """The vertices of the convex hull of the points ``v`` (trimesh, i.e. qhull)."""
    import trimesh

    with np.errstate(all="ignore"):  # trimesh divides by a flat hull's zero volume
        try:
            hull = trimesh.convex.convex_hull(v)
        except Exception as exc:  # qhull: flat or degenerate input
            raise ValueError(f"ConvexMesh ({name}): no convex hull of {len(v)} points: the "
                             f"points may lie in one plane ({type(exc).__name__})") from None
        volume = hull.volume
    if not volume > 0.0:
        raise ValueError(f"ConvexMesh ({name}): the convex hull has no volume (the "
                         f"points lie in one plane)")
    return np.asarray(hull.vertices, dtype=float)


def _farthest_points(v: np.ndarray, k: int) -> np.ndarray:
    """``k`` of the points ``v``, each the farthest from those chosen before (starting from
    the one farthest from the centroid): a deterministic spread over the hull."""
    chosen = [int(np.argmax(np.sum((v - v.mean(axis=0)) ** 2, axis=1)))]
    d = np.sum((v - v[chosen[0]]) ** 2, axis=1)
    while len(chosen) < k:
        i = int(np.argmax(d))
        chosen.append(i)
        d = np.minimum(d, np.sum((v - v[i]) ** 2, axis=1))
    return v[np.sort(chosen)]
