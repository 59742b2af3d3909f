"""Load a :class:`~cgadyn.multibody.model.Model` from MuJoCo's MJCF, through Pinocchio.

An XML document whose root element is ``<mujoco>`` is MJCF (``is_mjcf``, the one test
``cgadyn.load`` and the oracle use). Pinocchio parses it (``pinocchio_model``, the one
place that calls ``pinocchio.buildModelFromMJCF``) and ``from_pinocchio`` converts the
result, so the model is Pinocchio's reading of the file: its joints (hinge: revolute,
slide: prismatic, free: free flyer, ball: spherical, as Pinocchio reads them), the bodies without
a joint welded to their parent, the masses and inertias of the ``<inertial>`` elements.

Pinocchio's parser (4.1) reads less than MuJoCo does, silently; what it would get wrong
is refused here, by name, before it parses: a second top-level body (it reads only the
first ``<body>`` under ``<worldbody>``), a jointless top-level body away from the origin,
``floating_base=True`` on a top-level body that has its own joint, numbers that are not
finite. ``<include>`` elements (which it ignores) are expanded here, as MuJoCo does, and
named sites, which it drops, are added to its model as frames (links of cgadyn's model).
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from pathlib import Path

import numpy as np

from cgadyn.multibody.cache import cached
from cgadyn.multibody.joints import table
from cgadyn.multibody.model import Model
from cgadyn.multibody.urdf import ROOT_JOINT, _read_source

_PROLOG = re.compile(
    rb"\A(?:\xef\xbb\xbf)?(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>)*<([^\s/>]+)", re.DOTALL)
"""What comes before an XML document's root element (a byte-order mark, the declaration,
comments, a doctype, white space), then the root element's tag."""


def is_mjcf(xml: bytes) -> bool:
    """True when ``xml`` is an XML document whose root element is ``<mujoco>`` (read from
    the prolog only, without parsing the document: ``load`` asks it of every file)."""
    match = _PROLOG.match(xml)
    return match is not None and match.group(1) == b"mujoco"


def file_is_mjcf(path: os.PathLike | str) -> bool:
    """True when the file at ``path`` is MJCF (see ``is_mjcf``)."""
    return is_mjcf(Path(path).read_bytes())


def _parse_xml(xml: bytes, where: str):
    """The lxml element tree of an XML document, comments dropped; a ``ValueError`` names
    the document when it is not well-formed XML."""
    from lxml import etree

    try:
        parser = etree.XMLParser(remove_comments=True)
        return etree.fromstring(xml.strip(), parser=parser)
    except etree.XMLSyntaxError as exc:
        raise ValueError(f"malformed XML in {where}: {exc}") from None


def _expand_includes(root, directory: Path, where: str, seen: tuple = ()) -> bool:
    """Replace every ``<include file="...">`` under ``root`` by the children of the
    included file's ``<mujoco>`` element, as MuJoCo does (paths relative to ``directory``,
    the main file's; included files may include others, none twice). Pinocchio's parser
    (4.1) ignores ``<include>``. Returns whether there was any; a ``ValueError`` says which
    include is wrong and why."""
    includes = list(root.iter("include"))
    for include in includes:
        name = include.get("file")
        if not name:
            raise ValueError(f"{where}: an <include> has no 'file' attribute; expected "
                             f"<include file=\"other.xml\"/>")
        path = (directory / name).resolve()
        if not path.is_file():
            raise ValueError(f"{where}: <include file={name!r}> names a file that does not "
                             f"exist: {str(path)!r} (paths are relative to the main file's "
                             f"directory, {str(directory)!r})")
        if path in seen:
            raise ValueError(f"{where}: {str(path)!r} is included twice (or includes "
                             f"itself); MuJoCo includes a file once")
        inner_where = f"{str(path)!r} (included by {where})"
        inner = _parse_xml(path.read_bytes(), inner_where)
        if inner.tag != "mujoco":
            raise ValueError(f"{where}: the included file {str(path)!r} has the root element "
                             f"<{inner.tag}>; expected <mujoco>")
        _expand_includes(inner, directory, inner_where, (*seen, path))
        parent, index = include.getparent(), include.getparent().index(include)
        parent.remove(include)
        for k, child in enumerate(list(inner)):
            parent.insert(index + k, child)
        seen = (*seen, path)
    return bool(includes)


