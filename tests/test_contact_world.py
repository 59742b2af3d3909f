"""Contacts with the ground (contact/manifold.py, contact/world.py; docs/contact.md K21-K22):
each shape's deepest contact has the distance of ``shape_distance`` to the plane, a resting
face gives the corners of its patch, and a robot standing touches the ground by its feet."""

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import cgadyn
from cgadyn.contact import manifold as C
from cgadyn.contact.pairs import bounding_radii
from cgadyn.contact.world import World, ground_contacts

SHAPES = [cgadyn.Sphere(0.1), cgadyn.Capsule(0.05, 0.3), cgadyn.Box([0.1, 0.2, 0.05]),
          cgadyn.Cylinder(0.08, 0.2),
          cgadyn.ConvexMesh(np.random.default_rng(0).normal(size=(40, 3)) * 0.1)]


def _pose(rng):
    x, y, z, w = rng.normal(size=4)
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    T = np.eye(4)
    T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    T[:3, 3] = rng.normal(size=3) * [0.3, 0.3, 0.1]
    return T


def _contacts(shape, T, world=None, margin=1.0):
    world = World() if world is None else world
    out = np.empty((C.MAX_CONTACTS, C.OUT))
    cand = np.empty((C.CANDIDATES, C.CANDIDATE_COLUMNS))
    radius = bounding_radii([SimpleNamespace(shape=shape)])[0]
    vertices = np.ascontiguousarray(shape.packed_vertices, dtype=float).reshape(-1, 3)
    counts = np.zeros(1)  # floats, as the library passes them (one compiled variant)
    C.shapes_on_plane(np.array([shape.kind]), np.array([shape.packed_size], dtype=float),
                      vertices, np.array([0, len(vertices)]), T[None].copy(),
                      np.array([radius]), np.array([True]), np.zeros((1, 2)),
                      world.plane.packed_size,
                      np.eye(4), margin, 0.0, cand, out[None], counts, np.zeros((1, 2, 6)),
                      0.0)
    return out[:int(counts[0])]


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.name)
def test_deepest_contact_is_the_distance_to_the_plane(shape):
    """K21 against K5: the deepest contact point is the shape's closest point to the plane,
    at the signed distance ``shape_distance`` gives, on the shape, for random poses, on a
    level and on a tilted ground."""
    rng = np.random.default_rng(1)
    for world in (World(), World(ground_normal=(0.3, -0.2, 1.0), ground_height=0.05)):
        n = np.asarray(world.ground_normal)
        for _ in range(20):
            T = _pose(rng)
            d, p_a, _, _ = cgadyn.shape_distance(shape, T, world.plane, None)
            rows = _contacts(shape, T, world, margin=d + 1e-3)
            assert 1 <= len(rows) <= C.MAX_CONTACTS
            deepest = rows[np.argmin(rows[:, 3])]
            assert deepest[3] == pytest.approx(d, abs=1e-12)
            assert np.all(rows[:, 3] < d + 1e-3)
            # every point lies on the plane's side it claims: its distance is n · x - δ
            assert np.allclose(rows[:, :3] @ n - n[2] * world.ground_height, rows[:, 3],
                               atol=1e-12)
            if shape.kind in (C.SPHERE, C.BOX, C.CYLINDER):  # unique deepest point here
                assert np.allclose(deepest[:3], p_a, atol=1e-9) or \
                    np.sum(np.isclose(rows[:, 3], d, atol=1e-9)) > 1


def _resting(T_shape, height):
    T = T_shape.copy()
    T[2, 3] = height
    return T


def test_a_box_on_a_face_an_edge_and_a_corner():
    """K22: a box lying on its face touches by its four bottom corners, tipped onto an edge
    by two, balanced on a corner by one."""
    box = cgadyn.Box([0.1, 0.2, 0.05])
    rows = _contacts(box, _resting(np.eye(4), 0.05), margin=1e-6)
    assert len(rows) == 4
    assert np.allclose(np.sort(np.abs(rows[:, :2]), axis=0), [[0.1, 0.2]] * 4)
    assert np.allclose(rows[:, 2:], 0.0, atol=1e-15)
    c, s = math.cos(0.3), math.sin(0.3)
    edge = np.eye(4)
    edge[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
    edge[2, 3] = 0.2 * s + 0.05 * c  # the lower edge on the ground
    rows = _contacts(box, edge, margin=1e-9)
    assert len(rows) == 2 and np.allclose(rows[:, 3], 0.0, atol=1e-12)
    assert abs(rows[0, 0] - rows[1, 0]) == pytest.approx(0.2)
    R1 = edge[:3, :3]
    c2, s2 = math.cos(0.4), math.sin(0.4)
    R = np.array([[c2, 0, s2], [0, 1, 0], [-s2, 0, c2]]) @ R1
    corner = np.eye(4)
    corner[:3, :3] = R
    lowest = min((R @ (np.array([sx, sy, sz]) * [0.1, 0.2, 0.05]))[2]
                 for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1))
    corner[2, 3] = -lowest
    rows = _contacts(box, corner, margin=1e-9)
    assert len(rows) == 1 and rows[0, 3] == pytest.approx(0.0, abs=1e-12)


