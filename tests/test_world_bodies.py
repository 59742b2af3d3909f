"""Free rigid bodies in the world and the contacts between pairs of shapes
(contact/bodies.py, contact/pairs.py, sim/pairs.py; docs/contact.md, "Free bodies and
pairs", K36-K39): the appended model against Pinocchio, the bodies' inertias against coal,
bodies resting on the ground and on each other carrying their weights, two balls meeting
head-on conserving momentum, an arm pushing a ball, the pair distances against coal, the
compiled rollout against ``contact_step``, and bad input named.

(tests/test_free_bodies.py checks models with several free-flyer roots loaded from files;
this file the bodies a ``World`` adds.)"""

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.bodies import Body, empty_model, shape_inertia, with_bodies, world_model
from cgadyn.contact.pairs import candidate_pairs, pair_rows
from cgadyn.contact.step import contact_step
from cgadyn.contact.world import World

G = 9.81
DT = 1e-3
SIE = "semi_implicit_euler"
EMPTY = empty_model()


def _panda():
    """The panda and its collision shapes (hulls simplified to 64 vertices, silently)."""
    model = cgadyn.load("panda")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        return model, cgadyn.collision_model(model)


def _box(name="box", half=0.1, mass=2.0, z=None, x=0.0, **kw):
    return Body(cgadyn.Box([half] * 3), mass, position=(x, 0.0, half if z is None else z),
                name=name, **kw)


def _sim(world, steps, q0=None, v0=None, robot=EMPTY, **kw):
    q0 = np.zeros(robot.nq) if q0 is None else q0
    v0 = np.zeros(robot.nv) if v0 is None else v0
    return cgadyn.simulate(robot, q0, v0, DT, steps, integrator=SIE, world=world, **kw)


def test_the_appended_bodies_are_pinocchio_free_flyers():
    """The panda with a box, a capsule and a convex rock appended equals Pinocchio's panda
    with three free-flyer joints added (their inertias from ``Body``): rnea and aba at
    random states to 1e-10."""
    pin = pytest.importorskip("pinocchio")
    from cgadyn import oracle

    model, pm = oracle.models("panda")
    rock = cgadyn.ConvexMesh(np.random.default_rng(1).normal(size=(20, 3)))
    bodies = [_box(), Body(cgadyn.Capsule(0.05, 0.2), 0.7, name="cap"),
              Body(rock, 1.0, name="rock")]
    extended, cm, qb = with_bodies(model, None, bodies)
    assert (extended.nq, extended.nv) == (model.nq + 21, model.nv + 18)
    assert cm.names == ("box", "cap", "rock") and qb[:7].tolist() == [0, 0, 0.1, 0, 0, 0, 1]
    for b in bodies:
        j = pm.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), b.name)
        pm.appendBodyToJoint(j, pin.Inertia(b.mass, b.com, b.inertia), pin.SE3.Identity())
    d = pm.createData()
    rng = np.random.default_rng(0)
    for _ in range(4):
        qp = pin.randomConfiguration(pm, -np.ones(pm.nq), np.ones(pm.nq))
        q = oracle.cgadyn_configuration(extended, qp)
        v, a = rng.normal(size=pm.nv), rng.normal(size=pm.nv)
        assert np.abs(cgadyn.rnea(extended, q, v, a) - pin.rnea(pm, d, qp, v, a)).max() < 1e-10
        assert np.abs(cgadyn.aba(extended, q, v, a) - pin.aba(pm, d, qp, v, a)).max() < 1e-10


def test_the_solid_inertias_are_coals():
    """K36: a box's, capsule's, cylinder's and sphere's inertia per unit mass equal coal's
    ``computeMomentofInertiaRelatedToCOM / computeVolume``; a convex mesh's (a cube's
    corners) equal the box's, about its centroid."""
    coal = pytest.importorskip("coal")
    for ours, theirs in ((cgadyn.Box([0.1, 0.2, 0.05]), coal.Box(0.2, 0.4, 0.1)),
                         (cgadyn.Capsule(0.05, 0.2), coal.Capsule(0.05, 0.2)),
                         (cgadyn.Cylinder(0.05, 0.2), coal.Cylinder(0.05, 0.2)),
                         (cgadyn.Sphere(0.3), coal.Sphere(0.3))):
        com, inertia = shape_inertia(ours, 1.0)
        ref = theirs.computeMomentofInertiaRelatedToCOM() / theirs.computeVolume()
        assert np.abs(inertia - ref).max() < 1e-14 and not com.any()
    corners = np.array([[x, y, z] for x in (0, 0.2) for y in (0, 0.4) for z in (0, 0.1)])
    com, inertia = shape_inertia(cgadyn.ConvexMesh(corners), 1.0)
    assert com == pytest.approx([0.1, 0.2, 0.05], abs=1e-14)
    assert np.abs(inertia - shape_inertia(cgadyn.Box([0.1, 0.2, 0.05]), 1.0)[1]).max() < 1e-14