_PLACEMENT = {"pos": 3, "quat": 4, "euler": 3, "axisangle": 4, "xyaxes": 6, "zaxis": 3}
_NUMBERS = {
    "body": _PLACEMENT,
    "inertial": {**_PLACEMENT, "mass": 1, "diaginertia": 3, "fullinertia": 6},
    "joint": {"pos": 3, "axis": 3, "range": 2, "ref": 1, "armature": 1, "damping": 1},
    "site": {**_PLACEMENT, "fromto": 6},
    "geom": {**_PLACEMENT, "fromto": 6, "mass": 1, "density": 1},
}
"""The numbers the model is read from: element -> attribute -> how many."""


def _body_name(element) -> str:
    """The name of the body that holds ``element`` (the element itself if a body)."""
    body = element if element.tag == "body" else next(
        (a for a in element.iterancestors() if a.tag in ("body", "worldbody")), None)
    if body is None or body.tag == "worldbody":
        return "the world"
    return f"body {body.get('name', '(unnamed)')!r}"


def _check_numbers(root, where: str) -> None:
    """Every number of the bodies, inertials, joints, sites and geoms under
    ``<worldbody>`` parses and is finite; a ``ValueError`` names the body, the element, the
    attribute, what it holds and what was expected (Pinocchio would read NaN through, and
    fail later without saying where)."""
    for worldbody in root.iter("worldbody"):
        for element in worldbody.iter(*_NUMBERS):
            for attr, count in _NUMBERS[element.tag].items():
                text = element.get(attr)
                if text is None:
                    continue
                try:
                    values = [float(x) for x in text.split()]
                except ValueError:
                    values = []
                if len(values) != count or not all(math.isfinite(x) for x in values):
                    raise ValueError(
                        f"{where}: {_body_name(element)}: <{element.tag} {attr}=\"{text}\"> "
                        f"is not {count} finite number{'s' if count > 1 else ''}")


def _numbers(values) -> str:
    """Numbers as MJCF attribute text, exactly (17 significant digits)."""
    return " ".join(format(float(x), ".17g") for x in values)


def _unit_axisangles(root) -> bool:
    """Normalise the axis of every ``axisangle`` attribute, as MuJoCo does: Pinocchio's
    parser (4.1) takes the axis as given, and a non-unit axis gives it a placement that is
    not a rotation. Returns whether any changed."""
    changed = False
    for element in root.iter():
        text = element.get("axisangle") if isinstance(element.tag, str) else None
        if text is None:
            continue
        values = np.array(text.split(), dtype=float)  # checked by _check_numbers
        norm = np.linalg.norm(values[:3])
        if norm > 0.0 and norm != 1.0:
            element.set("axisangle", _numbers([*(values[:3] / norm), values[3]]))
            changed = True
    return changed


def _label(body, k: int | None = None) -> str:
    name = body.get("name")
    return repr(name) if name else f"an unnamed <body> (number {k + 1} under <worldbody>)" \
        if k is not None else "an unnamed <body>"


def _read_bodies(top) -> set:
    """``top`` and the bodies Pinocchio's parser reads in it: its ``<body>`` children, theirs,
    and so on (not a body inside a ``<frame>`` or any other element). The elements
    themselves, so that lxml keeps their proxies (compared by identity)."""
    kept, stack = set(), [top]
    while stack:
        body = stack.pop()
        kept.add(body)
        stack.extend(body.findall("body"))
    return kept


