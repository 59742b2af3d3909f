"""A trajectory as a self-contained HTML animation of the robot with its meshes.

The page is meshcat's three.js viewer (``main.min.js``, shipped in the ``meshcat`` wheel,
inlined) fed with meshcat's own scene commands (``set_object``, ``set_transform``,
``set_animation``, msgpack-encoded), which are written into the page as base64 strings in
one JSON ``<script>`` element: the file loads nothing from the network and plays offline.

Geometry comes from the URDF's ``<visual>`` elements (meshes in DAE, STL or OBJ, boxes,
cylinders, spheres), each placed at its link frame composed with the visual's ``<origin>``
(and ``scale``); a model without visuals is a skeleton of its joints with its collision
shapes (an MJCF model's geoms); the link frames per animation frame are
:func:`cgadyn.link_placements` of the trajectory, sampled at ``fps`` frames per second.
A rollout with a world adds its contact forces, one arrow per contact slot, animated with
the robot (position, direction and length keyframed with the links').
"""

from __future__ import annotations

import base64
import json
import math
import os
import uuid
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..multibody.meshes import model_source, resolve_mesh

__all__ = ["MissingViewer", "animation_frames", "require_viewer", "resolve_mesh", "visuals",
           "shape_visuals", "skeleton", "write_html"]

FPS = 30.0
"""Frames per second of the animation (the trajectory is sampled at these instants)."""

_MESH_FORMATS = {".dae": "dae", ".stl": "stl", ".obj": "obj"}
_DEFAULT_RGBA = (0.7, 0.7, 0.72, 1.0)


class MissingViewer(ImportError):
    """The optional ``viewer`` extra (meshcat) is not installed."""


def require_viewer():
    """meshcat's geometry module and its msgpack encoder; ``MissingViewer`` without them."""
    try:
        with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated ioloop
            warnings.simplefilter("ignore", DeprecationWarning)
            import meshcat.geometry as g
            import umsgpack
    except ImportError:
        raise MissingViewer("the HTML animation needs meshcat, which is not installed: "
                            "pip install 'cgadyn[viewer]' (or pip install meshcat)") from None
    return g, umsgpack


def _viewer_js() -> str:
    import meshcat

    path = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
    if not path.is_file():
        raise MissingViewer(f"meshcat's viewer script {str(path)!r} is missing; reinstall "
                            f"meshcat")
    return path.read_text(encoding="utf-8").replace("</script", "<\\/script")


# --- the URDF's visuals ---------------------------------------------------------------


def _urdf_source(model, urdf) -> tuple[bytes | None, Path | None]:
    """The URDF XML and its file (None for text) of ``model``: ``urdf`` if given, else
    the registry's file for the model's name; ``(None, None)`` for an MJCF model."""
    kind, xml, path = model_source(model, urdf)
    return (None, None) if kind == "mjcf" else (xml, path)


def _rgba(visual, materials: dict) -> tuple:
    mat = visual.material
    if mat is not None and mat.color is not None:
        return tuple(float(c) for c in mat.color.rgba)
    if mat is not None and mat.name in materials:
        return materials[mat.name]
    return _DEFAULT_RGBA


