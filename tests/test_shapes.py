"""Collision shapes and their signed distances (docs/contact.md, K1-K9): every pair against
coal at random poses, separated and penetrating; analytic cases; a URDF robot's collisions
placed as Pinocchio's GeometryModel places them; an MJCF model's geoms as MuJoCo places
them; bad input refused."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import cgadyn
from cgadyn.contact import shapes as S
from cgadyn.contact.distance import DEPTH_SLACK

coal = pytest.importorskip("coal")

ROOT = Path(__file__).resolve().parents[1]
RNG_SEED = 35


def _rotation(rng) -> np.ndarray:
    q = rng.normal(size=4)
    return _quaternion_matrix(*(q / np.linalg.norm(q)))


def _quaternion_matrix(w, x, y, z) -> np.ndarray:
    """The rotation of the unit quaternion ``w + x i + y j + z k``."""
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _pose(rng, spread: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = _rotation(rng)
    T[:3, 3] = rng.uniform(-spread, spread, 3)
    return T


def _coal(shape):
    if shape.kind == S.SPHERE:
        return coal.Sphere(shape.size[0])
    if shape.kind == S.CAPSULE:
        return coal.Capsule(shape.size[0], shape.length)
    if shape.kind == S.BOX:
        return coal.Box(*(2.0 * shape.half_extents))
    if shape.kind == S.CYLINDER:
        return coal.Cylinder(shape.size[0], shape.length)
    if shape.kind == S.PLANE:
        return coal.Halfspace(shape.normal, shape.offset)
    if shape.kind == S.ELLIPSOID:
        return coal.Ellipsoid(*shape.radii)
    points = coal.StdVec_Vec3s()
    for v in shape.vertices:
        points.append(v)
    return coal.Convex.convexHull(points, False, None)


def _coal_distance(a, Ta, b, Tb):
    req, res = coal.DistanceRequest(), coal.DistanceResult()
    req.gjk_tolerance = req.epa_tolerance = 1e-12
    req.gjk_max_iterations = req.epa_max_iterations = 1000
    d = coal.distance(_coal(a), coal.Transform3s(Ta[:3, :3], Ta[:3, 3]), _coal(b),
                      coal.Transform3s(Tb[:3, :3], Tb[:3, 3]), req, res)
    return d, res.getNearestPoint1(), res.getNearestPoint2(), np.asarray(res.normal)


SHAPES = {
    "sphere": S.Sphere(0.3),
    "capsule": S.Capsule(0.2, 0.6),
    "box": S.Box([0.2, 0.3, 0.4]),
    "cylinder": S.Cylinder(0.25, 0.5),
    "plane": S.Plane([0.0, 0.3, 1.0], 0.1),
    "mesh": S.ConvexMesh(np.random.default_rng(0).normal(size=(30, 3)) * 0.3),
    "ellipsoid": S.Ellipsoid([0.15, 0.3, 0.45]),
}
CLOSED = {("sphere", "sphere"), ("sphere", "capsule"), ("capsule", "capsule"),
          ("sphere", "box"), ("capsule", "box"), ("sphere", "cylinder")}
"""Pairs in closed form besides every pair with a plane (K5, K7, K8); the others go to
GJK, and EPA where they overlap (K9)."""
PAIRS = [(a, b) for a in SHAPES for b in SHAPES if (a, b) != ("plane", "plane")]


def _centre_in_cylinder(Ta, Tb, sphere_first: bool) -> bool:
    Ts, Tc = (Ta, Tb) if sphere_first else (Tb, Ta)
    x = Tc[:3, :3].T @ (Ts[:3, 3] - Tc[:3, 3])
    cyl = SHAPES["cylinder"]
    return bool(np.hypot(x[0], x[1]) < cyl.size[0] and abs(x[2]) < cyl.length / 2)


def _sphere_in_cylinder(sa, Ta, sb, Tb, sphere_first: bool):
    """A sphere whose centre lies inside a cylinder leaves it fastest through the nearer of
    the side and the cap. coal 3.0 only looks at the side (its normal is always radial), so
    where the cap is nearer its depth is not the least: this is the reference there."""
    (sph, Ts), (cyl, Tc) = ((sa, Ta), (sb, Tb)) if sphere_first else ((sb, Tb), (sa, Ta))
    x = Tc[:3, :3].T @ (Ts[:3, 3] - Tc[:3, 3])
    r, h, rho = cyl.size[0], cyl.size[1], np.hypot(x[0], x[1])
    if h - abs(x[2]) <= r - rho:
        depth, m, y = h - abs(x[2]), np.array([0, 0, -np.sign(x[2])]), [x[0], x[1],
                                                                      np.sign(x[2]) * h]
    else:
        u = np.array([x[0], x[1], 0.0]) / rho
        depth, m, y = r - rho, -u, r * u + [0, 0, x[2]]
    n = Tc[:3, :3] @ m
    p_sphere, p_cyl = Ts[:3, 3] + sph.radius * n, Tc[:3, :3] @ y + Tc[:3, 3]
    d = -depth - sph.radius
    return (d, p_sphere, p_cyl, n) if sphere_first else (d, p_cyl, p_sphere, -n)


def _support(shape, T: np.ndarray, N: np.ndarray) -> np.ndarray:
    """The support function ``h(n) = max_{x in shape} x · n`` of a shape at pose ``T``
    along the unit rows of ``N`` (k, 3), in closed form (independent of cgadyn's code)."""
    R, t = T[:3, :3], T[:3, 3]
    local = N @ R  # the directions in the shape's frame
    s = shape.size
    if shape.kind == S.SPHERE:
        h = s[0] * np.ones(len(N))
    elif shape.kind == S.CAPSULE:
        h = s[1] * np.abs(local[:, 2]) + s[0]
    elif shape.kind == S.BOX:
        h = np.abs(local) @ s[:3]
    elif shape.kind == S.CYLINDER:
        h = s[1] * np.abs(local[:, 2]) + s[0] * np.hypot(local[:, 0], local[:, 1])
    elif shape.kind == S.ELLIPSOID:
        h = np.linalg.norm(local * s[:3], axis=1)
    else:
        h = np.max(local @ shape.vertices.T, axis=1)
    return N @ t + h


def _support_depth(a, Ta, b, Tb) -> float:
    """The penetration depth of two convex shapes, ``min_n h_a(n) + h_b(-n)`` over unit
    ``n`` (negative: they are apart), by 20000 sampled directions and Nelder-Mead from the
    three best: the reference for overlaps of curved shapes, where coal's EPA may stop on a
    face of its polytope short of the surface."""
    from scipy.optimize import minimize

    N = np.random.default_rng(0).normal(size=(20000, 3))
    N /= np.linalg.norm(N, axis=1)[:, None]
    values = _support(a, Ta, N) + _support(b, Tb, -N)

    def f(x):
        n = (x / np.linalg.norm(x))[None]
        return float(_support(a, Ta, n)[0] + _support(b, Tb, -n)[0])

    return min(minimize(f, N[i], method="Nelder-Mead",
                        options={"xatol": 1e-12, "fatol": 1e-15, "maxiter": 5000}).fun
               for i in np.argsort(values)[:3])


@pytest.mark.parametrize("a,b", PAIRS, ids=[f"{a}-{b}" for a, b in PAIRS])
def test_distance_agrees_with_coal(a, b):
    """Distance, witness points and normal at random poses, near (many penetrate) and far:
    closed forms, GJK and EPA on polytopes to 1e-9; GJK with a cylinder's curved side, where
    both libraries iterate to a tolerance and GJK converges slowly (its support points jump
    around the rim): the distance to 1e-6, the points to 1e-4 (the distance is stationary
    along the surface: its error is about the square of theirs).
    The same for an ellipsoid's curved surface. Where a cylinder or an ellipsoid overlaps a
    shape other than a plane or a sphere, EPA then its refinement (K9a) give the depth
    within its certified bound of the least support function (``_support_depth``; 1e-7
    m, or 5 % of the depth where EPA stopped short; coal's EPA is not the
    reference there: it may stop on its polytope short of a curved surface), or refuse it
    (a few of 60 poses at most), never answer wrongly."""
    rng = np.random.default_rng(RNG_SEED + PAIRS.index((a, b)))
    sa, sb = SHAPES[a], SHAPES[b]
    closed = "plane" in (a, b) or (a, b) in CLOSED or (b, a) in CLOSED
    curved = ("cylinder" in (a, b) or "ellipsoid" in (a, b)) and not closed
    point_tol = 1e-4 if curved else 1e-9
    distance_tol = 1e-6 if curved else 1e-9
    compared = penetrating = refused = 0
    for k in range(60):
        Ta, Tb = _pose(rng, 1.0), _pose(rng, 0.3 if k % 2 else 1.0)
        try:
            d, pa, pb, n = cgadyn.shape_distance(sa, Ta, sb, Tb)
        except ValueError as exc:
            assert curved and "penetration depth is not computed" in str(exc)
            assert _support_depth(sa, Ta, sb, Tb) > 0.0  # they do overlap
            refused += 1
            continue
        np.testing.assert_allclose(pb - pa, d * n, atol=1e-12)
        assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-12)
        if curved and d < 0.0:  # EPA and its refinement: the depth, the witnesses' support
            reference = _support_depth(sa, Ta, sb, Tb)  # within the certified bound (K9a)
            assert abs(-d - reference) <= 1e-6 + DEPTH_SLACK * reference
            assert pa @ n == pytest.approx(_support(sa, Ta, n[None])[0], abs=1e-6)
            compared += 1
            penetrating += 1
            continue
        dc, pac, pbc, nc = _coal_distance(sa, Ta, sb, Tb)
        if {a, b} == {"sphere", "cylinder"} and _centre_in_cylinder(Ta, Tb, a == "sphere"):
            dc, pac, pbc, nc = _sphere_in_cylinder(sa, Ta, sb, Tb, a == "sphere")
        assert d == pytest.approx(dc, abs=distance_tol)
        np.testing.assert_allclose(pa, pac, atol=point_tol)
        np.testing.assert_allclose(pb, pbc, atol=point_tol)
        if abs(d) > 1e-3:
            np.testing.assert_allclose(n, nc, atol=point_tol / abs(d) + 1e-9)
        compared += 1
        penetrating += d < 0
    assert compared >= 20 and penetrating >= 2
    assert refused <= (3 if curved else 0)


