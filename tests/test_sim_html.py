"""The HTML animation (``cgadyn.sim.html``): self-contained (nothing loaded from the
network), its frames are the link placements of the trajectory composed with the URDF's
visual origins, and headless Chromium shows the robot in its colours."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest

import cgadyn
from cgadyn.sim import html

umsgpack = pytest.importorskip("umsgpack", reason="the viewer extra (meshcat) is not installed")
pytest.importorskip("meshcat", reason="the viewer extra (meshcat) is not installed")

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") \
    or shutil.which("google-chrome")


def _pendulum_trajectory(model, n: int = 301, dt: float = 0.01) -> np.ndarray:
    t = dt * np.arange(n)
    q = np.zeros((n, model.nq))
    q[:, 0] = 1.0 * np.cos(2.0 * t)
    q[:, 1] = -0.5 + 0.3 * np.sin(3.0 * t)
    return q


def _page_parts(text: str) -> tuple[dict, list[dict]]:
    def script(name):
        m = re.search(rf'<script type="application/json" id="{name}">(.*?)</script>', text,
                      re.S)
        assert m, f"no <script id={name}>"
        return json.loads(m.group(1))

    cmds = [umsgpack.unpackb(base64.b64decode(b)) for b in script("cgadyn-commands")]
    return script("cgadyn-animation"), cmds


@pytest.fixture(scope="module")
def pendulum_page(tmp_path_factory):
    model = cgadyn.load("double_pendulum")
    q = _pendulum_trajectory(model)
    path = html.write_html(model, q, 0.01, tmp_path_factory.mktemp("html") / "dp.html")
    return model, q, path


def test_page_is_self_contained(pendulum_page):
    _, _, path = pendulum_page
    text = path.read_text(encoding="utf-8")
    assert text.lstrip().startswith("<!DOCTYPE html>")
    # nothing is fetched: no external script, stylesheet, image, import or fetch
    assert not re.search(r"<(script|link|img|iframe)[^>]*\b(src|href)\s*=", text, re.I)
    assert not re.search(r"""(fetch|import)\s*\(\s*["'`]https?:""", text, re.I)
    assert not re.search(r"""url\(\s*["']?https?:""", text, re.I)
    assert not re.search(r"""\bfrom\s+["']https?:""", text)
    assert "MeshCat.Viewer" in text and "handle_command_bytearray" in text


def test_frames_are_link_placements_with_visual_origins(pendulum_page):
    model, q, path = pendulum_page
    meta, cmds = _page_parts(path.read_text(encoding="utf-8"))
    rows = html.animation_frames(q, 0.01, html.FPS)
    assert meta["frames"] == len(rows) == 91  # 3 s at 30 frames per second
    assert rows[0] == 0 and rows[-1] == len(q) - 1
    (anim,) = [c for c in cmds if c["type"] == "set_animation"]
    T = cgadyn.link_placements(model, q[rows])
    vis = html.visuals(model)
    assert {v["kind"] for v in vis} == {"mesh"} and len(vis) == 3  # base and two links
    animated = {model.link_names[v["link"]] for v in vis}
    assert set(meta["links"]) == animated
    for a in anim["animations"]:
        li = model.link_names.index(a["path"].rsplit("/", 1)[-1])
        pos = {t["name"]: t for t in a["clip"]["tracks"]}[".position"]["keys"]
        quat = {t["name"]: t for t in a["clip"]["tracks"]}[".quaternion"]["keys"]
        assert [k["time"] for k in pos] == pytest.approx(rows * 0.01 * html.FPS)
        np.testing.assert_allclose([k["value"] for k in pos], T[:, li, :3, 3], atol=1e-12)
        # the quaternion (x, y, z, w) rotates like the link's rotation matrix
        for k, R in zip(quat, T[:, li, :3, :3], strict=True):
            x, y, z, w = k["value"]
            Rq = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                           [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                           [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
            np.testing.assert_allclose(Rq, R, atol=1e-12)
    # each visual sits at its URDF origin in its link's frame, with the mesh's bytes inline
    objects = [c for c in cmds if c["type"] == "set_object" and c["path"] != "/cgadyn/floor"]
    assert len(objects) == len(vis)
    for c, v in zip(objects, vis, strict=True):
        data = c["object"]["geometries"][0]["data"]
        payload = data.data if hasattr(data, "data") else data
        assert bytes(payload) == v["file"].read_bytes()


def test_bad_inputs_are_refused(tmp_path):
    model = cgadyn.load("double_pendulum")
    q = np.zeros((5, 2))
    with pytest.raises(ValueError, match=r"shape \(T, nq\)"):
        html.write_html(model, np.zeros((5, 3)), 0.01, tmp_path / "a.html")
    with pytest.raises(ValueError, match="dt must be a positive"):
        html.write_html(model, q, 0.0, tmp_path / "a.html")
    bad = q.copy()
    bad[2, 0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        html.write_html(model, bad, 0.01, tmp_path / "a.html")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        html.write_html(model, q, 0.01, tmp_path / "no" / "a.html")
    with pytest.raises(FileNotFoundError, match="mesh 'package://nowhere/x.stl'"):
        html.resolve_mesh("package://nowhere/x.stl", None)


def screenshot(page: Path, png: Path, size=(800, 600), budget_ms: int = 3000) -> None:
    """Render ``page`` in headless Chromium with every host name unresolvable (offline)."""
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
             "--no-first-run", "--disable-background-networking", "--disable-component-update",
             "--disable-sync", "--host-resolver-rules=MAP * ~NOTFOUND",
             f"--user-data-dir={profile}", f"--virtual-time-budget={budget_ms}",
             f"--window-size={size[0]},{size[1]}", f"--screenshot={png}", page.as_uri()],
            capture_output=True, timeout=120, check=False)


def robot_pixels(png: Path) -> dict:
    """Fractions of the picture in the double pendulum's colours (yellow base, grey links),
    the count of red pixels (contact arrows) and of distinct colours; meshcat's background
    is a blue gradient."""
    import matplotlib.image as mpimg

    img = (mpimg.imread(png)[..., :3] * 255).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    yellow = (r > 180) & (g > 180) & (b < 90)
    grey = (np.abs(r - g) < 12) & (np.abs(g - b) < 12) & (r > 120)
    red = (r > 150) & (g < 80) & (b < 80)  # the contact arrows (html.CONTACT_RGBA)
    return {"yellow": float(yellow.mean()), "grey": float(grey.mean()),  # empty scene: 0, 0.005
            "red": int(red.sum()), "colours": len(np.unique(img.reshape(-1, 3), axis=0))}


@pytest.mark.slow
@pytest.mark.browser
@pytest.mark.skipif(CHROMIUM is None, reason="no chromium to render the page")
def test_chromium_shows_the_robot(pendulum_page, tmp_path):
    _, _, path = pendulum_page
    png = tmp_path / "shot.png"
    screenshot(path, png)
    assert png.is_file() and png.stat().st_size > 0, "chromium wrote no screenshot"
    px = robot_pixels(png)
    assert px["colours"] > 200, f"blank page: {px}"
    assert px["yellow"] > 1e-3, f"the pendulum's yellow base is not visible: {px}"
    assert px["grey"] > 1.2e-2, f"the pendulum's grey links are not visible: {px}"


def test_urdf_without_visuals_is_drawn_as_a_skeleton(tmp_path):
    model = cgadyn.load("cart_pole")  # the project's own URDF: no <visual>
    assert html.visuals(model) == []
    sk = html.skeleton(model)
    assert [v["kind"] for v in sk].count("sphere") == model.njoints
    T0 = cgadyn.link_placements(model, np.zeros(model.nq))
    for v in sk:
        if v["kind"] == "cylinder":  # from its link's origin to a child joint's origin
            radius, length = v["size"]
            end = (T0[v["link"]] @ v["origin"] @ [0, 0, length / 2, 1])[:3]
            starts = [T0[v["link"]][:3, 3]]
            assert np.allclose((T0[v["link"]] @ v["origin"] @ [0, 0, -length / 2, 1])[:3],
                               starts[0], atol=1e-12)
            assert any(np.allclose(end, T0[li][:3, 3], atol=1e-12)
                       for li in range(model.nlinks))
    path = html.write_html(model, np.zeros((11, model.nq)), 0.1, tmp_path / "cp.html")
    _, cmds = _page_parts(path.read_text(encoding="utf-8"))
    assert sum(c["type"] == "set_object" and c["path"] != "/cgadyn/floor"
               for c in cmds) == len(sk)


def test_an_mjcf_model_is_drawn_as_a_skeleton_at_its_joints():
    """MJCF has no URDF visuals to read (``simulate --html`` refused it): a sphere at each
    joint's origin, a cylinder from each joint to its children, in the right links."""
    path = Path(__file__).resolve().parents[1] / "robots" / "slide_arm.xml"
    model = cgadyn.load(str(path))
    assert html.visuals(model, path) == []
    sk = html.skeleton(model)
    q = np.array([0.3, -0.4, 0.0, 0.7])  # the slide at 0: its bone ends at its origin
    T = cgadyn.link_placements(model, q)
    joints, _ = cgadyn.forward_kinematics(model, q)
    origins = np.array([cgadyn.matrix_from_motor(m)[:3, 3] for m in joints])
    spheres = [(T[v["link"]] @ v["origin"])[:3, 3] for v in sk if v["kind"] == "sphere"]
    np.testing.assert_allclose(spheres, origins, atol=1e-12)
    for v in sk:
        if v["kind"] == "cylinder":  # ends at a joint and at one of its children
            frame = T[v["link"]] @ v["origin"]
            ends = [(frame @ [0, 0, z * v["size"][1] / 2, 1])[:3] for z in (-1, 1)]
            assert min(np.linalg.norm(origins - ends[1], axis=1)) < 1e-12
            assert min(np.linalg.norm(np.vstack([origins, [0, 0, 0]]) - ends[0],
                                      axis=1)) < 1e-12


def test_the_floor_is_a_grid_under_the_robot_seen_from_above(pendulum_page):
    """meshcat's 20 m grid is hidden (renderers that drop lines passing behind the camera
    showed only its far edge, like a ceiling seen from below); a grid sized to the robot
    lies at z = 0 and the camera looks down on it from above."""
    _, _, path = pendulum_page
    text = path.read_text(encoding="utf-8")
    meta, cmds = _page_parts(text)
    assert {"type": "set_property", "path": "/Grid", "property": "visible",
            "value": False} in cmds
    (floor,) = [c for c in cmds if c.get("path") == "/cgadyn/floor"]
    points = np.frombuffer(floor["object"]["geometries"][0]["data"]["attributes"]["position"]
                           ["array"].data, dtype=np.float32).reshape(-1, 3)
    assert meta["floor"] == 0.0 and np.all(points[:, 2] == 0.0)
    c, r = np.array(meta["center"]), meta["radius"]
    assert np.abs(points[:, :2] - c[:2]).max() < 2.5 * r  # about the robot, not 20 m
    assert "h = Math.max(c[2] + 1.6 * r, meta.floor + 0.8 * r)" in text  # camera above it


@pytest.fixture(scope="module")
def standing_page(tmp_path_factory):
    """solo12 standing on the ground for 0.3 s, its contact forces drawn."""
    from contact_cases import solo12_on_the_ground

    model, cm, q = solo12_on_the_ground()
    pd = cgadyn.PD(kp=20.0, kd=0.5, q_ref=q, gravity_compensation=False)
    traj = cgadyn.simulate(model, q, np.zeros(model.nv), 1e-3, 300, controller=pd,
                           integrator="semi_implicit_euler", world=cgadyn.World(),
                           collisions=cm)
    path = html.write_html(model, traj.q, 1e-3, tmp_path_factory.mktemp("html") / "solo.html",
                           contacts=traj.contacts)
    return model, traj, path


def test_contact_forces_are_arrows_ending_at_their_points(standing_page):
    """One clip per contact slot: at each frame the arrow's head (its tail plus its length
    along the force) is the contact point, its length the force times the robot's size
    over its weight; hidden where the slot holds no contact."""
    model, traj, path = standing_page
    meta, cmds = _page_parts(path.read_text(encoding="utf-8"))
    clips = [a for c in cmds if c["type"] == "set_animation" for a in c["animations"]
             if a["path"].startswith("/cgadyn/contacts/")]
    rows = html.animation_frames(traj.q, 1e-3)
    seen = {c.slot for r in rows for c in traj.contacts(int(r))}
    assert len(seen) >= 4 and {a["path"] for a in clips} == {
        f"/cgadyn/contacts/slot_{s}" for s in seen}
    per_newton = meta["radius"] / (model.total_mass * 9.81)
    for a in clips:
        slot = int(a["path"].rsplit("_", 1)[1])
        pos, quat, scale = ([k["value"] for k in t["keys"]] for t in a["clip"]["tracks"])
        for i, r in enumerate(rows):
            c = next((c for c in traj.contacts(int(r)) if c.slot == slot), None)
            if c is None or not np.all(np.isfinite(c.force)) or not np.any(c.force):
                assert scale[i] == [html.HIDDEN] * 3
                continue
            x, y, z, w = quat[i]
            up = np.array([2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)])
            np.testing.assert_allclose(up, c.force / np.linalg.norm(c.force), atol=1e-9)
            assert scale[i][1] == pytest.approx(np.linalg.norm(c.force) * per_newton)
            np.testing.assert_allclose(np.array(pos[i]) + scale[i][1] * up, c.point,
                                       atol=1e-12)


@pytest.mark.slow
@pytest.mark.browser
@pytest.mark.skipif(CHROMIUM is None, reason="no chromium to render the page")
def test_chromium_shows_the_contact_forces(standing_page, tmp_path):
    _, _, path = standing_page
    png = tmp_path / "shot.png"
    screenshot(path, png, budget_ms=1500)
    red = robot_pixels(png)["red"]
    assert red > 50, f"no contact arrow drawn: {red} red pixels"


def test_a_slot_that_never_pushes_has_no_arrow(tmp_path):
    """A contact found within the margin but carrying no force in any frame (zero, or NaN at
    the last state, whose step was never taken) draws nothing and breaks nothing."""
    from types import SimpleNamespace

    model = cgadyn.load("double_pendulum")
    q = _pendulum_trajectory(model, n=31)

    def contacts(k):
        push = np.array([0.0, 0.0, 5.0 if k >= 10 else 0.0])
        return [SimpleNamespace(slot=0, point=np.zeros(3), force=np.zeros(3)),
                SimpleNamespace(slot=1, point=np.ones(3), force=np.full(3, np.nan)),
                SimpleNamespace(slot=4, point=np.ones(3), force=push)]

    path = html.write_html(model, q, 0.01, tmp_path / "dp.html", contacts=contacts)
    _, cmds = _page_parts(path.read_text(encoding="utf-8"))
    clips = [a for c in cmds if c["type"] == "set_animation" for a in c["animations"]
             if a["path"].startswith("/cgadyn/contacts/")]
    assert [a["path"] for a in clips] == ["/cgadyn/contacts/slot_4"]
    scale = [k["value"] for k in clips[0]["clip"]["tracks"][2]["keys"]]
    assert scale[0] == [html.HIDDEN] * 3 and scale[-1][1] > 0.0


def test_an_mjcf_model_is_drawn_with_its_geoms(tmp_path):
    """Gymnasium's Ant (MJCF: no URDF visuals) is drawn as its skeleton and its geoms: the
    torso's sphere, and each leg's capsules as a cylinder between two spheres at the
    capsule's ends, in its link; its floor (a geom of the world) is not drawn."""
    pytest.importorskip("mujoco", reason="MJCF through MuJoCo's compiler")
    model = cgadyn.load("gymnasium:ant")
    shapes = html.shape_visuals(model, "gymnasium:ant")
    kinds = [v["kind"] for v in shapes]
    assert kinds.count("cylinder") == 12 and kinds.count("sphere") == 1 + 2 * 12
    assert all(v["link"] >= 0 for v in shapes)
    q = cgadyn.neutral(model)
    T = cgadyn.link_placements(model, q)
    cm = cgadyn.collision_model(model, "gymnasium:ant")
    capsules = [c for c in cm if c.link >= 0 and c.shape.name == "capsule"]
    ends = [(T[v["link"]] @ v["origin"])[:3, 3] for v in shapes if v["kind"] == "sphere"]
    for c in capsules:  # both ends of each capsule's segment carry a sphere
        for z in (-c.shape.size[1], c.shape.size[1]):
            p = (T[c.link] @ np.asarray(c.placement) @ [0.0, 0.0, z, 1.0])[:3]
            assert min(np.linalg.norm(np.array(ends) - p, axis=1)) < 1e-12
    path = html.write_html(model, np.tile(q, (3, 1)), 0.01, tmp_path / "ant.html",
                           urdf="gymnasium:ant")
    _, cmds = _page_parts(path.read_text(encoding="utf-8"))
    drawn = sum(c["type"] == "set_object" and c["path"] != "/cgadyn/floor" for c in cmds)
    assert drawn == len(html.skeleton(model)) + len(shapes)


@pytest.fixture(scope="module")
def travelling_page(tmp_path_factory):
    """The double pendulum on a free-flyer base carried 20 m along x in 2 s, swinging."""
    model = cgadyn.load("double_pendulum", floating_base=True)
    n = 201
    q = np.zeros((n, model.nq))
    q[:, 0], q[:, 6] = np.linspace(0.0, 20.0, n), 1.0
    q[:, 7:] = _pendulum_trajectory(cgadyn.load("double_pendulum"), n)
    path = html.write_html(model, q, 0.01, tmp_path_factory.mktemp("html") / "far.html",
                           loop=False)
    return model, q, path


def test_the_camera_follows_a_robot_that_travels_far(travelling_page):
    """The follow node's keys are the robot's shift along the ground (its x here, z never),
    and the floor grid covers the whole path."""
    _, q, path = travelling_page
    meta, cmds = _page_parts(path.read_text(encoding="utf-8"))
    assert meta["follows"]
    (anim,) = [c for c in cmds if c["type"] == "set_animation"]
    (clip,) = [a["clip"] for a in anim["animations"] if a["path"] == html.FOLLOW]
    keys = np.array([k["value"] for k in clip["tracks"][0]["keys"]])
    rows = html.animation_frames(q, 0.01)
    np.testing.assert_allclose(keys[:, 0], q[rows, 0], atol=1e-9)
    assert np.all(keys[:, 2] == 0.0) and np.abs(keys[:, 1]).max() < 0.1
    (floor,) = [c for c in cmds if c.get("path") == "/cgadyn/floor"]
    points = np.frombuffer(floor["object"]["geometries"][0]["data"]["attributes"]["position"]
                           ["array"].data, dtype=np.float32).reshape(-1, 3)
    assert points[:, 0].min() < 0.0 and points[:, 0].max() > 20.0


@pytest.mark.slow
@pytest.mark.browser
@pytest.mark.skipif(CHROMIUM is None, reason="no chromium to render the page")
def test_chromium_keeps_a_travelling_robot_in_view(travelling_page, tmp_path):
    """After the 2 s clip the pendulum, 20 m from where it started, is still in the
    picture: its grey links (4-5 % of the pixels here) against the same page with the follow
    turned off, whose last frame shows the grid alone (0.9 %). (Its yellow base may hide
    behind the links in the frame the screenshot catches.)"""
    _, _, path = travelling_page
    fixed = tmp_path / "fixed.html"
    fixed.write_text(path.read_text(encoding="utf-8").replace('"follows": true',
                                                              '"follows": false'),
                     encoding="utf-8")
    shots = {}
    for name, page in (("follow", path), ("fixed", fixed)):
        screenshot(page, tmp_path / f"{name}.png", budget_ms=4000)
        shots[name] = robot_pixels(tmp_path / f"{name}.png")
    assert shots["follow"]["grey"] > shots["fixed"]["grey"] + 1e-2, shots
