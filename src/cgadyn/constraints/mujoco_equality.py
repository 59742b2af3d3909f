"""MJCF loop closures: MuJoCo's ``<equality connect/weld>`` as cgadyn ``Constraint``s.

MuJoCo's compiler resolves each equality into ``eq_type``, ``eq_obj1id``, ``eq_obj2id``,
``eq_objtype`` and ``eq_data``; ``mj_instantiateEquality`` states what they hold, and the
constraints here hold the same (``docs/constraints.md``, C11):

- ``connect`` of bodies: the point ``eq_data[0:3]`` of body1 on the point ``eq_data[3:6]``
  of body2 (the compiler fills the second anchor so that the two coincide at ``qpos0``); a
  point constraint, 3 rows in the world's axes (``local_world_aligned``), as MuJoCo's rows
  ``pos1 - pos2`` are;
- ``weld`` of bodies: the frame of body1 at ``eq_data[3:6]`` turned by the quaternion
  ``eq_data[6:10]`` (w, x, y, z; ``relpose``) on the frame of body2 at ``eq_data[0:3]``
  (``anchor``); a frame constraint, 6 rows;
- of sites (``site1``, ``site2``): the sites' frames, for a point (connect) or a frame
  (weld).

Body2 is the world where ``eq_obj2id`` is 0. cgadyn's links carry MuJoCo's body frames and
named sites (``multibody.mujoco_model``), so each placement is MuJoCo's number, unchanged.

Joint and tendon couplings (polynomials of joint values) are not points or frames: the
model holds the linear ones itself (``Model.coupling_*``, read by ``from_mujoco``; the
contact step's rows, docs/contact.md K45), so they are left to it here. What a rigid
constraint cannot hold is refused by name: flex equalities, and a weld's ``torquescale``
other than 1 (a weld that holds the orientation only partly). Equalities inactive at the start
(``eq_active0`` 0) are left out, as MuJoCo leaves them out of its solver. MuJoCo's
constraints are soft (``solref``, ``solimp``): cgadyn's are exact, with the Baumgarte gains
``corrector`` (C5) keeping their drift bounded in a simulation.
"""

from __future__ import annotations

import numpy as np

from ..multibody.mujoco_model import _pose, _rotation, mujoco_model
from .model import Constraint

_TYPES = {0: "connect", 1: "weld", 2: "joint", 3: "tendon", 4: "flex"}
"""``mjtEq`` by value (the types after flex are named by MuJoCo's enum)."""


def _placement(pos, quat=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """The 4x4 placement of a position and MuJoCo's unit quaternion (w, x, y, z)."""
    return _pose(pos, _rotation(quat))


def _name(mj, obj, i: int, fallback: str) -> str:
    import mujoco

    return mujoco.mj_id2name(mj, obj, i) or fallback


def _type_name(mj, k: int) -> str:
    import mujoco

    kind = int(mj.eq_type[k])
    try:
        return mujoco.mjtEq(kind).name.removeprefix("mjEQ_").lower()
    except ValueError:
        return _TYPES.get(kind, f"type {kind}")


def _end(mj, model, k: int, side: int, pos, quat=(1.0, 0.0, 0.0, 0.0)):
    """``(link, placement)`` of one end of equality k: a body with the placement ``pos``,
    ``quat`` in its frame (None for the world body), or a site (its own frame)."""
    import mujoco

    obj = int(mj.eq_obj1id[k] if side == 0 else mj.eq_obj2id[k])
    if int(mj.eq_objtype[k]) == int(mujoco.mjtObj.mjOBJ_SITE):
        name = _name(mj, mujoco.mjtObj.mjOBJ_SITE, obj, f"site {obj}")
        return _link(model, name, f"site {name!r}"), np.eye(4)
    if obj == 0:
        return None, _placement(pos, quat)
    name = _name(mj, mujoco.mjtObj.mjOBJ_BODY, obj, f"body{obj}")
    return _link(model, name, f"body {name!r}"), _placement(pos, quat)


def _link(model, name: str, what: str) -> int:
    if name not in model.link_names:
        raise ValueError(f"the equality's {what} is not a link of {model.name!r}: the model "
                         f"must come from the same MuJoCo model (cgadyn.load_mujoco)")
    return model.link_names.index(name)


def mujoco_constraints(model, source, corrector=(0.0, 0.0),
                       skip_couplings: bool = False) -> list[Constraint]:
    """The active ``connect`` and ``weld`` equalities of a MuJoCo model as ``Constraint``s of
    ``model`` (its conversion, ``cgadyn.load_mujoco``), in MuJoCo's order (the module's
    docstring). ``source``: a ``mujoco.MjModel``, an MJCF path or MJCF text. ``corrector``:
    the Baumgarte gains ``(Kp, Kd)`` of every constraint. Joint and tendon couplings are
    the model's own (``Model.coupling_*``) and left out. ``skip_couplings``: leave flex
    couplings out instead of refusing them (``cgadyn validate`` checks the rest).

    Raises ``ValueError`` naming an equality that a rigid point or frame constraint cannot
    hold (flex couplings, unless skipped; a partial weld)."""
    import mujoco

    mj = mujoco_model(source)
    out = []
    for k in range(mj.neq):
        kind = _type_name(mj, k)
        label = _name(mj, mujoco.mjtObj.mjOBJ_EQUALITY, k, f"equality {k}")
        if kind in ("joint", "tendon"):  # Model.coupling_*: the contact step's rows (K45)
            continue
        if kind not in ("connect", "weld"):
            if skip_couplings:
                continue
            raise ValueError(f"MuJoCo model {model.name!r}: equality {label!r} is a {kind} "
                             f"constraint, which cgadyn cannot hold yet (it holds connect "
                             f"and weld equalities: points and frames)")
        if not bool(mj.eq_active0[k]):
            continue
        data = np.asarray(mj.eq_data[k], dtype=float)
        if kind == "connect":
            (l1, P1), (l2, P2) = _end(mj, model, k, 0, data[0:3]), \
                _end(mj, model, k, 1, data[3:6])
            kind_rows = "point"
        else:
            if data[10] != 1.0:
                raise ValueError(f"MuJoCo model {model.name!r}: weld {label!r} has "
                                 f"torquescale {data[10]}; cgadyn's frame constraints hold "
                                 f"the orientation whole (torquescale 1)")
            (l1, P1), (l2, P2) = _end(mj, model, k, 0, data[3:6], data[6:10]), \
                _end(mj, model, k, 1, data[0:3])
            kind_rows = "frame"
        if l1 is None:  # body1 the world: the constraint written from the other end
            (l1, P1), (l2, P2) = (l2, P2), (l1, P1)
        if l1 is None:
            raise ValueError(f"MuJoCo model {model.name!r}: equality {label!r} holds the "
                             f"world to itself")
        out.append(Constraint(model, kind_rows, l1, placement=P1, other=l2,
                              other_placement=P2, corrector=corrector))
    return out