def test_curved_overlaps_a_few_millimetres_deep():
    """The overlaps of contact: a cylinder or an ellipsoid pressed 10 µm to 10 mm into a
    box, a capsule, a cylinder or a convex mesh along the normal of their distance, as a
    step leaves them; the depth within its certified bound of ``_support_depth`` (1e-7 m,
    or 5 % of the depth where EPA stopped short) and to 1e-6 in 9 cases of 10 at least;
    refused in 5 of 40 poses at most (EPA's polytope and its refinement do not meet at a
    rim there)."""
    rng = np.random.default_rng(3)
    for a, b in [("cylinder", "box"), ("cylinder", "capsule"), ("cylinder", "cylinder"),
                 ("cylinder", "mesh"), ("ellipsoid", "box"), ("ellipsoid", "mesh")]:
        sa, sb = SHAPES[a], SHAPES[b]
        tried = refused = exact = 0
        while tried < 40:
            Ta, Tb = _pose(rng, 0.6), _pose(rng, 0.6)
            try:
                d, _, _, n = cgadyn.shape_distance(sa, Ta, sb, Tb)
            except ValueError:  # an overlap to begin with
                continue
            if d <= 0.0:
                continue
            depth = 10.0 ** rng.uniform(-5, -2)
            Tb[:3, 3] -= (d + depth) * n
            tried += 1
            try:
                d = cgadyn.shape_distance(sa, Ta, sb, Tb)[0]
            except ValueError:
                refused += 1
                continue
            reference = _support_depth(sa, Ta, sb, Tb)
            assert abs(-d - reference) <= 1e-6 + DEPTH_SLACK * reference, (a, b)
            exact += abs(-d - reference) <= 1e-6
        assert refused <= 5, (a, b, refused)
        assert exact >= 0.9 * (tried - refused), (a, b, exact)