def visuals(model, urdf=None) -> list[dict]:
    """The URDF's visuals of every link of ``model``: dicts with ``link`` (index in
    ``model.link_names``), ``origin`` (4x4, scale included), ``kind`` (``'mesh'``,
    ``'box'``, ``'cylinder'``, ``'sphere'``), ``file`` and ``format`` (meshes),
    ``size`` (primitives) and ``rgba``."""
    from ..multibody.urdf import _parse

    xml, path = _urdf_source(model, urdf)
    if xml is None:  # MJCF: drawn as a skeleton (its geoms are not read)
        return []
    robot = _parse(xml, repr(str(path)) if path else "the URDF text")
    materials = {m.name: tuple(float(c) for c in m.color.rgba)
                 for m in robot.materials if m.color is not None}
    out = []
    for link in robot.links:
        if link.name not in model.link_names:
            continue
        li = model.link_names.index(link.name)
        for vis in link.visuals:
            origin = np.eye(4) if vis.origin is None else np.asarray(vis.origin, float)
            geo = vis.geometry
            item = {"link": li, "origin": origin, "rgba": _rgba(vis, materials)}
            if geo.mesh is not None:
                file = resolve_mesh(geo.mesh.filename, path)
                fmt = _MESH_FORMATS.get(file.suffix.lower())
                if fmt is None:
                    raise ValueError(f"mesh {str(file)!r}: format {file.suffix!r} is not "
                                     f"supported; expected .dae, .stl or .obj")
                scale = np.ones(3) if geo.mesh.scale is None else np.broadcast_to(
                    np.asarray(geo.mesh.scale, float), (3,))
                item.update(kind="mesh", file=file, format=fmt,
                            origin=origin @ np.diag([*scale, 1.0]))
            elif geo.box is not None:
                item.update(kind="box", size=[float(s) for s in geo.box.size])
            elif geo.cylinder is not None:
                item.update(kind="cylinder", size=[float(geo.cylinder.radius),
                                                    float(geo.cylinder.length)])
            elif geo.sphere is not None:
                item.update(kind="sphere", size=[float(geo.sphere.radius)])
            else:
                continue
            out.append(item)
    return out


_SKELETON_RGBA = (0.95, 0.55, 0.1, 1.0)


def _joint_anchor(model, j: int) -> tuple[int, np.ndarray] | None:
    """A link that moves with joint ``j`` (the world for -1) and the joint's frame in that
    link's frame: the link whose frame is the joint's where there is one (URDF), else the
    first link of the joint (an MJCF joint may sit anywhere in its body). None for the
    world of a robot that has no link fixed to it (a floating base), and for a joint that
    moves no link: one of an MJCF body's several joints but its last, whose massless body
    has nothing to draw (``multibody.mujoco_model``)."""
    attached = [li for li in range(model.nlinks) if model.link_joint[li] == j]
    for li in attached:
        if np.allclose(model.link_placement_matrices[li], np.eye(4)):
            return li, np.eye(4)
    if not attached:
        return None
    li = attached[0]
    return li, np.linalg.inv(np.asarray(model.link_placement_matrices[li], float))


def skeleton(model) -> list[dict]:
    """Visuals for a robot without any (a URDF without ``<visual>``, an MJCF model): a
    sphere at every joint frame and a cylinder from each joint frame's origin to its
    children's, fixed in the parent's link."""
    offsets = [np.asarray(model.placement_matrices[j][:3, 3]) for j in range(model.njoints)]
    lengths = [float(np.linalg.norm(p)) for p in offsets if np.linalg.norm(p) > 1e-9]
    r = 0.12 * (float(np.median(lengths)) if lengths else 0.5)
    out = []
    for j in range(model.njoints):
        anchor = _joint_anchor(model, j)
        if anchor is None:  # inside a body's chain of joints: drawn at the chain's last
            continue
        out.append({"link": anchor[0], "origin": anchor[1], "kind": "sphere", "size": [r],
                    "rgba": _SKELETON_RGBA})
        p, length = offsets[j], float(np.linalg.norm(offsets[j]))
        parent = _joint_anchor(model, int(model.parents[j]))
        if length < 1e-9 or parent is None:
            continue
        out.append({"link": parent[0], "origin": parent[1] @ _bone(p, length),
                    "kind": "cylinder", "size": [0.4 * r, length],
                    "rgba": (0.6, 0.6, 0.65, 1.0)})
    return out


SHAPE_RGBA = (0.8, 0.62, 0.42, 1.0)
"""The colour of collision shapes drawn for a model without visuals."""
WALL_RGBA = (0.55, 0.6, 0.7, 0.2)
"""The colour of a wall (a plane obstacle): see-through, so that it hides nothing."""
WALL_HALF_WIDTH = 1.5
"""Half the side of the square drawn for a wall (m): a plane has no edges of its own."""
WALL_THICKNESS = 0.005
"""The thickness of that square (m), drawn behind the wall's face."""


