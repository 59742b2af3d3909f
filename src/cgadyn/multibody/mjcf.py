"""Load a :class:`~cgadyn.multibody.model.Model` from MuJoCo's MJCF, through Pinocchio.

An XML document whose root element is ``<mujoco>`` is MJCF (``is_mjcf``, the one test
``cgadyn.load`` and the oracle use). Pinocchio parses it (``pinocchio_model``, the one
place that calls ``pinocchio.buildModelFromMJCF``) and ``from_pinocchio`` converts the
result, so the model is Pinocchio's reading of the file: its joints (hinge: revolute,
slide: prismatic, free: free flyer; ball joints are refused by name), the bodies without
a joint welded to their parent, the masses and inertias of the ``<inertial>`` elements.
"""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

from cgadyn.multibody.cache import cached
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


_IDENTITY = {"pos": (0.0, 0.0, 0.0), "quat": (1.0, 0.0, 0.0, 0.0), "euler": (0.0, 0.0, 0.0),
             "xyaxes": (1.0, 0.0, 0.0, 0.0, 1.0, 0.0), "zaxis": (0.0, 0.0, 1.0)}
"""A body's placement attributes in MJCF, and the values that leave it at its parent's frame
(``axisangle`` is the identity when its angle, the fourth number, is zero)."""


def _dropped_root_pose(xml: bytes, where: str) -> None:
    """Refuse a body welded to the world (a child of ``<worldbody>`` without a joint) that
    is placed away from the world's origin: Pinocchio's MJCF parser (4.1) puts such a body
    at the origin, so its model would not be the file's robot. Its children's placements,
    and those of top-level bodies with a joint, are read correctly."""
    from lxml import etree

    try:
        root = etree.fromstring(xml.strip())
    except etree.XMLSyntaxError as exc:
        raise ValueError(f"malformed XML in {where}: {exc}") from None
    for body in root.iterfind("worldbody/body"):
        if body.find("joint") is not None or body.find("freejoint") is not None:
            continue
        for attr, identity in (*_IDENTITY.items(), ("axisangle", None)):
            text = body.get(attr)
            if text is None:
                continue
            try:
                values = tuple(float(x) for x in text.split())
            except ValueError:
                values = ()
            if attr == "axisangle":
                moved = values[3:] != (0.0,)
            elif attr == "quat":  # q and -q are the same rotation
                moved = values not in (identity, tuple(-x for x in identity))
            else:
                moved = values != identity
            if moved:
                raise ValueError(
                    f"{where}: body {body.get('name')!r} is welded to the world with "
                    f"{attr}=\"{text}\", which Pinocchio's MJCF parser ignores (it places a "
                    f"jointless child of <worldbody> at the origin), so the model would not be "
                    f"the file's; expected it at the origin: wrap it in a <body> without "
                    f"{attr} (nested placements are read)")


def _has_free_root(pm) -> bool:
    return pm.njoints > 1 and pm.joints[1].shortname() == "JointModelFreeFlyer"


def pinocchio_model(source, floating_base: bool | None = None):
    """Pinocchio's model of an MJCF file path or MJCF text (text goes through a temporary
    file, so relative ``<include>`` paths are not found).

    ``floating_base``: ``None`` keeps the file's own base (a ``<freejoint/>`` on the root
    body gives a free flyer); ``True`` adds a free-flyer root ``root_joint`` when the file
    has none; ``False`` refuses a file whose root body has a free joint.
    """
    import pinocchio as pin

    xml, path = _read_source(source)
    where = repr(path) if path is not None else "the MJCF text"
    if not is_mjcf(xml):
        raise ValueError(f"{where} is not MJCF: expected an XML document whose root element "
                         f"is <mujoco>")
    _dropped_root_pose(xml, where)
    with tempfile.TemporaryDirectory() as tmp:
        if path is None:
            path = os.path.join(tmp, "model.xml")
            Path(path).write_bytes(xml)
        try:
            pm = pin.buildModelFromMJCF(str(path))
            added = bool(floating_base) and not _has_free_root(pm)
            if added:
                pm = pin.buildModelFromMJCFAndRootJoint(str(path), pin.JointModelFreeFlyer(),
                                                        ROOT_JOINT)
        except (RuntimeError, ValueError) as exc:
            raise ValueError(f"Pinocchio cannot parse the MJCF in {where}: {exc}") from None
    if floating_base is False and _has_free_root(pm):
        raise ValueError(f"{where}: the root body has a free joint {pm.names[1]!r}, so the "
                         f"model floats; expected floating_base=None or True for this file")
    if _has_free_root(pm) and not added:
        _free_joint_at_world(pm)
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