def test_the_distances_are_inner_products():
    """K1: a point's distance to a plane is ``X · π``; K3: ``|x - y|² = -2 X · Y``; both
    against the dense reference algebra."""
    from cgadyn.cga.basis import NULL
    from cgadyn.cga.objects import Point
    from cgadyn.contact import distance as D

    rng = np.random.default_rng(1)
    for _ in range(5):
        x, y, n = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        n /= np.linalg.norm(n)
        delta = float(rng.normal())
        plane = NULL.multivector([*n, delta], ["e1", "e2", "e3", "e∞"])
        X, Y = Point(x).mv, Point(y).mv
        assert D.plane_distance(*x, *n, delta) == pytest.approx(
            float((X | plane).scalar_part()), abs=1e-12)
        assert D.plane_distance(*x, *n, delta) == pytest.approx(n @ x - delta, abs=1e-12)
        assert D.point_distance(*x, *y) ** 2 == pytest.approx(
            -2.0 * float((X | Y).scalar_part()), abs=1e-12)


def _at(t, R=None):
    T = np.eye(4)
    T[:3, 3] = t
    if R is not None:
        T[:3, :3] = R
    return T


def test_analytic_cases():
    ground = cgadyn.Plane((0, 0, 1), 0.0)
    d, pa, pb, n = cgadyn.shape_distance(cgadyn.Sphere(0.1), _at([1, 2, 0.5]), ground, None)
    assert d == pytest.approx(0.4, abs=1e-15)
    np.testing.assert_allclose(pa, [1, 2, 0.4], atol=1e-15)
    np.testing.assert_allclose(pb, [1, 2, 0.0], atol=1e-15)
    np.testing.assert_allclose(n, [0, 0, -1])
    # a capsule lying 1 cm deep in the ground, a box standing on a corner
    lying = _at([0, 0, 0.09], np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]]))
    d = cgadyn.shape_distance(cgadyn.Capsule(0.1, 1.0), lying, ground, None)[0]
    assert d == pytest.approx(-0.01, abs=1e-15)
    r1, r3 = np.array([1.0, -1.0, 0.0]) / np.sqrt(2), np.ones(3) / np.sqrt(3)
    tilt = np.array([r1, np.cross(r3, r1), r3])  # the diagonal (1, 1, 1) upright
    d = cgadyn.shape_distance(cgadyn.Box([1, 1, 1]), _at([0, 0, 2.0], tilt), ground, None)[0]
    assert d == pytest.approx(2.0 - np.sqrt(3.0), abs=1e-12)
    # a cylinder upright on the ground; two spheres 1 m apart; a sphere deep in a box
    d = cgadyn.shape_distance(ground, None, cgadyn.Cylinder(0.2, 1.0), _at([0, 0, 0.6]))[0]
    assert d == pytest.approx(0.1, abs=1e-15)
    d, pa, pb, n = cgadyn.shape_distance(cgadyn.Sphere(0.2), _at([0, 0, 0]), cgadyn.Sphere(0.3),
                                         _at([1, 0, 0]))
    assert (d, *pa, *pb, *n) == pytest.approx((0.5, 0.2, 0, 0, 0.7, 0, 0, 1, 0, 0))
    d, pa, pb, n = cgadyn.shape_distance(cgadyn.Sphere(0.1), _at([0.05, 0, 0]),
                                         cgadyn.Box([0.2, 0.5, 0.5]), None)
    assert d == pytest.approx(-0.25, abs=1e-15)
    np.testing.assert_allclose(n, [-1, 0, 0])
    # a sphere whose centre is inside a cylinder, nearer its cap than its side
    d, pa, pb, n = cgadyn.shape_distance(cgadyn.Sphere(0.1), _at([0.1, 0, 0.2]),
                                         cgadyn.Cylinder(0.25, 0.5), None)
    assert d == pytest.approx(-0.15, abs=1e-15)
    np.testing.assert_allclose(n, [0, 0, -1])
    np.testing.assert_allclose(pb, [0.1, 0, 0.25], atol=1e-15)
    # two boxes side by side (GJK), then one 0.25 into the other (EPA); a pose as a Motor
    from cgadyn.cga import Motor

    motor = Motor.from_matrix(_at([0.0, 3.0, 0.0]))
    d = cgadyn.shape_distance(cgadyn.Box([1, 1, 1]), None, cgadyn.Box([1, 1, 1]), motor)[0]
    assert d == pytest.approx(1.0, abs=1e-12)
    d, pa, pb, n = cgadyn.shape_distance(cgadyn.Box([1, 1, 1]), None, cgadyn.Box([1, 2, 3]),
                                         _at([0.0, 0.0, 3.75]))
    assert d == pytest.approx(-0.25, abs=1e-12)
    np.testing.assert_allclose(n, [0, 0, 1], atol=1e-12)