def _top_body(root, where: str):
    """The one top-level body Pinocchio's parser reads: the first ``<body>`` of the first
    ``<worldbody>``. Every other body would be dropped by that parser, silently: refused,
    naming the top-level bodies that would be (with their descendants)."""
    worldbodies = root.findall("worldbody")
    top = None if not worldbodies else worldbodies[0].find("body")
    if top is None:
        raise ValueError(f"{where}: no <body> under <worldbody>; expected one top-level "
                         f"<body>, the robot")
    kept = _read_bodies(top)
    dropped = []  # the roots of the subtrees that would be dropped
    for worldbody in worldbodies:
        for k, body in enumerate(worldbody.iter("body")):
            if body in kept:
                continue
            above = next((a for a in body.iterancestors() if a.tag == "body"), None)
            if above is None or above in kept:
                dropped.append((body, k))
    if dropped:
        names = ", ".join(_label(b, k) for b, k in dropped)
        inside = sum(len(list(b.iter("body"))) - 1 for b, _ in dropped)
        more = f" with {inside} bodies inside them" if inside else ""
        raise ValueError(
            f"{where}: cgadyn reads one top-level body per MJCF file for now (through "
            f"Pinocchio's MJCF parser, which reads only the first <body> under <worldbody>, "
            f"{_label(top)}, and the bodies nested in it); the bodies {names}{more} would be "
            f"dropped; expected one top-level "
            f"<body>: put the robot in a file of its own or nest the bodies in one")
    return top


_IDENTITY = {"pos": (0.0, 0.0, 0.0), "quat": (1.0, 0.0, 0.0, 0.0), "euler": (0.0, 0.0, 0.0),
             "xyaxes": (1.0, 0.0, 0.0, 0.0, 1.0, 0.0), "zaxis": (0.0, 0.0, 1.0)}
"""A body's placement attributes in MJCF, and the values that leave it at its parent's frame
(``axisangle`` is the identity when its angle, the fourth number, is zero)."""


def _joints(body) -> list:
    """The joint elements of a body (``<joint>`` and ``<freejoint>``)."""
    return [c for c in body if c.tag in ("joint", "freejoint")]


def _is_free(joint) -> bool:
    return joint.tag == "freejoint" or joint.get("type") == "free"


def _dropped_root_pose(top, where: str) -> None:
    """Refuse a top-level body welded to the world (no joint) that is placed away from the
    world's origin: Pinocchio's MJCF parser (4.1) puts such a body at the origin, so its
    model would not be the file's robot. Its children's placements, and those of a
    top-level body with a joint, are read correctly."""
    if _joints(top):
        return
    for attr, identity in (*_IDENTITY.items(), ("axisangle", None)):
        text = top.get(attr)
        if text is None:
            continue
        values = tuple(float(x) for x in text.split())  # checked by _check_numbers
        if attr == "axisangle":
            moved = values[3:] != (0.0,)
        elif attr == "quat":  # q and -q are the same rotation
            moved = values not in (identity, tuple(-x for x in identity))
        else:
            moved = values != identity
        if moved:
            raise ValueError(
                f"{where}: body {top.get('name')!r} is welded to the world with "
                f"{attr}=\"{text}\", which Pinocchio's MJCF parser ignores (it places a "
                f"jointless child of <worldbody> at the origin), so the model would not be "
                f"the file's; expected it at the origin: wrap it in a <body> without "
                f"{attr} (nested placements are read)")


def _check_floating(top, floating_base: bool | None, where: str) -> bool:
    """Whether a free-flyer root must be added for ``floating_base``: only when asked and
    the top-level body has no joint. A top-level body with a joint of its own (other than
    a free one) cannot also float: Pinocchio's parser would ignore the request, silently,
    so it is refused, naming the joint."""
    joints = _joints(top)
    if not floating_base or any(_is_free(j) for j in joints):
        return False
    if joints:
        name = joints[0].get("name")
        joint = repr(name) if name else f"an unnamed {joints[0].get('type', 'hinge')} joint"
        raise ValueError(
            f"{where}: floating_base=True, but the top-level body {_label(top)} has the "
            f"joint {joint}, so no free flyer can be added above it (Pinocchio's MJCF "
            f"parser would ignore the request); expected floating_base=None or False for "
            f"this file, or a free body: wrap the body in a <body> with a <freejoint/> and "
            f"an <inertial>")
    return True