def shape_visuals(model, source=None) -> list[dict]:
    """Visuals for the collision shapes of a model without any (an MJCF model: its geoms,
    read through ``collision_model``): a sphere, a box, a cylinder, a capsule as a
    cylinder with a sphere at each end, an ellipsoid as a unit sphere scaled by its radii
    (in its static node's matrix), a convex mesh as its hull's triangles, each where its
    link carries it; none for a shape of the world (a floor: ``write_html``'s ``world``
    draws the obstacles), nor where the source holds no shapes."""
    import warnings

    from ..contact.model import collision_model

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cm = collision_model(model, source)
    except (ValueError, FileNotFoundError, OSError):
        return []
    return [v for c in cm if c.link >= 0 for v in _shape_visual(c.shape, c.pose, c.link)]


def _shape_visual(shape, placement, link: int) -> list[dict]:
    """The visuals of one collision ``shape`` at ``placement`` (4x4) in the frame of
    ``link`` (-1: the world): a sphere, a box, a cylinder, a capsule as a cylinder with a
    sphere at each end, an ellipsoid as a unit sphere scaled by its radii, a convex mesh
    as its hull's triangles, a plane (a wall) as a square ``2 WALL_HALF_WIDTH`` wide on
    its face."""
    from ..contact.shapes import BOX, CAPSULE, CYLINDER, ELLIPSOID, MESH, PLANE, SPHERE, frame_along

    T, size, kind = np.asarray(placement, dtype=float), shape.size, shape.kind
    if kind == SPHERE:
        return [{"link": link, "origin": T, "kind": "sphere", "size": [size[0]],
                 "rgba": SHAPE_RGBA}]
    if kind == ELLIPSOID:
        return [{"link": link, "origin": T @ np.diag([*size[:3], 1.0]), "kind": "sphere",
                 "size": [1.0], "rgba": SHAPE_RGBA}]
    if kind == BOX:
        return [{"link": link, "origin": T, "kind": "box",
                 "size": [2.0 * x for x in size[:3]], "rgba": SHAPE_RGBA}]
    if kind == MESH:
        return [{"link": link, "origin": T, "kind": "hull", "rgba": SHAPE_RGBA,
                 **_hull_triangles(np.asarray(shape.vertices))}]
    if kind == PLANE:  # a wall: a thin square of it about its point nearest the frame's origin
        n = np.asarray(shape.normal)
        face = T @ frame_along(n, shape.offset * n)
        face[:3, 3] -= face[:3, 2] * 0.5 * WALL_THICKNESS
        return [{"link": link, "origin": face, "kind": "box", "rgba": WALL_RGBA,
                 "size": [2.0 * WALL_HALF_WIDTH, 2.0 * WALL_HALF_WIDTH, WALL_THICKNESS]}]
    if kind not in (CYLINDER, CAPSULE):
        return []
    out = [{"link": link, "origin": T, "kind": "cylinder",  # along z, length 2 size[1]
            "size": [size[0], 2.0 * size[1]], "rgba": SHAPE_RGBA}]
    if kind == CAPSULE:
        for z in (-size[1], size[1]):
            end = T @ np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, z], [0, 0, 0, 1]])
            out.append({"link": link, "origin": end, "kind": "sphere", "size": [size[0]],
                        "rgba": SHAPE_RGBA})
    return out


def _hull_triangles(vertices: np.ndarray) -> dict:
    """The triangles of the convex hull of ``vertices`` (trimesh, i.e. qhull), each turned
    to face outwards (its normal away from the centroid), as ``{"vertices", "faces"}`` for
    three.js."""
    import trimesh

    hull = trimesh.convex.convex_hull(vertices)
    vertices, faces = np.asarray(hull.vertices, dtype=float), np.array(hull.faces)
    centre = vertices.mean(axis=0)
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a - centre) < 0.0
    faces[inward] = faces[inward][:, ::-1]
    return {"vertices": vertices.astype(np.float32), "faces": faces.astype(np.uint32)}


def _bone(p: np.ndarray, length: float) -> np.ndarray:
    """The frame of a cylinder from the origin to ``p`` (URDF cylinders lie along z): a
    capsule's between two points (``shapes.frame_along``)."""
    from ..contact.shapes import frame_along

    return frame_along(p / length, 0.5 * p)