def test_boxes_stacked_to_rounding_touch_and_never_fail():
    """A box on a box, their faces overlapping by 1e-14 m with rotations of 1e-14 to 1e-6
    rad (what a stack resting under a solver's tolerance reaches): the distance is the
    overlap to 1e-13 m and what the tilts dip a corner, its normal nearly the faces', where
    EPA's nearest face once came out 1e-17 behind the origin and the pair was refused as if
    its depth could not be computed."""
    rng = np.random.default_rng(RNG_SEED)
    a, b = cgadyn.Box([0.1, 0.1, 0.1]), cgadyn.Box([0.05, 0.05, 0.05])
    for _ in range(300):
        tilt = 10.0 ** rng.uniform(-14, -6)
        poses = []
        for _ in range(2):
            x, y, z = rng.normal(size=3) * tilt
            poses.append(_quaternion_matrix(np.sqrt(1.0 - x * x - y * y - z * z), x, y, z))
        at = [rng.uniform(-0.04, 0.04), rng.uniform(-0.04, 0.04), 0.15 - 1e-14]
        d, _, _, n = cgadyn.shape_distance(a, _at([0, 0, 0], poses[0]), b, _at(at, poses[1]))
        assert abs(d + 1e-14) < 1e-13 + 2.0 * tilt  # a corner of a box tilted dips
        assert abs(n[2]) > 0.99  # an edge pair's normal, nearly parallel, may tilt a little