def test_a_box_rests_on_the_ground_carrying_its_weight():
    """A box on the ground stays where it is (< 1e-9 m over 1 s) and the ground's four
    contacts carry m g to 1e-6. (Its own friction, the smaller one, makes the loop the one with
    pairs, which the other rollouts here compile.)"""
    tr = _sim(World(bodies=[_box(friction=0.8)]), 1000)
    assert np.abs(tr.q - tr.q[0]).max() < 1e-9
    assert tr.contact_count[-1] == 4
    # at rest to the 1e-6 relative: the step corrects overlaps of 1e-11 m
    assert tr.contact_forces[-1].sum(axis=0) == pytest.approx([0, 0, 2.0 * G],
                                                              abs=1e-6 * 2.0 * G)


def test_a_box_rests_on_a_box_both_carrying_what_lies_on_them():
    """A 1 kg box on a 2 kg box on the ground, by ``contact_step``: both stay still, the
    ground carries (m₁ + m₂) g, the upper box presses on the lower one with m₁ g (each
    pair contact's force on its first shape, the lower box)."""
    world = World(bodies=[_box(), _box("top", 0.05, 1.0, z=0.25)])
    extended, cm, q = world_model(EMPTY, None, world)
    v = np.zeros(extended.nv)
    for _ in range(200):
        s = contact_step(EMPTY, None, q, v, np.zeros(0), DT, world)
        q, v = s.q, s.v
    assert np.abs(q - world_model(EMPTY, None, world)[2]).max() < 1e-9
    ground = s.contacts.other == -1
    assert s.forces[ground].sum(axis=0) == pytest.approx([0, 0, 3.0 * G], abs=1e-6)
    assert s.forces[~ground].sum(axis=0) == pytest.approx([0, 0, -1.0 * G], abs=1e-6)
    assert set(s.contacts.collision[~ground]) == {0} and set(s.contacts.other[~ground]) == {1}


def _rotation(quaternion):
    """The rotation matrix of a quaternion ``(x, y, z, w)``."""
    from cgadyn.cga.conventions import matrix_from_motor, motor_from_quaternion

    x, y, z, w = quaternion
    return matrix_from_motor(motor_from_quaternion((w, x, y, z)))[:3, :3]


def _world_velocity(q, v):
    """The linear velocity in the world of a free flyer ``q`` (7,), ``v`` (6,)."""
    return _rotation(q[3:7]) @ v[:3]


def test_two_balls_meeting_head_on_keep_their_momentum_and_lose_energy():
    """Two balls (1 kg and 3 kg) meet head-on in the air without gravity: the total linear
    momentum stays what it was to 1e-9, the kinetic energy never rises, and (restitution 0)
    they leave together, at the common velocity ``(m₁ v₁ + m₂ v₂) / (m₁ + m₂)``."""
    a = Body(cgadyn.Sphere(0.1), 1.0, position=(-0.3, 0.0, 1.0), name="a")
    b = Body(cgadyn.Sphere(0.1), 3.0, position=(0.3, 0.0, 1.0), name="b")
    v0 = np.array([2.0, 0, 0, 0, 0, 0, -1.0, 0, 0, 0, 0, 0])
    extended, _, qb = world_model(EMPTY, None, World(ground=False, bodies=[a, b]))
    tr = _sim(World(ground=False, bodies=[a, b]), 400, q0=qb, v0=v0, gravity=(0, 0, 0))
    p = np.array([1.0 * _world_velocity(q[:7], v[:6]) + 3.0 * _world_velocity(q[7:], v[6:])
                  for q, v in zip(tr.q, tr.v, strict=True)])
    assert np.abs(p - p[0]).max() < 1e-9
    assert np.all(np.diff(tr.kinetic) <= 1e-12)
    assert tr.contact_count.max() >= 1
    common = (1.0 * 2.0 + 3.0 * -1.0) / 4.0
    assert _world_velocity(tr.q[-1, :7], tr.v[-1, :6])[0] == pytest.approx(common, abs=1e-6)
    assert _world_velocity(tr.q[-1, 7:], tr.v[-1, 6:])[0] == pytest.approx(common, abs=1e-6)


def _coal_pose(coal, T):
    return coal.Transform3s(T[:3, :3].copy(), T[:3, 3].copy())