def test_a_flat_mesh_face_is_held_by_its_corners():
    """K22: a convex mesh whose bottom face carries a 5 x 5 grid of vertices, resting on it,
    is held by the four corners of that face (the largest patch four points span), not by
    four neighbouring grid points."""
    g = np.linspace(-0.1, 0.1, 5)
    bottom = [(x, y, -0.05) for x in g for y in g]
    top = [(x, y, 0.05) for x in (-0.1, 0.1) for y in (-0.1, 0.1)]
    mesh = cgadyn.ConvexMesh(np.array(bottom + top))
    rows = _contacts(mesh, _resting(np.eye(4), 0.05), margin=1e-9)
    assert len(rows) == 4
    assert np.allclose(np.sort(np.abs(rows[:, :2]).ravel()), 0.1)


def test_cylinders_and_capsules_standing_and_lying():
    """K21: a cylinder on its cap touches by four rim points a quarter-turn apart, lying on
    its side by one point of each rim; a capsule lying down by both end spheres."""
    cyl, cap = cgadyn.Cylinder(0.08, 0.2), cgadyn.Capsule(0.05, 0.3)
    rows = _contacts(cyl, _resting(np.eye(4), 0.1), margin=1e-9)
    assert len(rows) == 4
    assert np.allclose(np.hypot(rows[:, 0], rows[:, 1]), 0.08)
    side = np.eye(4)
    side[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # its axis along y
    side[2, 3] = 0.08
    for shape, rows in ((cyl, _contacts(cyl, side, margin=1e-9)),
                        (cap, _contacts(cap, _resting(side, 0.05), margin=1e-9))):
        assert len(rows) == 2, shape
        assert np.allclose(sorted(rows[:, 1]), [-shape.length / 2, shape.length / 2])
        assert np.allclose(rows[:, 2:], 0.0, atol=1e-12)


def test_a_box_resting_on_a_tilted_ground():
    """A box placed flat on a ground tilted by 0.2 rad touches it by four corners, at zero
    distance, with the ground's normal."""
    t = 0.2
    world = World(ground_normal=(0.0, -math.sin(t), math.cos(t)))
    box = cgadyn.Box([0.1, 0.1, 0.1])
    T = np.eye(4)
    T[:3, :3] = [[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]]
    T[:3, 3] = 0.1 * np.asarray(world.ground_normal)
    rows = _contacts(box, T, world, margin=1e-9)
    assert len(rows) == 4 and np.allclose(rows[:, 3], 0.0, atol=1e-12)


@pytest.fixture(scope="module")
def solo():
    model = cgadyn.load("solo12")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        return model, cgadyn.collision_model(model, "solo12")


def test_solo12_stands_on_its_feet(solo):
    """solo12 in its standing posture, lowered until its lowest shape touches the ground:
    every contact within 1 mm is on a foot, each foot touches, and the contact points lie
    where the feet's shapes are closest to the ground."""
    model, cm = solo
    q = cgadyn.neutral(model)
    q[7:] = np.tile([0.0, 0.8, -1.6], 4)
    q[2] = 0.3
    first = ground_contacts(model, cm, q, margin=1.0)
    q[2] -= first.distance.min()
    ct = ground_contacts(model, cm, q, margin=1e-3)
    names = {cm[k].name for k in ct.collision}
    assert names == {"FL_FOOT_0", "FR_FOOT_0", "HL_FOOT_0", "HR_FOOT_0"}
    assert ct.distance.min() == pytest.approx(0.0, abs=1e-12)
    assert np.all(ct.distance < 1e-3) and np.allclose(ct.normal, [0, 0, 1])
    assert np.allclose(ct.point[:, 2], ct.distance, atol=1e-12)
    assert [model.link_names[i] for i in ct.link] == [cm[k].name[:-2] for k in ct.collision]
    assert len(ground_contacts(model, cm, q, World(ground=False), margin=1.0)) == 0


def test_an_mjcf_floor_is_not_its_own_contact():
    """Gymnasium's ant: its floor geom is fixed in the world and never a contact; its legs
    touch the World's ground."""
    ant = cgadyn.load("gymnasium:ant")
    cm = cgadyn.collision_model(ant, "gymnasium:ant")
    q = cgadyn.neutral(ant)
    ct = ground_contacts(ant, cm, q, margin=10.0)
    assert len(ct) and np.all(ct.link >= 0)
    assert all(cm[k].link >= 0 for k in ct.collision)


def test_a_link_welded_to_the_world_never_touches_the_ground():
    """The double pendulum's base link sits on z = 0 with its fixed base: no force moves it,
    so it is no contact (its rows would be zero and the contact problem unsolvable); its
    moving links are, when lowered into reach."""
    model = cgadyn.load("double_pendulum")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        cm = cgadyn.collision_model(model)
    q = cgadyn.neutral(model)
    ct = ground_contacts(model, cm, q, margin=10.0)
    assert len(ct) and {model.link_names[i] for i in ct.link} == {"link1", "link2"}
    assert model.link_joint[model.link_names.index("base_link")] == -1


def test_bad_input_is_named(solo):
    model, cm = solo
    with pytest.raises(ValueError, match="ground_normal"):
        World(ground_normal=(0, 0, 0))
    with pytest.raises(ValueError, match="friction"):
        World(friction=-1.0)
    with pytest.raises(ValueError, match="q: expected shape"):
        ground_contacts(model, cm, np.zeros(3))
    with pytest.raises(ValueError, match="margin"):
        ground_contacts(model, cm, cgadyn.neutral(model), margin=-1.0)
    with pytest.raises(ValueError, match="ground_contacts: world must be a cgadyn.World"):
        ground_contacts(model, cm, cgadyn.neutral(model), world="floor")