def test_bad_input_is_refused():
    for make, words in [
        (lambda: cgadyn.Sphere(-1.0), "radius must be finite and > 0"),
        (lambda: cgadyn.Sphere(float("nan")), "radius"),
        (lambda: cgadyn.Capsule(0.1, 0.0), "length must be finite and > 0"),
        (lambda: cgadyn.Box([1, 2]), "three numbers"),
        (lambda: cgadyn.Box([1, -2, 1]), "half extent"),
        (lambda: cgadyn.Cylinder("a", 1.0), "must be a number"),
        (lambda: cgadyn.Plane((0, 0, 0)), "must not be zero"),
        (lambda: cgadyn.ConvexMesh(np.eye(3)), "V >= 4"),
        (lambda: cgadyn.ConvexMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), "one plane"),
        (lambda: cgadyn.shape_distance(cgadyn.Plane(), None, cgadyn.Plane(), None),
         "two planes"),
        (lambda: cgadyn.shape_distance(cgadyn.Sphere(1), np.ones((4, 4)), cgadyn.Sphere(1),
                                       None), "not a rigid transform"),
    ]:
        with pytest.raises(ValueError, match=words):
            make()
    with pytest.raises(TypeError, match="cgadyn shape"):
        cgadyn.shape_distance("sphere", None, cgadyn.Sphere(1.0), None)


def test_a_large_hull_is_simplified_with_a_warning():
    points = np.random.default_rng(3).normal(size=(500, 3))
    points /= np.linalg.norm(points, axis=1)[:, None]
    with pytest.warns(cgadyn.MeshSimplified, match="simplified to 64"):
        mesh = cgadyn.ConvexMesh(points)
    assert len(mesh.vertices) <= 64
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(cgadyn.ConvexMesh(points[:20]).vertices) <= 20


# --- a robot's collisions -----------------------------------------------------------------