def test_the_step_uses_coals_pair_distances():
    """K37: the deepest contact of each pair (a box on a box, a sphere and a capsule on a
    box, a convex rock on a sphere) lies at coal's distance of the two shapes, to 1e-9."""
    coal = pytest.importorskip("coal")
    rock = np.random.default_rng(2).normal(size=(16, 3)) * 0.05
    shapes = [(cgadyn.Box([0.1, 0.1, 0.1]), coal.Box(0.2, 0.2, 0.2), (0, 0, 0.1)),
              (cgadyn.Box([0.05, 0.05, 0.05]), coal.Box(0.1, 0.1, 0.1), (0.03, 0, 0.251)),
              (cgadyn.Sphere(0.04), coal.Sphere(0.04), (0.15, 0.02, 0.13)),
              (cgadyn.Capsule(0.03, 0.1), coal.Capsule(0.03, 0.1), (-0.05, 0.16, 0.05)),
              (cgadyn.ConvexMesh(rock), None, (0.2, 0.0, 0.22))]
    bodies = [Body(s, 1.0, position=p, orientation=(0.1 * k, 0.0, 0.05, 1.0), name=f"s{k}")
              for k, (s, _, p) in enumerate(shapes)]
    model, cm, q = with_bodies(EMPTY, None, bodies)
    poses = cgadyn.collision_poses(model, cm, q)
    pairs = np.array([(0, 1), (0, 2), (0, 3), (2, 4)])
    which, xa, xb, n, d = pair_rows(model, cm, poses, pairs, 0.05)
    for p, (i, j) in enumerate(pairs):
        mine = d[which == p]
        assert mine.size
        if shapes[j][1] is None:
            ref = cgadyn.collision_distances(cm, poses, [(i, j)])[1][0]
        else:
            req, res = coal.DistanceRequest(), coal.DistanceResult()
            ref = coal.distance(shapes[i][1], _coal_pose(coal, poses[i]), shapes[j][1],
                                _coal_pose(coal, poses[j]), req, res)
        assert mine.min() == pytest.approx(ref, abs=1e-9)
        assert np.allclose(xa[which == p] - xb[which == p], d[which == p, None] * n[which == p])


def test_the_compiled_rollout_is_contact_step_with_bodies():
    """A box on the ground, a ball thrown onto it off-centre, spinning, and a capsule lying
    apart: 300 steps of ``simulate`` equal 300 ``contact_step`` calls to 1e-10 (forces
    from zero each step, as ``contact_step`` starts them; the solvers' tolerance 1e-12, as
    the two build G with different rounding and a looser stop can end a sweep apart)."""
    world = World(bodies=[_box(), Body(cgadyn.Sphere(0.05), 0.5, position=(0.03, 0, 0.3),
                                       friction=0.4, name="ball"),
                          Body(cgadyn.Capsule(0.04, 0.2), 0.8, position=(-0.5, 0, 0.04),
                               orientation=(0.7071, 0, 0, 0.7071), name="cap")])
    extended, _, q = world_model(EMPTY, None, world)
    v = np.zeros(extended.nv)
    v[6], v[10] = 0.3, 2.0  # the ball's x velocity and y spin
    settings = cgadyn.ContactSettings(warm_start=False, tolerance=1e-12, accept=1e-10)
    tr = _sim(world, 300, q0=q, v0=v, contact=settings)
    assert tr.contact_count.max() >= 7  # the ground's and the ball on the box
    for k in range(300):
        assert np.abs(tr.q[k] - q).max() < 1e-10 and np.abs(tr.v[k] - v).max() < 1e-10
        s = contact_step(EMPTY, None, q, v, np.zeros(0), DT, world, contact=settings)
        q, v = s.q, s.v


def test_a_rollout_without_bodies_has_no_pairs():
    """Without bodies and without self-collision the world tuple's pairs are None (the
    pairs' code is pruned); with ``self_collision`` the panda's non-adjacent links pair."""
    from cgadyn.sim.contact import world_arrays

    model, cm = _panda()
    settings = cgadyn.ContactSettings()
    arrays = world_arrays(model, cm, World(), settings)
    assert arrays.pairs is None and arrays.shape_friction is None
    pairs = candidate_pairs(cm, model.njoints, True)
    assert len(pairs) and not any(cm.adjacent(i, j) for i, j in pairs)
    assert world_arrays(model, cm, World(self_collision=True), settings).pairs is not None