def _site_placements(root, top, where: str) -> list:
    """``[(site name, parent body name or None for the world, 4x4 pose in that body's
    frame)]`` of the named sites of the bodies Pinocchio reads and of ``<worldbody>``.
    The poses are Pinocchio's own reading of the site's placement attributes (its
    compiler's angle unit and Euler sequence included): the sites are read as bodies
    of a second document. Unnamed sites cannot be asked for and are left out; a site in a
    ``<frame>``, or a file whose ``<default>`` classes place sites, is refused."""
    from lxml import etree

    sites = [s for s in root.iter("site") if s.get("name")]
    if not sites:
        return []
    for default in root.iter("default"):
        placed = [a for s in default.findall("site") for a in (*_PLACEMENT, "fromto")
                  if s.get(a) is not None]
        if placed:
            raise ValueError(f"{where}: a <default> class sets the site attribute "
                             f"{placed[0]!r}, which cgadyn does not read; expected each "
                             f"site's placement on the site itself")
    kept = _read_bodies(top)
    doc = etree.Element("mujoco", model="sites")
    for compiler in root.findall("compiler"):
        etree.SubElement(doc, "compiler", {a: compiler.get(a) for a in ("angle", "eulerseq")
                                           if compiler.get(a) is not None})
    holder = etree.SubElement(etree.SubElement(doc, "worldbody"), "body", name="sites")
    out = []
    for k, site in enumerate(sites):
        parent = site.getparent()
        if parent.tag not in ("body", "worldbody"):
            raise ValueError(f"{where}: site {site.get('name')!r} is inside a "
                             f"<{parent.tag}>, which cgadyn does not read; expected it in a "
                             f"<body> or <worldbody>")
        if parent.tag == "body" and parent not in kept:
            continue  # in a dropped body: refused by _top_body already
        attrs = {a: site.get(a) for a in _PLACEMENT if site.get(a) is not None}
        if site.get("fromto") is not None:  # MuJoCo: at the midpoint, z from "to" to "from"
            a, b = np.split(np.array(site.get("fromto").split(), dtype=float), 2)
            attrs = {"pos": _numbers((a + b) / 2), "zaxis": _numbers(a - b)}
        etree.SubElement(holder, "body", name=f"s{k}", **attrs)
        out.append((site.get("name"), parent.get("name") if parent.tag == "body" else None,
                    f"s{k}"))
    pm = _parse_pinocchio(etree.tostring(doc), None, False, where)
    return [(name, body, pm.frames[pm.getFrameId(key)].placement) for name, body, key in out]


def _add_sites(pm, sites: list, where: str) -> None:
    """Each site a ``BODY`` frame of ``pm`` (no mass) on its body's joint: a link of the
    model cgadyn converts, and a frame of the oracle's model. Added by ``addFrame`` with a
    zero inertia not appended: ``addBodyFrame`` (4.1) can add uninitialised memory (NaN)
    to the joint's inertia."""
    import pinocchio as pin

    for name, body, local in sites:
        if pm.existBodyName(name):
            raise ValueError(f"{where}: site {name!r} has the name of a body; expected site "
                             f"names distinct from body names (both become links)")
        if body is None:
            joint, frame, placement = 0, 0, local
        else:
            frame = pm.getFrameId(body, pin.FrameType.BODY)
            joint, placement = pm.frames[frame].parentJoint, pm.frames[frame].placement * local
        pm.addFrame(pin.Frame(name, joint, frame, placement, pin.FrameType.BODY,
                              pin.Inertia.Zero()), False)  # its inertia not appended


def _has_free_root(pm) -> bool:
    record = table.PINOCCHIO.get(pm.joints[1].shortname()) if pm.njoints > 1 else None
    return record is not None and record.floating


_CPP_LOCATION = re.compile(r"From file:.*?message:\s*", re.DOTALL)