def test_urdf_collisions_are_placed_as_pinocchio_places_them():
    """solo12 collides through meshes: every ``<collision>`` is read (its hull), on its link;
    at random q each shape's world pose is Pinocchio's ``oMg`` of the same object, from
    ``buildGeomFromUrdf``."""
    pin = pytest.importorskip("pinocchio")
    from cgadyn import oracle
    from cgadyn.multibody import registry

    model, pm = oracle.models("solo12")
    urdf = str(registry.robot_path("solo12"))
    erd = registry.example_robot_data_dir()
    with pytest.warns(cgadyn.MeshSimplified):
        cm = cgadyn.collision_model(model)
    gm = pin.buildGeomFromUrdf(pm, urdf, pin.GeometryType.COLLISION,
                               package_dirs=[str(erd.parent.parent), str(erd.parent)])
    assert cm.names == tuple(g.name for g in gm.geometryObjects)
    feet = [c for c in cm if "FOOT" in c.name]
    assert len(feet) == 4 and all(isinstance(c.shape, cgadyn.ConvexMesh) for c in feet)
    pd, gd = pm.createData(), gm.createData()
    rng = np.random.default_rng(12)
    for _ in range(5):
        q = oracle.cgadyn_configuration(model, pin.randomConfiguration(pm, -np.ones(pm.nq),
                                                                     np.ones(pm.nq)))
        q[:3] = rng.uniform(-1, 1, 3)
        poses = cgadyn.collision_poses(model, cm, q)
        pin.updateGeometryPlacements(pm, pd, gm, gd, oracle.pin_configuration(model, q))
        for k in range(len(cm)):
            np.testing.assert_allclose(poses[k], gd.oMg[k].homogeneous, atol=1e-12)
    # every pair MuJoCo would test (no parent and child) in one call, as shape_distance
    pairs, d, pa, pb, n = cgadyn.collision_distances(cm, poses)
    assert len(pairs) and np.all(np.isfinite(d))
    assert not any(cm.adjacent(i, j) for i, j in pairs)
    assert cm.adjacent(cm.names.index("FL_LOWER_LEG_0"), cm.names.index("FL_FOOT_0"))
    for k in range(0, len(pairs), 17):
        i, j = pairs[k]
        one = cgadyn.shape_distance(cm[i].shape, poses[i], cm[j].shape, poses[j])
        assert one[0] == d[k] and np.array_equal(one[1], pa[k])
    # the hull holds the mesh's own vertices (those kept) and reaches as far in every
    # direction as the simplification allows
    foot = feet[0].shape
    mesh = gm.geometryObjects[cm.names.index(feet[0].name)].geometry
    verts = np.array(mesh.vertices())
    for d in np.random.default_rng(1).normal(size=(20, 3)):
        assert (foot.vertices @ d).max() <= (verts @ d).max() + 1e-12


def test_mjcf_geoms_are_read_as_mujoco_compiled_them():
    """Gymnasium's ant: its floor (a plane on the world), its torso sphere and leg capsules
    (MuJoCo's (radius, half-length) sizes), contype and conaffinity kept."""
    mujoco = pytest.importorskip("mujoco")
    path = ROOT / "robots" / "mujoco" / "gymnasium" / "ant.xml"
    mj = mujoco.MjModel.from_xml_path(str(path))
    cm = cgadyn.collision_model(cgadyn.load(path), path)
    assert len(cm) == mj.ngeom
    floor = cm[cm.names.index("floor")]
    assert isinstance(floor.shape, cgadyn.Plane) and floor.link == -1
    assert (floor.contype, floor.conaffinity) == (1, 1)
    assert isinstance(cm[cm.names.index("torso_geom")].shape, cgadyn.Sphere)
    leg = cm[cm.names.index("left_leg_geom")]
    assert isinstance(leg.shape, cgadyn.Capsule) and leg.conaffinity == 0
    assert leg.shape.radius == pytest.approx(0.08)
    assert leg.shape.length == pytest.approx(2 * mj.geom_size[mj.geom("left_leg_geom").id][1])


@pytest.mark.parametrize("name", ["ant", "humanoid", "walker2d", "hopper", "half_cheetah"])
def test_mjcf_geoms_are_placed_and_measured_as_mujoco_does(name):
    """At random states, every geom's pose is MuJoCo's geom_xpos/geom_xmat after
    mj_kinematics, and every pair's distance and witness points (separated or penetrating:
    planes, spheres, capsules, boxes) MuJoCo's mj_geomDistance, to 1e-12."""
    mujoco = pytest.importorskip("mujoco")
    path = ROOT / "robots" / "mujoco" / "gymnasium" / f"{name}.xml"
    mj = mujoco.MjModel.from_xml_path(str(path))
    model = cgadyn.load(path)
    cm = cgadyn.collision_model(model, path)
    data = mujoco.MjData(mj)
    rng = np.random.default_rng(4)
    penetrating = 0
    for _ in range(5):
        data.qpos[:] = mj.qpos0 + rng.normal(scale=0.3, size=mj.nq)
        if model.floating_base:
            data.qpos[3:7] /= np.linalg.norm(data.qpos[3:7])
        mujoco.mj_kinematics(mj, data)
        q, _ = cgadyn.from_mujoco_state(model, data.qpos, data.qvel)
        poses = cgadyn.collision_poses(model, cm, q)
        np.testing.assert_allclose(poses[:, :3, 3], data.geom_xpos, atol=1e-12)
        np.testing.assert_allclose(poses[:, :3, :3], data.geom_xmat.reshape(-1, 3, 3),
                                   atol=1e-12)
        pairs, d, pa, pb, n = cgadyn.collision_distances(cm, poses)
        assert len(pairs) and all(cm.can_touch(i, j) for i, j in pairs)
        fromto = np.zeros(6)
        for (i, j), dk, a, b in zip(pairs, d, pa, pb, strict=True):
            ref = mujoco.mj_geomDistance(mj, data, int(i), int(j), 10.0, fromto)
            assert dk == pytest.approx(ref, abs=1e-12)
            np.testing.assert_allclose(np.concatenate([a, b]), fromto, atol=1e-12)
            penetrating += dk < 0
    assert penetrating >= 1