# --- meshcat commands ---------------------------------------------------------------------


def _hex(rgba) -> int:
    r, g, b = (min(255, max(0, round(255 * c))) for c in rgba[:3])
    return (r << 16) | (g << 8) | b


def _object(vis: dict) -> dict:
    """The ``set_object`` payload of one visual (three.js JSON, meshcat's extensions)."""
    g, umsgpack = require_viewer()
    material = g.MeshPhongMaterial(color=_hex(vis["rgba"]), opacity=vis["rgba"][3],
                                   transparent=vis["rgba"][3] < 1)
    if vis["kind"] == "mesh" and vis["format"] in ("dae", "obj"):
        # meshcat's "_meshfile_object": the mesh with the materials of its own file
        return {"metadata": {"version": 4.5, "type": "Object"}, "geometries": [],
                "materials": [], "object": {"uuid": str(uuid.uuid1()),
                                            "type": "_meshfile_object",
                                            "format": vis["format"], "resources": {},
                                            "data": vis["file"].read_text(errors="replace")}}
    if vis["kind"] == "mesh":  # STL: its colour from the URDF
        data = umsgpack.Ext(0x12, vis["file"].read_bytes())  # meshcat's Uint8Array code
        geometry = g.MeshGeometry(data, "stl")
    elif vis["kind"] == "box":
        geometry = g.Box(vis["size"])
    elif vis["kind"] == "sphere":
        geometry = g.Sphere(vis["size"][0])
    elif vis["kind"] == "hull":  # a convex mesh: its hull's triangles
        geometry = g.TriangularMeshGeometry(vis["vertices"], vis["faces"])
    else:  # three.js cylinders lie along y, URDF's along z: turned in _visual_matrix
        geometry = g.Cylinder(vis["size"][1], vis["size"][0])
    return g.Mesh(geometry, material).lower()


def _visual_matrix(vis: dict) -> np.ndarray:
    if vis["kind"] == "cylinder":
        turn = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])
        return vis["origin"] @ turn
    return vis["origin"]


def _quaternion_xyzw(R: np.ndarray) -> list[float]:
    """The unit quaternion (x, y, z, w) of a rotation matrix, three.js's order."""
    from meshcat.transformations import quaternion_from_matrix

    T = np.eye(4)
    T[:3, :3] = R
    w, x, y, z = quaternion_from_matrix(T)
    return [float(x), float(y), float(z), float(w)]


def animation_frames(q: np.ndarray, dt: float, fps: float = FPS) -> np.ndarray:
    """Row indices of ``q`` (states ``dt`` apart) shown at ``fps`` frames per second:
    the states nearest to ``0, 1/fps, 2/fps, ...`` and always the last one."""
    n = len(q)
    duration = (n - 1) * dt
    count = int(math.floor(duration * fps + 1e-9)) + 1
    idx = np.minimum(np.rint(np.arange(count) / (fps * dt)).astype(np.int64), n - 1)
    if idx[-1] != n - 1:
        idx = np.append(idx, n - 1)
    return idx


