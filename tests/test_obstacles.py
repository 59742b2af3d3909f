"""Static shapes of the world (contact/obstacles.py; docs/contact.md, "The static world",
K44): a ball resting on a table and an arm falling onto a step, both where geometry says
and where MuJoCo's own simulation of the same MJCF puts them; an MJCF's floor and geoms
as the default world of ``simulate``, replaced by a ``World`` given; the pairs an obstacle
forms; the energy of a fall onto an obstacle; bad input named."""

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.bodies import empty_model
from cgadyn.contact.obstacles import Obstacle, scene_collisions
from cgadyn.contact.pairs import candidate_pairs
from cgadyn.contact.static_world import static_world

mujoco = pytest.importorskip("mujoco")

DT = 1e-3
SIE = "semi_implicit_euler"

SCENE = """
<mujoco>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" pos="0 0 0.2" size="2 2 .1" friction="0.7"/>
    <geom name="table" type="box" pos="0.3 0 0.6" size="0.3 0.3 0.02" friction="0.9"/>
    <geom name="step" type="box" pos="-0.2 0 0.7" size="0.1 0.2 0.1"/>
    <body name="ball" pos="0.3 0 1.0">
      <freejoint/>
      <geom name="ball" type="sphere" size="0.05" mass="1"/>
    </body>
    <body name="stone" pos="1.2 0 0.5">
      <freejoint/>
      <geom name="stone" type="sphere" size="0.04" mass="0.5"/>
    </body>
    <body name="arm" pos="-0.5 0 1.0">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom name="arm" type="capsule" fromto="0 0 0 0.5 0 0" size="0.02" mass="0.3"/>
    </body>
  </worldbody>
</mujoco>
"""
"""A ball dropped onto a table (its top at z = 0.62), a stone beside it onto the floor
(z = 0.2), and an arm hinged at (-0.5, 0, 1) falling onto a step (its top at z = 0.8,
from x = -0.3 to -0.1)."""

ARM_REST = np.arctan2(0.2, 0.4) - np.arcsin(0.02 / np.hypot(0.2, 0.4))
"""The hinge's angle at rest: the arm's capsule (radius 0.02) on the step's far top edge,
0.4 m out and 0.2 m down from the hinge."""


@pytest.fixture(scope="module")
def scene():
    mj = mujoco.MjModel.from_xml_string(SCENE)
    model = cgadyn.from_mujoco(mj)
    return model, cgadyn.collision_model(model, mj), mj


def _rest(model, collisions, world=None, steps=1500):
    q0 = model.home.copy()
    return cgadyn.simulate(model, q0, np.zeros(model.nv), DT, steps, integrator=SIE,
                           world=world, collisions=collisions)


def test_the_mjcf_world_is_its_floor_and_geoms(scene):
    """``static_world`` of the scene's collisions: the floor plane the ground at its height
    and friction, the table and the step obstacles at their placements with their
    friction; the robot's shapes are not part of it."""
    model, cm, _ = scene
    world = static_world(cm)
    assert world.ground and world.ground_height == pytest.approx(0.2, abs=1e-12)
    assert np.allclose(world.ground_normal, (0, 0, 1)) and world.friction == 0.7
    assert [o.name for o in world.obstacles] == ["table", "step"]
    table = world.obstacles[0]
    assert np.allclose(table.position, (0.3, 0, 0.6)) and table.friction == 0.9
    assert np.allclose(table.shape.size[:3], (0.3, 0.3, 0.02))
    assert world.obstacles[1].friction == 1.0  # MuJoCo's default


def test_resting_on_the_static_world_where_geometry_and_mujoco_say(scene):
    """Without ``world=``, the scene's own floor and geoms are the world: the ball rests on
    the table (z = 0.62 + 0.05), the stone on the floor at 0.2 (z = 0.24) and the arm on
    the step's edge (``ARM_REST``), each to 1e-4 after 1.5 s; MuJoCo's simulation of the
    same file (soft contacts, which sink a little) agrees to 2e-3 m and 1e-2 rad."""
    model, cm, mj = scene
    traj = _rest(model, cm)
    assert traj.completed == 1500
    q = traj.q[-1]
    ball, stone = (model.joint_names.index(f"{b}_joint0") for b in ("ball", "stone"))
    z_ball, z_stone = q[model.idx_q[ball] + 2], q[model.idx_q[stone] + 2]
    angle = q[model.idx_q[model.joint_names.index("hinge")]]
    assert z_ball == pytest.approx(0.67, abs=1e-4)
    assert z_stone == pytest.approx(0.24, abs=1e-4)
    assert angle == pytest.approx(ARM_REST, abs=1e-4)
    assert np.abs(traj.v[-1]).max() < 1e-3
    # the table and the floor carry the ball and the stone: the forces on them, upwards
    contacts = traj.contacts(1499)
    on = {c.link: 0.0 for c in contacts}
    for c in contacts:
        on[c.link] += c.force[2]
    assert on["ball"] == pytest.approx(9.81 * 1.0, rel=1e-6)
    assert on["stone"] == pytest.approx(9.81 * 0.5, rel=1e-6)
    d = mujoco.MjData(mj)
    for _ in range(1500):
        mujoco.mj_step(mj, d)
    qpos = d.qpos
    assert qpos[2] == pytest.approx(z_ball, abs=2e-3)
    assert qpos[9] == pytest.approx(z_stone, abs=2e-3)
    assert qpos[14] == pytest.approx(angle, abs=1e-2)