def test_unknown_geom_types_are_refused():
    mujoco = pytest.importorskip("mujoco")
    xml = """<mujoco><asset><hfield name="h" nrow="3" ncol="3" size="0.5 0.5 0.1 0.1"/>
             </asset><worldbody><body name="b"><freejoint/>
             <geom name="tile" type="hfield" hfield="h"/><geom type="sphere" size="0.1"/>
             </body></worldbody></mujoco>"""
    model = cgadyn.from_mujoco(mujoco.MjModel.from_xml_string(xml))
    with pytest.raises(ValueError, match="geom 'tile' of body 'b': geom type 'hfield'"):
        cgadyn.collision_model(model, mujoco.MjModel.from_xml_string(xml))
    urdf = """<robot name="r"><link name="a"><collision><geometry><sphere radius="-1"/>
              </geometry></collision></link></robot>"""
    model = cgadyn.load_urdf(urdf)
    with pytest.raises(ValueError, match="collision 'a_0' of link 'a'.*radius"):
        cgadyn.collision_model(model, urdf)


def test_the_python_path_computes_the_same(tmp_path):
    """Under NUMBA_DISABLE_JIT=1 the kernels run as Python and give the compiled numbers:
    GJK, EPA, separating axes and a support point against a plane."""
    import json
    import os
    import subprocess
    import sys

    script = """
import json, numpy as np, cgadyn
rng = np.random.default_rng(7)
shapes = [cgadyn.Box([0.2, 0.3, 0.4]), cgadyn.Capsule(0.1, 0.5),
          cgadyn.ConvexMesh(rng.normal(size=(20, 3)) * 0.3), cgadyn.Cylinder(0.2, 0.4),
          cgadyn.Plane((0, 0, 1), 0.0)]
out = []
for a, b in [(0, 0), (1, 0), (2, 0), (3, 2), (2, 4), (1, 1)]:
    T = np.eye(4)
    T[:3, 3] = rng.uniform(-0.2, 0.2, 3) if a != 3 else [1.0, 0.0, 0.0]
    d, pa, pb, n = cgadyn.shape_distance(shapes[a], T, shapes[b], None)
    out.append([d, *pa, *pb, *n])
print(json.dumps(out))
"""
    results = []
    for jit in ("0", "1"):
        env = dict(os.environ, NUMBA_DISABLE_JIT=jit)
        done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                              text=True, timeout=600)
        assert done.returncode == 0, done.stderr
        results.append(np.array(json.loads(done.stdout.strip().splitlines()[-1])))
    assert (results[0][:, 0] < 0).sum() >= 3  # EPA and separating axes ran
    np.testing.assert_allclose(results[0], results[1], atol=1e-12)