def _commands(model, q: np.ndarray, dt: float, fps: float, urdf,
              loop: bool, contacts=None, world=None) -> tuple[list[dict], dict]:
    from ..algorithms.api import link_placements

    vis = visuals(model, urdf) or skeleton(model) + shape_visuals(model, urdf)
    rows = animation_frames(q, dt, fps)
    T = np.asarray(link_placements(model, q[rows]))  # (F, nl, 4, 4)
    links = sorted({v["link"] for v in vis})
    path = {li: f"/cgadyn/{model.name}/{model.link_names[li]}" for li in links}
    cmds: list[dict] = []
    for i, v in enumerate(vis):
        node = f"{path[v['link']]}/visual_{i}"
        cmds.append({"type": "set_object", "path": node, "object": _object(v)})
        cmds.append({"type": "set_transform", "path": node,
                     "matrix": [float(x) for x in _visual_matrix(v).T.ravel()]})
    times = rows * dt * fps  # keyframe times in frames of the clip (three.js divides by fps)
    animations = []
    for li in links:
        pos = T[:, li, :3, 3]
        quat = [_quaternion_xyzw(R) for R in T[:, li, :3, :3]]
        cmds.append({"type": "set_transform", "path": path[li],
                     "matrix": [float(x) for x in T[0, li].T.ravel()]})
        tracks = [{"name": ".position", "type": "vector3",
                   "keys": [{"time": float(t), "value": [float(x) for x in p]}
                            for t, p in zip(times, pos, strict=True)]},
                  {"name": ".quaternion", "type": "quaternion",
                   "keys": [{"time": float(t), "value": r}
                            for t, r in zip(times, quat, strict=True)]}]
        animations.append({"path": path[li], "clip": {"fps": float(fps), "name": "default",
                                                      "tracks": tracks}})
    framing, shift = _framing(T, vis)
    if shift is not None:  # a robot that travels far: the page's camera follows this node
        cmds.append({"type": "set_transform", "path": FOLLOW, "matrix": IDENTITY})
        animations.append({"path": FOLLOW, "clip": {
            "fps": float(fps), "name": "default", "tracks": [
                {"name": ".position", "type": "vector3",
                 "keys": [{"time": float(t), "value": [float(x) for x in p]}
                          for t, p in zip(times, shift, strict=True)]}]}})
    if contacts is not None:
        arrows, clips = _contact_arrows(model, contacts, rows, times, fps, framing)
        cmds += arrows
        animations += clips
    cmds.append({"type": "set_animation", "path": "", "animations": animations,
                 "options": {"play": True, "repetitions": 1_000_000 if loop else 1}})
    cmds.append({"type": "set_property", "path": "/Axes", "property": "visible",
                 "value": False})
    if world is not None:
        cmds += _obstacles(world)
        if world.ground:  # the grid on the World's ground (level: a tilted one at its z)
            framing["floor"] = float(world.ground_height)
    cmds += _floor(framing)
    return cmds, framing


def _obstacles(world) -> list[dict]:
    """Static nodes for the World's obstacles (``contact.obstacles``), each shape drawn
    where it stands (``_shape_visual``; a convex mesh is not drawn)."""
    from ..contact.obstacles import obstacle_names

    cmds: list[dict] = []
    for k, (o, name) in enumerate(zip(world.obstacles, obstacle_names(world.obstacles),
                                      strict=True)):
        label = "".join(ch if ch.isalnum() or ch in "_-" else "_" for ch in name)
        for i, v in enumerate(_shape_visual(o.shape, o.pose @ o.shape.placement, -1)):
            node = f"/cgadyn/world/{k}_{label}/visual_{i}"
            cmds.append({"type": "set_object", "path": node, "object": _object(v)})
            cmds.append({"type": "set_transform", "path": node,
                         "matrix": [float(x) for x in _visual_matrix(v).T.ravel()]})
    return cmds


CONTACT_RGBA = (0.85, 0.15, 0.1, 1.0)
"""The colour of the contact force arrows."""
HIDDEN = 1e-9
"""The scale of an arrow whose slot holds no contact in a frame: too small to draw."""