def test_a_world_given_replaces_the_static_geoms(scene):
    """``World()`` in place of the scene's own: a level ground at z = 0 and no table, so
    the ball falls past where the table was and rests on that ground (z = 0.05)."""
    model, cm, _ = scene
    traj = _rest(model, cm, cgadyn.World(), steps=1200)
    ball = model.joint_names.index("ball_joint0")
    assert traj.q[-1, model.idx_q[ball] + 2] == pytest.approx(0.05, abs=1e-4)


def test_a_ball_dropped_on_an_obstacle_rests_without_gaining_energy():
    """A ``World`` with an ``Obstacle`` table (no MJCF): a free ball dropped on it rests
    at the table's top plus its radius to 1e-4, and its energy never rises above the
    start's (1e-9 relative)."""
    table = Obstacle(cgadyn.Box((0.4, 0.4, 0.02)), position=(0, 0, 0.5),
                     orientation=(0, 0, np.sin(0.3), np.cos(0.3)))
    ball = cgadyn.Body(cgadyn.Sphere(0.05), 1.0, position=(0.1, 0.0, 0.8))
    world = cgadyn.World(bodies=[ball], obstacles=[table])
    traj = cgadyn.simulate(empty_model(), np.zeros(0), np.zeros(0), DT, 1000, integrator=SIE,
                           world=world)
    assert traj.q[-1, 2] == pytest.approx(0.57, abs=1e-4)
    assert np.allclose(traj.q[-1, :2], (0.1, 0.0), atol=1e-6)
    assert np.max(traj.energy) <= traj.energy[0] + 1e-9 * abs(traj.energy[0])


def test_an_obstacle_pairs_with_every_moving_shape(scene):
    """An obstacle forms a pair with each moving shape its filter allows, without
    ``self_collision``; never with another shape of the world, nor with one whose
    ``contype``/``conaffinity`` exclude it; the MJCF's own world shapes touch nothing once
    a World replaces them."""
    model, cm, _ = scene
    shy = Obstacle(cgadyn.Sphere(0.1), position=(2, 2, 2), contype=0, conaffinity=0,
                   name="shy")
    world = cgadyn.World(obstacles=[Obstacle(cgadyn.Sphere(0.1), name="rock"), shy])
    sc = scene_collisions(cm, world, model)
    names = sc.names
    pairs = {tuple(sorted((names[i], names[j]))) for i, j in candidate_pairs(sc, model.njoints)}
    assert pairs == {("ball", "rock"), ("rock", "stone"), ("arm", "rock")}
    own = static_world(cm)
    sc = scene_collisions(cm, own, model)
    pairs = {tuple(sorted((sc.names[i], sc.names[j])))
             for i, j in candidate_pairs(sc, model.njoints)}
    assert ("ball", "table") in pairs and ("arm", "step") in pairs and len(pairs) == 6


def test_bad_obstacles_are_named():
    with pytest.raises(ValueError, match="shape must be a cgadyn Sphere, .* or Plane"):
        Obstacle("wall")
    with pytest.raises(ValueError, match="position must be three finite numbers"):
        Obstacle(cgadyn.Sphere(0.1), position=(0, np.nan, 0))
    with pytest.raises(ValueError, match="orientation must be a nonzero quaternion"):
        Obstacle(cgadyn.Sphere(0.1), orientation=(0, 0, 0, 0))
    with pytest.raises(ValueError, match="contype must be an integer bit mask"):
        Obstacle(cgadyn.Sphere(0.1), contype=-1)
    with pytest.raises(ValueError, match="obstacles must be cgadyn.Obstacle records"):
        cgadyn.World(obstacles=[cgadyn.Sphere(0.1)])