def _parse_pinocchio(xml: bytes, path: str | None, free_flyer: bool, where: str):
    """Pinocchio's model of the MJCF file ``path``, or of the document ``xml`` (through a
    temporary file) when ``path`` is ``None``, with a free-flyer root ``root_joint`` when
    ``free_flyer``; its errors as a ``ValueError`` without Pinocchio's C++ source
    location."""
    import pinocchio as pin

    with tempfile.TemporaryDirectory() as tmp:
        if path is None:
            path = os.path.join(tmp, "model.xml")
            Path(path).write_bytes(xml)
        try:
            if free_flyer:
                return pin.buildModelFromMJCFAndRootJoint(path, pin.JointModelFreeFlyer(),
                                                          ROOT_JOINT)
            return pin.buildModelFromMJCF(path)
        except (RuntimeError, ValueError) as exc:
            message = _CPP_LOCATION.sub("", str(exc)).strip()
            raise ValueError(f"Pinocchio cannot parse the MJCF in {where}: {message}") \
                from None


def pinocchio_model(source, floating_base: bool | None = None):
    """Pinocchio's model of an MJCF file path or MJCF text (``<include>`` paths relative to
    the file's directory, or for text to the working directory), its named sites added as
    ``BODY`` frames.

    ``floating_base``: ``None`` keeps the file's own base (a ``<freejoint/>`` on the root
    body gives a free flyer); ``True`` adds a free-flyer root ``root_joint`` to a jointless
    top-level body (a top-level body with a hinge or slide joint is refused); ``False``
    refuses a file whose root body has a free joint. What Pinocchio's parser would drop
    or misread is refused (see the module's docstring).
    """
    xml, path = _read_source(source)
    where = repr(path) if path is not None else "the MJCF text"
    if not is_mjcf(xml):
        raise ValueError(f"{where} is not MJCF: expected an XML document whose root element "
                         f"is <mujoco>")
    root = _parse_xml(xml, where)
    from lxml import etree

    directory = Path(path).resolve().parent if path is not None else Path.cwd()
    if _expand_includes(root, directory, where):
        xml, path = etree.tostring(root), None
    _check_numbers(root, where)
    if _unit_axisangles(root):
        xml, path = etree.tostring(root), None
    top = _top_body(root, where)
    _dropped_root_pose(top, where)
    added = _check_floating(top, floating_base, where)
    sites = _site_placements(root, top, where)
    pm = _parse_pinocchio(xml, path, added, where)
    if floating_base is not None and not floating_base and _has_free_root(pm):
        raise ValueError(f"{where}: the root body has a free joint {pm.names[1]!r}, so the "
                         f"model floats; expected floating_base=None or True for this file")
    if _has_free_root(pm) and not added:
        _free_joint_at_world(pm)
    _add_sites(pm, sites, where)
    return pm


def _free_joint_at_world(pm) -> None:
    """A free joint's configuration is its body's pose in the world (MuJoCo's meaning): its
    placement is the identity. Pinocchio's parser (4.1) gives a free body placed at ``p``
    with rotation ``R`` the placement ``(I, p - R p)``, every position off by that constant
    (the dynamics unchanged); corrected here, in Pinocchio's model, for cgadyn and the
    oracle alike."""
    import pinocchio as pin

    pm.jointPlacements[1] = pin.SE3.Identity()


def load_mjcf(source, name: str | None = None, floating_base: bool | None = None,
              check_inertia: bool = True) -> Model:
    """The model of an MJCF file path or MJCF text (see ``pinocchio_model`` for
    ``floating_base``), converted by ``from_pinocchio``; ``name`` defaults to the
    ``<mujoco model="...">`` name. Cached on disk like URDF models (keyed by the file's
    text, so a file that ``<include>``s others is rebuilt every time)."""
    from cgadyn.multibody.pinocchio_model import from_pinocchio

    xml, _ = _read_source(source)

    def build() -> Model:
        return from_pinocchio(pinocchio_model(source, floating_base), name=name,
                              check_inertia=check_inertia)

    if b"<include" in xml:
        return build()
    options = ("mjcf", name, floating_base, bool(check_inertia))
    return cached(xml, options, build)