def _contact_arrows(model, contacts, rows, times, fps: float,
                    framing: dict) -> tuple[list[dict], list[dict]]:
    """One arrow per contact slot that holds a contact in any frame (``contacts(k)``: the
    ``ContactPoint``s of state k, a trajectory's ``contacts``): the force on the robot,
    pushing at the contact point (the arrow ends there, outside the body it pushes), the
    robot's weight as long as the robot's size (capped at twice it), animated with the
    robot; hidden (``HIDDEN`` scale) in the frames where its slot holds no force; none for
    a slot whose contacts never push. Returns the arrows' commands and their animation
    clips."""
    g, _ = require_viewer()
    per_frame = [{c.slot: c for c in contacts(int(r))} for r in rows]
    slots = sorted({slot for frame in per_frame for slot in frame})
    radius = framing["radius"]
    weight = max(model.total_mass * 9.81, 1e-12)
    per_newton = radius / weight
    cmds: list[dict] = []
    clips: list[dict] = []
    for slot in slots:
        node = f"/cgadyn/contacts/slot_{slot}"
        shown = [frame.get(slot) for frame in per_frame]
        shown = [c if c is not None and np.all(np.isfinite(c.force))
                 and np.linalg.norm(c.force) > 0.0 else None for c in shown]
        if all(c is None for c in shown):  # found, but never pushing: no arrow
            continue
        shaft = g.Cylinder(1.0, 0.02 * radius)  # along y, centred: moved up by half
        cmds.append({"type": "set_object", "path": f"{node}/shaft",
                     "object": g.Mesh(shaft, g.MeshLambertMaterial(
                         color=_hex(CONTACT_RGBA))).lower()})
        cmds.append({"type": "set_transform", "path": f"{node}/shaft",
                     "matrix": [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0.5, 0, 1.0]})
        points = _filled([None if c is None else np.asarray(c.point, dtype=float)
                          for c in shown])
        pos, quat, scale = [], [], []
        for c, p in zip(shown, points, strict=True):
            if c is None:
                pos.append([float(x) for x in p])
                quat.append([0.0, 0.0, 0.0, 1.0])
                scale.append([HIDDEN] * 3)
                continue
            f = np.asarray(c.force, dtype=float)
            d = f / np.linalg.norm(f)
            length = min(float(np.linalg.norm(f)) * per_newton, 2.0 * radius)
            pos.append([float(x) for x in p - length * d])  # the tail; the head at p
            quat.append(_quaternion_y_to(d))
            scale.append([1.0, length, 1.0])
        tracks = [{"name": f".{name}", "type": kind,
                   "keys": [{"time": float(t), "value": v} for t, v in zip(times, values,
                                                                          strict=True)]}
                  for name, kind, values in (("position", "vector3", pos),
                                             ("quaternion", "quaternion", quat),
                                             ("scale", "vector3", scale))]
        clips.append({"path": node, "clip": {"fps": float(fps), "name": "default",
                                             "tracks": tracks}})
    return cmds, clips


def _filled(points: list) -> list[np.ndarray]:
    """``points`` (one at least not None) with each None replaced by the nearest point
    before it (after it, at the start), so that a hidden arrow waits where its slot's
    contact appears or left."""
    last = next(p for p in points if p is not None)
    out = []
    for p in points:
        last = p if p is not None else last
        out.append(last)
    return out


def _quaternion_y_to(d: np.ndarray) -> list[float]:
    """The unit quaternion ``(x, y, z, w)`` of the shortest turn of the y axis onto the unit
    vector ``d``: ``(y × d, 1 + y · d)`` normalised (the half-way rotor); a half turn about
    x where d is -y."""
    x, y, z, w = d[2], 0.0, -d[0], 1.0 + d[1]  # y × d = (d_z, 0, -d_x)
    norm = math.sqrt(x * x + z * z + w * w)
    if norm < 1e-12:
        return [1.0, 0.0, 0.0, 0.0]
    return [float(x / norm), y, float(z / norm), float(w / norm)]


FOLLOW = "/cgadyn/follow"
"""An empty node whose animated position is the shift of the camera that follows a robot
travelling far (``_framing``); the page moves the camera and its target by it (``_PAGE``),
so that the user's own turns and zooms keep working."""
IDENTITY = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]