def test_walls_are_obstacles_and_contactless_models_have_no_world():
    """dm_control's quadruped: its floor the ground, its four wall planes half-space
    obstacles, each paired with every moving shape; dm_control's cartpole turns contacts
    off: its world's geoms (the floor and the rails its cart slides in) are left out, with
    a warning, and ``simulate`` with its collisions and no World names what is missing."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its actuators, couplings and height field
        model = cgadyn.load("dm_control:quadruped")
        cm = cgadyn.collision_model(model)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        world = static_world(cm)
    assert world.ground and world.ground_height == 0.0
    walls = ("wall_px", "wall_py", "wall_nx", "wall_ny")
    assert tuple(o.name for o in world.obstacles) == walls
    assert all(o.shape.kind == cgadyn.Plane.kind for o in world.obstacles)
    sc = scene_collisions(cm, world, model)
    wall = len(sc) - 4  # the obstacle (the model's own wall_px, before it, touches nothing)
    moving = sum(1 for k, c in enumerate(cm) if c.link >= 0 and model.link_joint[c.link] >= 0
                 and sc.can_touch(wall, k))
    paired = [sc.names[j] for i, j in candidate_pairs(sc, model.njoints)]
    assert moving > 0 and all(paired.count(w) == moving for w in walls)
    cart = cgadyn.load("dm_control:cartpole")
    with pytest.warns(UserWarning, match="turns contacts off.*'floor', 'rail1', 'rail2'"):
        cm = cgadyn.collision_model(cart)
    assert all(c.link >= 0 for c in cm)
    with pytest.raises(ValueError, match="collisions given without a world"):
        cgadyn.simulate(cart, cart.home, np.zeros(cart.nv), DT, 2, integrator=SIE,
                        collisions=cm)


def test_the_page_draws_the_obstacles_and_the_ground(scene, tmp_path):
    """``write_html(..., world=)``: a static node per obstacle (the table's box sized as it
    is, the step's; a convex mesh's hull as triangles) and the floor grid at the ground's
    height; a bad world is named."""
    pytest.importorskip("meshcat")
    from cgadyn.sim import html

    model, cm, _ = scene
    world = static_world(cm)
    q = np.tile(model.home, (3, 1))
    cmds, framing = html._commands(model, q, 0.01, 30.0, SCENE, True, None, world)
    nodes = {c["path"]: c for c in cmds if c["type"] == "set_object"}
    assert "/cgadyn/world/0_table/visual_0" in nodes and "/cgadyn/world/1_step/visual_0" in nodes
    table = [c for c in cmds if c["type"] == "set_transform"
             and c["path"] == "/cgadyn/world/0_table/visual_0"][0]
    assert np.allclose(np.reshape(table["matrix"], (4, 4)).T[:3, 3], (0.3, 0, 0.6))
    assert framing["floor"] == pytest.approx(0.2)
    rock = Obstacle(cgadyn.ConvexMesh(np.random.default_rng(2).normal(size=(20, 3))),
                    name="rock")
    hull = html._obstacles(cgadyn.World(obstacles=[rock]))[0]["object"]
    data = hull["geometries"][0]["data"]
    faces = np.frombuffer(data["index"]["array"].data, dtype=np.uint32).reshape(-1, 3)
    corners = np.frombuffer(data["attributes"]["position"]["array"].data,
                            dtype=np.float32).reshape(-1, 3)
    assert len(faces) >= 4 and faces.max() < len(corners)
    assert len(faces) == 2 * len(corners) - 4  # a closed triangulated convex hull
    page = html.write_html(model, q, 0.01, tmp_path / "scene.html", SCENE, world=world)
    assert page.stat().st_size > 0
    with pytest.raises(ValueError, match="world must be a cgadyn.World"):
        html.write_html(model, q, 0.01, tmp_path / "bad.html", world="floor")


def test_an_arm_falls_onto_a_table_and_stays_on_it():
    """The panda (fixed base, its links' convex hulls), held by joint dampers alone, sags
    from 0.36 m above a table obstacle onto it: after 2 s it rests (joint speeds below
    1e-3 rad/s) with its hand within 10 cm of the table's top, its links touching the
    table and nothing else, none more than 1e-4 m into it."""
    panda = cgadyn.load("panda")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        cm = cgadyn.collision_model(panda)
    q0 = np.array([0.0, 0.3, 0.0, -1.2, 0.0, 1.5, 0.8, 0.02, 0.02])
    table = Obstacle(cgadyn.Box([0.3, 0.4, 0.02]), position=(0.6, 0.0, 0.25), name="table")
    inertia = np.diag(cgadyn.crba(panda, q0))
    traj = cgadyn.simulate(panda, q0, np.zeros(panda.nv), DT, 2000, integrator=SIE,
                           world=cgadyn.World(obstacles=[table]), collisions=cm,
                           controller=cgadyn.PD(0.0 * inertia, 2.0 * inertia, q_ref=q0,
                                                gravity_compensation=False),
                           contact=cgadyn.ContactSettings(accept=1e-4))
    assert traj.completed == 2000
    hand = panda.link_index("panda_hand")
    z = [cgadyn.link_placements(panda, q)[hand][2, 3] for q in (traj.q[0], traj.q[-1])]
    assert z[0] > 0.6 and 0.27 < z[1] < 0.37
    assert np.abs(traj.v[-1]).max() < 1e-3
    contacts = traj.contacts(1999)
    assert contacts and {c.other for c in contacts} == {"table"}
    assert min(c.distance for c in contacts) > -1e-4


def test_one_contact_step_in_the_mjcf_world(scene):
    """``contact_step`` without ``world=`` steps in the scene's own world too: from the
    rest the rollout reached, the ball held by the table (its contacts' forces on it
    summing to its weight, its speed after the step below 1e-6 m/s) and the arm by the
    step."""
    model, cm, _ = scene
    traj = _rest(model, cm)
    step = cgadyn.contact_step(model, cm, traj.q[-1], traj.v[-1], np.zeros(model.nv), DT)
    ball = model.link_names.index("ball")
    on_ball = step.contacts.link == ball
    names = np.asarray(step.collisions.names)  # the step's shapes: the obstacles appended
    assert on_ball.any() and set(names[step.contacts.other[on_ball]]) == {"table"}
    assert step.forces[on_ball, 2].sum() == pytest.approx(9.81, rel=1e-6)
    assert np.abs(step.v[:6]).max() < 1e-6
    arm = step.contacts.link == model.link_names.index("arm")
    assert set(names[step.contacts.other[arm]]) == {"step"}


WALL_SCENE = """
<mujoco>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 .1" friction="0.1"/>
    <geom name="wall" type="plane" pos="0.4 0 0" zaxis="-1 0 0" size="1 1 .1" friction="0.1"/>
    <body name="box" pos="0 0 0.05">
      <freejoint/>
      <geom name="box" type="box" size="0.05 0.05 0.05" mass="1" friction="0.1"/>
    </body>
  </worldbody>
</mujoco>
"""
"""A box sliding at 1.5 m/s on a floor of friction 0.1 into a wall plane at x = 0.4: it
would slide 1.15 m, so it reaches the wall and stops against it, its centre at 0.35."""


def test_a_box_slides_into_an_mjcf_wall_and_stops_against_it():
    """The MJCF's second plane is a wall of its static world (K44a): the box stops flush
    against it, its centre at x = 0.35 to 1e-4, upright, the wall's contacts a patch of
    its face's corners pushing along -x, and it never gains energy. MuJoCo's simulation of
    the same file stops it at the wall too, neither through it nor more than 1.5 cm short
    of it (its soft contact bounces the box back 1.1 cm; cgadyn's rigid one does not)."""
    mj = mujoco.MjModel.from_xml_string(WALL_SCENE)
    model = cgadyn.from_mujoco(mj)
    cm = cgadyn.collision_model(model, mj)
    v0 = np.zeros(model.nv)
    v0[0] = 1.5  # the base twist's linear part, in the box's frame (unturned: the world's)
    traj = cgadyn.simulate(model, model.home, v0, DT, 1000, integrator=SIE, collisions=cm)
    assert traj.completed == 1000
    assert traj.q[-1, 0] == pytest.approx(0.35, abs=1e-4)
    assert traj.q[-1, 2] == pytest.approx(0.05, abs=1e-4)
    assert np.allclose(traj.q[-1, 3:], (0, 0, 0, 1), atol=1e-3)
    assert np.max(traj.energy) <= traj.energy[0] + 1e-9 * abs(traj.energy[0])
    wall = [c for c in traj.contacts(999) if c.other == "wall"]
    assert len(wall) >= 3 and all(np.allclose(c.normal, (-1, 0, 0)) for c in wall)
    assert all(c.force[0] <= 1e-9 for c in wall)
    data = mujoco.MjData(mj)
    data.qvel[0] = 1.5
    for _ in range(1000):
        mujoco.mj_step(mj, data)
    assert 0.335 < data.qpos[0] < 0.35 + 1e-3


def test_a_ball_rests_in_a_trough_of_two_walls():
    """Two plane obstacles, tilted by ±0.5 rad, make a V with no ground: a ball dropped
    into it rolls from wall to wall, then rests at its bottom after 3 s, its centre
    r / cos(0.5) above the edge (to 1e-4), held
    by one contact on each wall whose forces sum to its weight (1e-5 of it), and never gains
    energy."""
    a, r = 0.5, 0.05
    left = Obstacle(cgadyn.Plane((np.sin(a), 0, np.cos(a)), 0.0), name="left")
    right = Obstacle(cgadyn.Plane(), orientation=(0, -np.sin(a / 2), 0, np.cos(a / 2)),
                     name="right")
    ball = cgadyn.Body(cgadyn.Sphere(r), 1.0, position=(0.3, 0.0, 0.5))
    world = cgadyn.World(ground=False, bodies=[ball], obstacles=[left, right])
    traj = cgadyn.simulate(empty_model(), np.zeros(0), np.zeros(0), DT, 3000,
                           integrator=SIE, world=world)
    assert np.allclose(traj.q[-1, :3], (0, 0, r / np.cos(a)), atol=1e-4)
    assert np.max(traj.energy) <= traj.energy[0] + 1e-9 * abs(traj.energy[0])
    contacts = traj.contacts(2999)
    assert sorted(c.other for c in contacts) == ["left", "right"]
    total = np.sum([c.force for c in contacts], axis=0)
    assert np.allclose(total, (0, 0, 9.81), atol=1e-4)


def test_the_geoms_of_bodies_welded_to_the_world_are_the_worlds():
    """dm_control's manipulator: the geoms of its cup and slot, bodies without a joint, are
    shapes of the world as MuJoCo counts them (link -1, placed where MuJoCo's geom_xpos and
    geom_xmat put them at any state, to 1e-12), obstacles of its static world that its
    moving shapes touch without ``self_collision``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its actuators and couplings
        model = cgadyn.load("dm_control:manipulator")
        cm = cgadyn.collision_model(model)
    from cgadyn.multibody.registry import robot_path

    mj = mujoco.MjModel.from_xml_path(str(robot_path("dm_control:manipulator")))
    static = ["slot_0", "slot_1", "slot_2", "cup_0", "cup_1", "cup_2", "cup_3"]
    assert all(cm[cm.names.index(name)].link == -1 for name in static)
    data = mujoco.MjData(mj)
    rng = np.random.default_rng(5)
    for _ in range(3):
        data.qpos[:] = mj.qpos0 + rng.normal(scale=0.3, size=mj.nq)
        mujoco.mj_kinematics(mj, data)
        q, _ = cgadyn.from_mujoco_state(model, data.qpos, data.qvel)
        poses = cgadyn.collision_poses(model, cm, q)
        order = [mj.geom(name).id for name in cm.names]
        np.testing.assert_allclose(poses[:, :3, 3], data.geom_xpos[order], atol=1e-12)
        np.testing.assert_allclose(poses[:, :3, :3],
                                   data.geom_xmat[order].reshape(-1, 3, 3), atol=1e-12)
    world = static_world(cm)
    assert set(static) <= {o.name for o in world.obstacles}
    sc = scene_collisions(cm, world, model)
    paired = {sc.names[j] for i, j in candidate_pairs(sc, model.njoints)}
    assert set(static) <= paired


def test_a_rollout_stops_where_a_pairs_depth_is_not_computed():
    """A pair whose penetration depth is not computed (K9a: a few poses in ten thousand of
    a cylinder at a box's corner, which ones moving with the last bits of the pose) stops
    the rollout: ``failed_pair`` finds the first pair whose status is not OK in the
    detection's scratch, and the rollout's message names its two shapes."""
    from cgadyn.algorithms.status import CONTACT_PAIR, fault
    from cgadyn.sim.pairs import failed_pair
    from cgadyn.sim.simulate import _message

    pairs = np.array([[1, 0], [2, 0]], dtype=np.int64)
    status = np.zeros(2)
    ps = (np.zeros((2, 4, 4)), np.zeros(2), np.zeros((2, 3)), status, np.zeros((3, 4)),
          np.zeros(8), np.zeros(10), np.zeros(4), np.zeros((4, 4)))
    assert failed_pair(pairs, ps) == -1 and failed_pair(None, ps) == -1
    status[1] = 1.0  # PENETRATION_UNSUPPORTED
    assert failed_pair(pairs, ps) == 1
    model = empty_model()
    message = _message(model, np.array([fault(CONTACT_PAIR, 1)]), np.array([3]), DT, 5, 0,
                       np.zeros((8, 0)), np.zeros((1, 4, 0)), None, None,
                       [("body0", "box"), ("body1", "box")])
    assert "stopped after 3 of 5 steps" in message
    assert "the penetration depth of the shapes 'body1' and 'box' was not computed" in message
