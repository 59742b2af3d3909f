"""Load a :class:`~cgadyn.multibody.model.Model` from URDF (a file or XML text).

The URDF is parsed with yourdfpy (meshes are never loaded). The root link is fixed to the
world; ``revolute``, ``continuous``, ``prismatic`` and ``fixed`` joints are supported.

Joint order (the order of ``q``): Pinocchio's URDF parser walks the kinematic tree
depth-first (pre-order) from the root link; at each link it visits the child joints
sorted by joint name (byte-wise, as urdfdom keeps joints in a ``std::map``), not in
the order of the file. Fixed joints are walked through but take no index.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from cgadyn.multibody.cache import cached
from cgadyn.multibody.joints import FREE_FLYER, TYPES
from cgadyn.multibody.model import Model, build_model, merge_inertias

SUPPORTED_JOINTS = ("revolute", "continuous", "prismatic", "fixed")


def _read_source(source) -> tuple[bytes, str | None]:
    """Return (xml bytes, path or None) for a path or URDF text."""
    if isinstance(source, bytes):
        return source, None
    if isinstance(source, os.PathLike) or (isinstance(source, str) and "<" not in source):
        path = Path(source)
        if not path.is_file():
            raise FileNotFoundError(
                f"URDF file not found: {str(path)!r} (expected a path to a .urdf file or "
                f"URDF XML text)")
        return path.read_bytes(), str(path)
    if isinstance(source, str):
        return source.encode("utf-8"), None
    raise TypeError(f"load_urdf expects a path or URDF XML text, got {type(source).__name__}")


def _parse(xml: bytes, where: str):
    """Parse URDF bytes into a yourdfpy Robot."""
    from lxml import etree

    try:
        parser = etree.XMLParser(remove_blank_text=True, remove_comments=True)
        root = etree.fromstring(xml.strip(), parser=parser)
    except etree.XMLSyntaxError as exc:
        raise ValueError(f"malformed XML in {where}: {exc}") from None
    if root.tag != "robot":
        raise ValueError(f"{where} is not a URDF: the root element is <{root.tag}>, "
                         f"expected <robot>")
    if not root.get("name"):
        root.set("name", "robot")
    for tag in ("link", "joint"):
        for el in root.findall(tag):
            if not el.get("name"):
                raise ValueError(f"{where}: a <{tag}> has no 'name' attribute")
    for el in root.findall("joint"):
        for sub in ("parent", "child"):
            s = el.find(sub)
            if s is None or not s.get("link"):
                raise ValueError(f"{where}: joint {el.get('name')!r} has no <{sub} link=...>")
    _check_numbers(root, where)
    import yourdfpy

    try:
        return yourdfpy.URDF._parse_robot(xml_element=root)
    except (ValueError, TypeError, AttributeError, KeyError) as exc:
        raise ValueError(f"invalid URDF in {where}: {exc}") from None


_NUMBERS = (  # (element path, attribute, count, what is expected)
    ("origin", "xyz", 3, "3 finite numbers (metres)"),
    ("origin", "rpy", 3, "3 finite numbers (radians)"),
    ("axis", "xyz", 3, "3 finite numbers, not all zero"),
    ("limit", "lower", 1, "a finite number"),
    ("limit", "upper", 1, "a finite number"),
    ("limit", "effort", 1, "a number"),
    ("limit", "velocity", 1, "a number"),
    ("inertial/origin", "xyz", 3, "3 finite numbers (metres)"),
    ("inertial/origin", "rpy", 3, "3 finite numbers (radians)"),
    ("inertial/mass", "value", 1, "a finite number >= 0"),
    *(("inertial/inertia", a, 1, "a finite number")
      for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")),
)


def _check_numbers(root, where: str) -> None:
    """Every number of the joints and links that the model reads parses and is finite
    (``effort`` and ``velocity`` may be infinite): a ``ValueError`` names the element, the
    attribute, what it holds and what was expected."""
    for tag in ("joint", "link"):
        for el in root.findall(tag):
            for path, attr, count, expected in _NUMBERS:
                sub = el.find(path)
                if sub is None or sub.get(attr) is None:
                    continue
                if (tag == "joint") == path.startswith("inertial"):
                    continue
                text = sub.get(attr)
                try:
                    values = [float(x) for x in text.split()]
                except ValueError:
                    values = []
                ok = len(values) == count and (
                    attr in ("effort", "velocity") and not any(v != v for v in values)
                    or all(abs(v) < float("inf") for v in values))
                if ok and attr == "xyz" and path == "axis" and el.get("type") != "fixed":
                    ok = any(v != 0.0 for v in values)  # a fixed joint's axis is unread
                if ok and path == "inertial/mass":
                    ok = values[0] >= 0.0
                if not ok:
                    raise ValueError(f"{where}: {tag} {el.get('name')!r}: <{path} {attr}="
                                     f"{text!r}> is not {expected}")


def _inertial(link, check: bool = True):
    """(mass, com, rotational inertia about com) of one link in its own frame; ``check``:
    refuse a rotational inertia that is not positive semi-definite."""
    inertial = link.inertial
    if inertial is None or inertial.mass is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=float)
    inertia = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia,
                                                                           dtype=float)
    mass = float(inertial.mass)
    scale = max(1.0, float(np.abs(inertia).max()))
    if not np.isfinite(mass) or mass < 0:
        raise ValueError(f"link {link.name!r} has mass {mass}; expected a finite mass >= 0")
    if not np.all(np.isfinite(inertia)):
        raise ValueError(f"link {link.name!r} has a rotational inertia that is not finite")
    if check and np.linalg.eigvalsh(inertia).min() < -1e-12 * scale:
        raise ValueError(
            f"link {link.name!r} has a rotational inertia that is not positive semi-definite "
            f"(eigenvalues {np.linalg.eigvalsh(inertia).tolist()}); expected a physical inertia "
            f"(load with check_inertia=False to accept it, as Pinocchio does)")
    rot = origin[:3, :3]
    return mass, origin[:3, 3].copy(), rot @ inertia @ rot.T


def _dynamics(joint, what: str, where: str) -> float:
    """A joint's ``<dynamics damping=...>`` or ``friction=...`` (``what``; 0 without one),
    finite and non-negative (as Pinocchio's parser reads them into ``model.damping`` and
    ``model.friction``)."""
    dynamics = getattr(joint, "dynamics", None)
    value = None if dynamics is None else getattr(dynamics, what)
    value = 0.0 if value is None else float(value)
    if not (np.isfinite(value) and value >= 0.0):
        raise ValueError(f"{where}: joint {joint.name!r}: <dynamics {what}=\"{value}\"> is "
                         f"not a finite number >= 0")
    return value


def _limit(joint, attr, default):
    value = None if joint.limit is None else getattr(joint.limit, attr)
    return default if value is None else float(value)


def load_urdf(source: str | os.PathLike, name: str | None = None,
              floating_base: bool = False, check_inertia: bool = True) -> Model:
    """Build a :class:`Model` from a URDF file path or URDF XML text.

    The root link is fixed to the world, or with ``floating_base`` moved by a free-flyer
    joint ``root_joint`` (Pinocchio's ``JointModelFreeFlyer``), the first joint. Links
    joined by fixed joints are merged into the body of the nearest movable joint above them
    (their inertial frames' rotations honoured); links without ``<inertial>`` are massless.
    Mimic joints are treated as independent joints, as Pinocchio does by default.

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` for malformed XML,
    unsupported joint types (``floating``, ``planar``), closed loops, several roots, links
    that do not exist, a zero joint axis, a revolute/prismatic joint without ``<limit>``, or
    a moving link whose rotational inertia is not positive semi-definite.
    """
    xml, path = _read_source(source)
    options = (name, bool(floating_base), bool(check_inertia))
    return cached(xml, options, lambda: _build(xml, path, *options))


ROOT_JOINT = "root_joint"
"""The name of a free-flyer root joint, as Pinocchio names it."""


def _build(xml: bytes, path: str | None, name: str | None, floating_base: bool,
           check_inertia: bool) -> Model:
    where = repr(path) if path is not None else "the URDF text"
    robot = _parse(xml, where)

    link_names = [link.name for link in robot.links]
    links = {}
    for link in robot.links:
        if link.name in links:
            raise ValueError(f"{where}: link {link.name!r} is defined twice")
        links[link.name] = link
    if not links:
        raise ValueError(f"{where}: the URDF has no <link>")
    joint_seen = set()
    parent_joint = {}  # child link -> joint
    children = {}  # parent link -> joints
    for joint in robot.joints:
        if joint.name in joint_seen:
            raise ValueError(f"{where}: joint {joint.name!r} is defined twice")
        joint_seen.add(joint.name)
        if joint.type in ("floating", "planar"):
            raise ValueError(
                f"{where}: joint {joint.name!r} is of type {joint.type!r}, which is not "
                f"supported: the root link is fixed to the world and only "
                f"{', '.join(SUPPORTED_JOINTS)} joints are supported")
        if joint.type not in SUPPORTED_JOINTS:
            raise ValueError(f"{where}: joint {joint.name!r} has unknown type {joint.type!r}; "
                             f"expected one of {', '.join(SUPPORTED_JOINTS)}")
        for role, lk in (("parent", joint.parent), ("child", joint.child)):
            if lk not in links:
                raise ValueError(f"{where}: joint {joint.name!r} names {role} link {lk!r}, "
                                 f"which is not defined")
        if joint.child in parent_joint:
            raise ValueError(
                f"{where}: link {joint.child!r} is the child of two joints "
                f"({parent_joint[joint.child].name!r} and {joint.name!r}): closed loops "
                f"are not supported, a URDF must be a tree")
        parent_joint[joint.child] = joint
        children.setdefault(joint.parent, []).append(joint)

    roots = [lk for lk in link_names if lk not in parent_joint]
    if len(roots) != 1:
        if not roots:
            raise ValueError(f"{where}: every link is the child of a joint: the joints form "
                             f"a closed loop; expected a tree with one root link")
        raise ValueError(f"{where}: several root links {roots} (links that are no joint's "
                         f"child); expected a tree with exactly one root link")
    root = roots[0]

    # Depth-first walk in Pinocchio's order: child joints sorted by name (byte-wise).
    joints = []  # movable yourdfpy joints, in order (None: the free-flyer root)
    parents = []
    placement_matrices = []
    link_joint = {root: -1}
    link_pose = {root: np.eye(4)}  # link frame in its body's joint frame
    if floating_base:  # the root link is the body of a free flyer at the world's origin
        if ROOT_JOINT in {jt.name for jt in robot.joints}:
            raise ValueError(f"{where}: a joint is called {ROOT_JOINT!r}, the name of the "
                             f"free-flyer root joint; rename it to load with a floating base")
        joints.append(None)
        parents.append(-1)
        placement_matrices.append(np.eye(4))
        link_joint[root] = 0
    def sorted_children(link):
        return sorted(children.get(link, []), key=lambda jt: jt.name.encode("utf-8"))

    stack = [(jt, root) for jt in reversed(sorted_children(root))]
    while stack:
        joint, plink = stack.pop()
        origin = np.eye(4) if joint.origin is None else np.asarray(joint.origin, float)
        pose = link_pose[plink] @ origin
        if joint.type == "fixed":
            link_joint[joint.child] = link_joint[plink]
            link_pose[joint.child] = pose
        else:
            link_joint[joint.child] = len(joints)
            link_pose[joint.child] = np.eye(4)
            parents.append(link_joint[plink])
            placement_matrices.append(pose)
            joints.append(joint)
        stack.extend((jt, joint.child) for jt in reversed(sorted_children(joint.child)))

    unreached = [lk for lk in link_names if lk not in link_joint]
    if unreached:
        raise ValueError(f"{where}: links {unreached} are not connected to the root link "
                         f"{root!r}: their joints form a closed loop; expected a tree")

    n = len(joints)
    joint_names = [ROOT_JOINT if jt is None else jt.name for jt in joints]
    base = TYPES[FREE_FLYER]  # what a floating base is
    kinds = [base.kind if jt is None else jt.type for jt in joints]
    axis_vectors = np.zeros((n, 3))
    lower, upper, velocity, effort = [], [], [], []  # per coordinate of q, q, v, v
    damping, friction = [], []  # per coordinate of v
    mimic = []
    for j, jt in enumerate(joints):
        if jt is None:  # free flyer: a box of translations, a unit quaternion
            lo, hi = base.limits(np.full(base.nq, -np.inf), np.full(base.nq, np.inf))
            lower += lo.tolist()
            upper += hi.tolist()
            velocity += [np.inf] * base.nv
            effort += [np.inf] * base.nv
            damping += [0.0] * base.nv
            friction += [0.0] * base.nv
            mimic.append(None)
            continue
        axis = np.array([1.0, 0.0, 0.0]) if jt.axis is None else np.asarray(jt.axis, float)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) < 1e-12:
            raise ValueError(f"{where}: joint {jt.name!r} has axis {axis.tolist()}; expected a "
                             f"non-zero 3-vector <axis xyz=\"x y z\"/>")
        axis_vectors[j] = axis
        if jt.type in ("revolute", "prismatic") and jt.limit is None:
            raise ValueError(f"{where}: {jt.type} joint {jt.name!r} has no <limit>; expected "
                             f"<limit lower=... upper=... effort=... velocity=...>")
        if jt.type == "continuous":
            lower.append(-np.inf)
            upper.append(np.inf)
        else:
            lower.append(_limit(jt, "lower", 0.0))
            upper.append(_limit(jt, "upper", 0.0))
        velocity.append(_limit(jt, "velocity", np.inf))
        effort.append(_limit(jt, "effort", np.inf))
        damping.append(_dynamics(jt, "damping", where))
        friction.append(_dynamics(jt, "friction", where))
        m = jt.mimic
        mimic.append(None if m is None else (
            m.joint, 1.0 if m.multiplier is None else float(m.multiplier),
            0.0 if m.offset is None else float(m.offset)))

    # Merge every link into the body of its joint, in that joint's frame.
    pieces = [([], [], []) for _ in range(n)]
    for lk in link_names:
        j = link_joint[lk]
        if j < 0:
            continue
        try:
            mass, com, rot = _inertial(links[lk], check_inertia)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        pose = link_pose[lk]
        r = pose[:3, :3]
        pieces[j][0].append(mass)
        pieces[j][1].append(r @ com + pose[:3, 3])
        pieces[j][2].append(r @ rot @ r.T)
    body_mass = np.zeros(n)
    body_com = np.zeros((n, 3))
    body_rot = np.zeros((n, 3, 3))
    for j in range(n):
        body_mass[j], body_com[j], body_rot[j] = merge_inertias(*pieces[j])

    return build_model(
        name=robot.name if name is None else name,
        joint_names=joint_names,
        joint_kinds=kinds,
        parents=parents,
        placement_matrices=np.array(placement_matrices).reshape(n, 4, 4),
        axis_vectors=axis_vectors,
        body_mass=body_mass,
        body_com=body_com,
        body_rotational_inertia=body_rot,
        lower=lower,
        upper=upper,
        velocity_limit=velocity,
        effort_limit=effort,
        link_names=link_names,
        link_joint=[link_joint[lk] for lk in link_names],
        link_placement_matrices=np.array([link_pose[lk] for lk in link_names]),
        root_link=root,
        mimic=mimic,
        check_inertia=check_inertia,
        damping=damping,
        friction=friction,
    )