def test_placed_shapes_are_the_shapes_moved():
    """A sphere's ``center``, a capsule between two points ``a`` and ``b``, a box's
    ``placement``: each shape's distance equals the centred shape's at the moved pose
    (to 1e-12), and a capsule from ``a`` to ``b`` has its length and middle there."""
    rng = np.random.default_rng(4)
    T = _pose(rng, 1.0)
    other, pose = cgadyn.Box([0.2, 0.3, 0.1]), _pose(rng, 0.5)
    for placed, centred in [
            (cgadyn.Sphere(0.2, center=T[:3, 3]), (cgadyn.Sphere(0.2), _at(T[:3, 3]))),
            (cgadyn.Box([0.1, 0.2, 0.3], placement=T), (cgadyn.Box([0.1, 0.2, 0.3]), T)),
            (cgadyn.Ellipsoid([0.1, 0.2, 0.3], placement=T),
             (cgadyn.Ellipsoid([0.1, 0.2, 0.3]), T))]:
        d1 = cgadyn.shape_distance(placed, None, other, pose)
        d2 = cgadyn.shape_distance(*centred, other, pose)
        for x, y in zip(d1, d2, strict=True):
            np.testing.assert_allclose(x, y, atol=1e-12)
    a, b = np.array([0.1, 0.2, 0.3]), np.array([0.5, -0.2, 0.9])
    capsule = cgadyn.Capsule(0.05, a, b)
    assert capsule.length == pytest.approx(np.linalg.norm(b - a), abs=1e-15)
    np.testing.assert_allclose(capsule.placement[:3, 3], 0.5 * (a + b), atol=1e-15)
    np.testing.assert_allclose(capsule.placement[:3, 2], (b - a) / np.linalg.norm(b - a),
                               atol=1e-15)
    d, pa, _, _ = cgadyn.shape_distance(capsule, None, cgadyn.Plane((0, 0, 1), 0.0), None)
    assert d == pytest.approx(0.3 - 0.05, abs=1e-12) and pa[2] == pytest.approx(0.25)
    for make, words in [
            (lambda: cgadyn.Sphere(0.1, center=(0, 0, 0), placement=np.eye(4)), "not both"),
            (lambda: cgadyn.Capsule(0.1, (0, 0, 0), (0, 0, 0)), "must differ"),
            (lambda: cgadyn.Box([1, 1, 1], placement=2 * np.eye(4)), "rigid 4x4"),
            (lambda: cgadyn.Sphere(0.1, center=(0, np.nan, 0)), "center must be three"),
            (lambda: cgadyn.Body(cgadyn.Sphere(0.1, center=(0, 0, 1)), 1.0), "centred")]:
        with pytest.raises(ValueError, match=words):
            make()


def test_hand_made_shapes_on_links():
    """``CollisionModel.with_shapes``: solo12's four foot hulls replaced by balls of 2 cm
    at the foot frames (each then the one shape of its foot, touching the ground at one
    point 2 cm under the frame), or added beside them (``replace=False``); ``shapes``
    gives each link's shapes placed in its frame, and a model made again from them
    places every shape where it was; unknown links and planes are named."""
    model = cgadyn.load("solo12")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        cm = cgadyn.collision_model(model)
    feet = [n for n in model.link_names if n.endswith("_FOOT")]
    balls = cm.with_shapes({f: [cgadyn.Sphere(0.02, center=(0, 0, 0))] for f in feet})
    assert len(balls) == len(cm) and all(len(balls.on(f)) == 1 for f in feet)
    assert all(balls.on(f)[0].shape.kind == cgadyn.Sphere(1).kind for f in feet)
    assert len(cm.with_shapes({"FL_FOOT": cgadyn.Sphere(0.02)}, replace=False)) == len(cm) + 1
    q = model.home.copy()
    q[2] = 1.0
    frames = cgadyn.link_placements(model, q)
    found = cgadyn.ground_contacts(model, balls, q, margin=10.0)
    for f in feet:
        rows = found.link == model.link_names.index(f)
        assert rows.sum() == 1
        z = frames[model.link_names.index(f)][2, 3]
        assert found.distance[rows][0] == pytest.approx(z - 0.02, abs=1e-12)
    again = cgadyn.CollisionModel([], model).with_shapes(
        {link: list(shapes) for link, shapes in balls.shapes.items()})
    np.testing.assert_allclose(np.sort(cgadyn.collision_poses(model, again, q), axis=0),
                               np.sort(cgadyn.collision_poses(model, balls, q), axis=0),
                               atol=1e-12)
    with pytest.raises(ValueError, match="no link 'paw'"):
        cm.with_shapes({"paw": [cgadyn.Sphere(0.02)]})
    with pytest.raises(ValueError, match="other than a plane"):
        cm.with_shapes({"FL_FOOT": [cgadyn.Plane()]})