def _framing(T: np.ndarray, vis: list[dict]) -> tuple[dict, np.ndarray | None]:
    """Centre and radius (metres) for the camera: the box swept by the visuals' origins,
    or, when the robot travels more than three times its own size, the box they sweep
    about the camera that follows it;
    and the height of the floor grid: z = 0 where that is near, else under the robot; and
    the extent of the grid in x and y (``floor_box``: its corners). For a robot that
    travels far, also the camera's shift at each frame (F, 3): how far the centre of its
    box has moved in x and y since the first frame, so that the camera follows it across
    a grid that covers its path (None otherwise)."""
    pts = np.stack([(T[:, v["link"]] @ v["origin"])[:, :3, 3] for v in vis], axis=1)

    def box(p):
        lo, hi = p.min(axis=0), p.max(axis=0)
        return 0.5 * (lo + hi), max(0.5 * float(np.linalg.norm(hi - lo)), 0.1) * 1.15

    center, radius = box(pts.reshape(-1, 3))
    c0, r0 = box(pts[0])
    framed, shift = pts, None
    if radius > 3 * r0:  # framed as the following camera sees it: its shift taken out
        shift = 0.5 * (pts.min(axis=1) + pts.max(axis=1)) - c0
        shift[:, 2] = 0.0  # along the ground: the camera does not bob with the robot
        framed = pts - shift[:, None, :]
        center, radius = box(framed.reshape(-1, 3))
    near = center[2] - 3 * radius <= 0.0 <= center[2] + radius  # the world's z = 0 in view
    floor = 0.0 if near else float(framed[..., 2].min())
    path = center[:2] + (np.zeros((1, 2)) if shift is None else shift[:, :2])
    return {"center": [float(c) for c in center], "radius": radius, "floor": floor,
            "floor_box": [[float(x) for x in path.min(axis=0)],
                          [float(x) for x in path.max(axis=0)]],
            "follows": shift is not None}, shift


def _floor(framing: dict) -> list[dict]:
    """A floor grid under the robot, sized to it (and long enough for its path where the
    camera follows it: ``floor_box``), in place of meshcat's 20 m one: some of
    that one's lines always pass behind the camera, and renderers that drop such lines
    instead of clipping them (headless Chromium's) drew only its far edge, which looked
    like a ceiling seen from below."""
    g, _ = require_viewer()
    (xl, yl), (xh, yh) = framing["floor_box"]  # the robot's centre: one point or its path
    r = framing["radius"]
    cell = _nice_step(r / 3.0)
    n = int(math.ceil(1.6 * r / cell))
    x0, x1 = math.floor(xl / cell) - n, math.ceil(xh / cell) + n  # in cells
    y0, y1 = math.floor(yl / cell) - n, math.ceil(yh / cell) + n
    lines = []
    for i in range(x0, x1 + 1):
        lines += [(i * cell, y0 * cell), (i * cell, y1 * cell)]
    for i in range(y0, y1 + 1):
        lines += [(x0 * cell, i * cell), (x1 * cell, i * cell)]
    points = np.array([[x, y, framing["floor"]] for x, y in lines], dtype=np.float32).T
    grid = g.LineSegments(g.PointsGeometry(points), g.LineBasicMaterial(color=0x8a8a8a))
    return [{"type": "set_property", "path": "/Grid", "property": "visible", "value": False},
            {"type": "set_object", "path": "/cgadyn/floor", "object": grid.lower()}]


def _nice_step(x: float) -> float:
    """The step of 1, 2 or 5 times a power of ten nearest below ``x``."""
    power = 10.0 ** math.floor(math.log10(x))
    return max(m * power for m in (1.0, 2.0, 5.0) if m * power <= x)