@pytest.mark.slow
def test_the_panda_pushes_a_box_along_the_ground():
    """The panda (fixed base) under PD swings its hand low through a box standing on the
    ground: the box is pushed 0.2 m away or more (it tips onto its side) and comes to rest,
    never sinking into the ground by 1e-3 m, and the arm reaches its goal. (A ball pushed
    so rolls away spinning: the explicit Euler term ``ω × v`` of a free flyer's body-frame
    velocity then feeds energy into it, a limit of the integrator noted in
    docs/contact.md.)"""
    model, cm = _panda()
    start = np.array([-0.6, 1.0, 0.0, -1.2, 0.0, 2.2, 0.8, 0.02, 0.02])
    goal = start.copy()
    goal[0] = 0.6
    hand = cgadyn.link_placements(model, 0.5 * (start + goal))[model.link_index("panda_hand")]
    half = np.array([0.05, 0.05, 0.08])  # the fingers pass 5.5 cm above the ground
    box = Body(cgadyn.Box(half), 0.3, position=(hand[0, 3], hand[1, 3], half[2]), name="box")
    inertia = np.diag(cgadyn.crba(model, start))  # gains of 10 rad/s, critically damped
    tr = cgadyn.simulate(model, start, np.zeros(model.nv), DT, 1500, integrator=SIE,
                         world=World(bodies=[box]), collisions=cm,
                         controller=cgadyn.PD(100.0 * inertia, 20.0 * inertia, q_ref=goal),
                         contact=cgadyn.ContactSettings(accept=1e-4))
    assert not tr.diverged
    qb = tr.q[:, model.nq:]
    assert np.linalg.norm(qb[-1, :2] - qb[0, :2]) > 0.2
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * half
    lowest = [np.min((_rotation(q[3:7]) @ corners.T)[2] + q[2]) for q in qb]
    assert min(lowest) > -1e-3
    assert np.abs(tr.q[-1, :model.nq] - goal).max() < 0.05
    assert np.abs(tr.v[-1, model.nv:]).max() < 1e-3  # the box at rest again


def test_bad_bodies_are_named():
    with pytest.raises(ValueError, match="Body 'b'.*mass"):
        Body(cgadyn.Sphere(0.1), 0.0, name="b")
    with pytest.raises(ValueError, match="Body 'b'.*mass"):
        Body(cgadyn.Sphere(0.1), -1.0, name="b")
    with pytest.raises(ValueError, match="Body 'b'.*shape"):
        Body("sphere", 1.0, name="b")
    with pytest.raises(ValueError, match="Body 'b'.*shape"):
        Body(cgadyn.Plane(), 1.0, name="b")
    with pytest.raises(ValueError, match="Body 'b'.*inertia"):
        Body(cgadyn.Sphere(0.1), 1.0, inertia=-np.eye(3), name="b")
    with pytest.raises(ValueError, match="bodies must be cgadyn.Body"):
        World(bodies=[cgadyn.Sphere(0.1)])
    sunk = Body(cgadyn.Box([0.1] * 3), 1.0, position=(0, 0, 0.098), name="sunk")
    with pytest.raises(ValueError, match="Body 'sunk' starts 0.002 m inside the ground"):
        _sim(World(bodies=[sunk]), 2)
    with pytest.raises(ValueError, match="Body 'panda_link1'.*name is taken"):
        with_bodies(cgadyn.load("panda"), None, [_box("panda_link1")])


def test_a_rollouts_pair_contacts_and_criteria_are_contact_steps():
    """A ball thrown off-centre onto a box on the ground: at every 10th step the contacts
    ``Trajectory.contacts`` finds again, the ball's on the box among them, are
    ``contact_step``'s from the same state (point, force, the other shape), and the
    criteria ``Trajectory.contact_criteria`` gives equal its step's, to 1e-9. The box on
    four corners under the ball is statically indeterminate: its corners' forces are not
    unique, and the two steps' G, equal to rounding (M's factors, a dense solve), may
    share them differently by up to 1e-6 N, their sum equal to 1e-9 N."""
    world = World(bodies=[_box(), Body(cgadyn.Sphere(0.05), 0.5, position=(0.03, 0, 0.3),
                                       friction=0.4, name="ball")])
    extended, _, q = world_model(EMPTY, None, world)
    v = np.zeros(extended.nv)
    v[6], v[10] = 0.3, 2.0
    settings = cgadyn.ContactSettings(warm_start=False, tolerance=1e-12, accept=1e-10)
    tr = _sim(world, 300, q0=q, v0=v, contact=settings)
    history = tr.contact_criteria()
    assert history.unmatched == 0
    assert np.array_equal(history.contacts, tr.contact_count[:-1])
    pairs_seen = 0
    for k in range(0, 300, 10):
        s = contact_step(EMPTY, None, tr.q[k], tr.v[k], np.zeros(0), DT, world,
                         contact=settings)
        found = tr.contacts(k)
        assert len(found) == len(s.contacts) == tr.contact_count[k]
        for c, i in zip(found, range(len(found)), strict=True):
            other = s.contacts.other[i]
            assert c.other == (None if other < 0 else ("box", "ball")[other])
            assert np.abs(c.point - s.contacts.point[i]).max() < 1e-12
            assert np.abs(c.force - s.forces[i]).max() < 1e-6
            pairs_seen += other >= 0
        total = sum(c.force for c in found) if len(found) else np.zeros(3)
        assert np.abs(total - s.forces.sum(axis=0)).max() < 1e-9
        if len(found):
            for name, value in s.criteria.maxima().items():
                assert getattr(history, name)[k] == pytest.approx(value, abs=1e-9), name
    assert pairs_seen >= 10