_PAGE = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title>
<style>body {{ margin: 0; }} #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#cgadyn-caption {{ position: absolute; left: 8px; bottom: 8px; font: 13px sans-serif;
color: #fff; text-shadow: 0 0 3px #000; }}</style></head>
<body>
<div id="meshcat-pane"></div>
<div id="cgadyn-caption">{caption}</div>
<script>{viewer_js}</script>
<script type="application/json" id="cgadyn-animation">{meta}</script>
<script type="application/json" id="cgadyn-commands">{commands}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
JSON.parse(document.getElementById("cgadyn-commands").textContent).forEach(function (b64) {{
  var s = atob(b64), bytes = new Uint8Array(s.length);
  for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
  viewer.handle_command_bytearray(bytes);
}});
// the camera frames the swept volume from above, looking down at it; its frame (under
// /Cameras/default/rotated) is y-up: world (x, y, z) is (x, z, -y) there
var meta = JSON.parse(document.getElementById("cgadyn-animation").textContent);
var c = meta.center, r = meta.radius, h = Math.max(c[2] + 1.6 * r, meta.floor + 0.8 * r);
viewer.controls.target.set(c[0], c[2], -c[1]);
viewer.camera.position.set(c[0] + 2.0 * r, h, -c[1] + 1.5 * r);
viewer.controls.update();
viewer.set_dirty();
// a robot that travels far: camera and target move by the follow node's shift (z-up, so
// world (dx, dy) is (dx, -dy) in the camera's y-up frame), the user's turns kept
if (meta.follows) {{
  var follow = viewer.scene_tree.find(["cgadyn", "follow"]).object, last = [0.0, 0.0];
  (function track() {{
    var dx = follow.position.x - last[0], dy = follow.position.y - last[1];
    if (dx !== 0 || dy !== 0) {{
      last = [follow.position.x, follow.position.y];
      viewer.camera.position.x += dx; viewer.camera.position.z -= dy;
      viewer.controls.target.x += dx; viewer.controls.target.z -= dy;
      viewer.controls.update();
      viewer.set_dirty();
    }}
    requestAnimationFrame(track);
  }})();
}}
</script>
</body>
</html>
"""


def write_html(model, q, dt: float, path: str | os.PathLike, urdf=None, fps: float = FPS,
               loop: bool = True, title: str | None = None, contacts=None,
               world=None) -> Path:
    """Write a self-contained HTML page that animates ``model`` through the states ``q``.

    ``q`` : (T, nq) configurations ``dt`` seconds apart (a trajectory's ``q``).
    ``contacts`` : the contacts of state k as ``contacts(k)`` (a trajectory's ``contacts``,
    of a rollout with a world): drawn as arrows of their forces on the robot.
    ``world`` : the ``cgadyn.World`` of the rollout: its obstacles drawn where they stand,
    the floor grid at its ground's height.
    ``urdf`` : the URDF file (or text) ``model`` was loaded from, to find its visuals;
    default: the registry's file for ``model.name``.
    ``fps`` : animation frames per second (the states nearest those instants are shown).
    A URDF without ``<visual>`` is drawn as a :func:`skeleton`.
    Raises :class:`MissingViewer` without meshcat, ``ValueError`` for bad ``q``/``dt``/
    ``fps`` or a URDF without visuals, ``FileNotFoundError`` for a missing mesh.
    """
    require_viewer()
    q = np.asarray(q, dtype=float)
    if q.ndim != 2 or q.shape[1] != model.nq or len(q) < 1:
        raise ValueError(f"q must be a trajectory of shape (T, nq) = (T, {model.nq}) with "
                         f"T >= 1, got shape {q.shape}")
    if not np.all(np.isfinite(q)):
        raise ValueError("q holds non-finite values; cut the trajectory where it diverged")
    for name, value in (("dt", dt), ("fps", fps)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    out = Path(path)
    if not out.parent.is_dir():
        raise FileNotFoundError(f"cannot write {str(out)!r}: directory {str(out.parent)!r} "
                                f"does not exist")
    _, umsgpack = require_viewer()
    if world is not None:
        from ..contact.world import World

        if not isinstance(world, World):
            raise ValueError(f"world must be a cgadyn.World, got {world!r}")
    cmds, framing = _commands(model, q, float(dt), float(fps), urdf, loop, contacts, world)
    blobs = [base64.b64encode(umsgpack.packb(c)).decode("ascii") for c in cmds]
    duration = (len(q) - 1) * dt
    meta = {"robot": model.name, "fps": fps, "frames": int(len(animation_frames(q, dt, fps))),
            "duration": duration, "links": _animated_links(cmds), **framing}
    page = _PAGE.format(title=_escape(title or f"cgadyn: {model.name}"),
                        caption=_escape(title or f"cgadyn simulate {model.name}: "
                                        f"{duration:.3g} s"),
                        viewer_js=_viewer_js(), meta=json.dumps(meta),
                        commands=json.dumps(blobs))
    out.write_text(page, encoding="utf-8")
    return out


def _animated_links(cmds: Sequence[dict]) -> list[str]:
    return [a["path"].rsplit("/", 1)[-1] for c in cmds if c["type"] == "set_animation"
            for a in c["animations"]]


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
