"""``Constraint``: a point or a frame of one link held at a point or frame of another link, or
of the world (``docs/constraints.md``, C1-C2).

A point constraint (``kind="point"``, Pinocchio's ``CONTACT_3D``) holds the conformal point
``X₁ = M₁ x ~M₁`` carried by ``link`` on the point ``X₂`` carried by ``other``: three rows. A
frame constraint (``kind="frame"``, ``CONTACT_6D``, a weld) holds the motor ``M₁`` of a frame
of ``link`` on the motor ``M₂`` of a frame of ``other``: six rows. ``frame`` fixes the frame
of the rows and of the forces, as Pinocchio's ``reference_frame`` does: ``"local"`` (the
axes of the constraint frame on ``link``) or ``"local_world_aligned"`` (the world's axes at
its origin).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..algorithms import _inputs
from ..algorithms.api import link_placements
from ..algorithms.configuration import neutral
from ..cga.conventions import motor_from_matrix
from ..cga.objects import Motor

KINDS = {"point": 3, "frame": 6}
"""Each kind and its number of rows."""

FRAMES = ("local", "local_world_aligned")


def _placement(value, name: str) -> np.ndarray:
    """A rigid placement given as a 4x4 matrix or a ``Motor``, as a 4x4 matrix."""
    if value is None:
        return np.eye(4)
    if isinstance(value, Motor):
        if value.values.shape != (8,):
            raise ValueError(f"{name} must be one motor, got a batch {value.values.shape[:-1]}")
        return np.asarray(value.matrix(), dtype=float)
    try:
        T = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 4x4 homogeneous matrix or a Motor, got "
                         f"{type(value).__name__}") from None
    if T.shape != (4, 4):
        raise ValueError(f"{name} must be a 4x4 homogeneous matrix or a Motor, got an array "
                         f"of shape {T.shape}")
    R = T[:3, :3]
    if (not np.all(np.isfinite(T)) or not np.allclose(T[3], [0.0, 0.0, 0.0, 1.0])
            or not np.allclose(R.T @ R, np.eye(3), atol=1e-9)
            or not np.isclose(np.linalg.det(R), 1.0, atol=1e-9)):
        raise ValueError(f"{name} must be a rigid 4x4 homogeneous matrix (a rotation and a "
                         f"translation, last row 0 0 0 1), got\n{T}")
    return T.copy()


def _joint_frame(model, link: int, P: np.ndarray) -> tuple[int, np.ndarray]:
    """The joint that carries the frame ``P`` of ``link`` (-1 where the link is fixed in the
    world), and that frame in the joint's frame (in the world for -1): what compiled code
    moves by the joint's world motor (``constraints/core.py``), one motor product per end."""
    return int(model.link_joint[link]), model.link_placement_matrices[link] @ P


@dataclass(frozen=True, eq=False)
class Constraint:
    """A bilateral constraint of ``model``.

    Parameters
    ----------
    model : the robot.
    kind : ``"point"`` (3 rows, Pinocchio's ``CONTACT_3D``) or ``"frame"`` (6 rows,
        ``CONTACT_6D``).
    link : the constrained link, a name or an index of ``model.link_names``.
    placement : the constraint frame in the link frame (the URDF link frame), a 4x4 matrix or
        a ``Motor``; identity by default. A point constraint holds its origin.
    other : the link it is held to, or None for the world.
    other_placement : the frame held to, in ``other``'s link frame; where ``other`` is None,
        in the world. By default, where ``other`` is None, the world placement of the
        constraint frame in the configuration ``q`` (the robot is held where it stands); else
        the identity.
    frame : ``"local"`` or ``"local_world_aligned"``: the frame of the rows and the forces.
    corrector : Baumgarte gains ``(Kp, Kd)`` (Pinocchio's ``corrector``), C5.
    q : the reference configuration of a world anchor taken from the robot (``other`` None,
        ``other_placement`` None); ``neutral(model)`` by default.
    """

    model: object
    kind: str
    link: int
    placement: np.ndarray
    other: int | None
    other_placement: np.ndarray
    frame: str
    corrector: tuple[float, float]
    name: str
    row: np.ndarray

    def __init__(self, model, kind: str, link, placement=None, other=None,
                 other_placement=None, frame: str = "local_world_aligned",
                 corrector=(0.0, 0.0), q=None):
        if kind not in KINDS:
            raise ValueError(f"constraint kind must be 'point' (3 rows, a point held) or "
                             f"'frame' (6 rows, a frame held), got {kind!r}")
        if frame not in FRAMES:
            raise ValueError(f"constraint frame must be 'local' or 'local_world_aligned' (the "
                             f"frame of its rows and forces), got {frame!r}")
        i = _inputs.link_index(model, link)
        P1 = _placement(placement, "placement")
        j = None if other is None else _inputs.link_index(model, other)
        if j == i:
            raise ValueError(f"a constraint holds a link to another link or to the world; "
                             f"link and other are both {model.link_names[i]!r}")
        try:
            kp, kd = corrector
        except (TypeError, ValueError):
            raise ValueError(f"corrector must be a pair (Kp, Kd) of numbers >= 0, got "
                             f"{corrector!r}") from None
        if other_placement is not None:
            P2 = _placement(other_placement, "other_placement")
        elif j is None:
            q0 = neutral(model) if q is None else _inputs.state(model, q, "q", model.nq)
            if q0.ndim != 1:
                raise ValueError(f"q must be one configuration ({model.nq},), got {q0.shape}")
            P2 = link_placements(model, q0)[i] @ P1  # held where it stands at q
        else:
            P2 = np.eye(4)
        label = f"{kind} {model.link_names[i]}"
        label += " on the world" if j is None else f" on {model.link_names[j]}"
        for name, value in (("model", model), ("kind", kind), ("link", i), ("placement", P1),
                            ("other", j), ("other_placement", P2), ("frame", frame),
                            ("corrector", (_inputs.nonnegative(kp, "corrector Kp"),
                                           _inputs.nonnegative(kd, "corrector Kd"))),
                            ("name", label)):
            object.__setattr__(self, name, value)
        P1.flags.writeable = False
        P2.flags.writeable = False
        b1, F1 = _joint_frame(model, i, P1)
        b2, F2 = (-1, P2) if j is None else _joint_frame(model, j, P2)
        row = np.concatenate([[0.0 if kind == "point" else 1.0, b1, b2,
                               FRAMES.index(frame), *self.corrector],
                              motor_from_matrix(F1), motor_from_matrix(F2)])
        row.flags.writeable = False
        object.__setattr__(self, "row", row)  # its floats in a pack (constraints/core.py)

    @property
    def size(self) -> int:
        """The number of rows: 3 for a point, 6 for a frame."""
        return KINDS[self.kind]

    def __repr__(self) -> str:
        return f"Constraint({self.name}, {self.frame}, corrector={self.corrector})"


def check_constraints(model, constraints) -> tuple[Constraint, ...]:
    """``constraints`` as a tuple of ``Constraint``s of ``model`` (one alone is accepted)."""
    if isinstance(constraints, Constraint):
        constraints = (constraints,)
    try:
        out = tuple(constraints)
    except TypeError:
        raise ValueError(f"constraints must be a list of cgadyn.Constraint, got "
                         f"{type(constraints).__name__}") from None
    for k, c in enumerate(out):
        if not isinstance(c, Constraint):
            raise ValueError(f"constraints[{k}] must be a cgadyn.Constraint, got "
                             f"{type(c).__name__}")
        if c.model is not model and (c.model.name, c.model.link_names, c.model.joint_names) \
                != (model.name, model.link_names, model.joint_names):
            raise ValueError(f"constraints[{k}] ({c.name}) was made for the model "
                             f"{c.model.name!r}, not for this one ({model.name!r})")
    return out


class Pack:
    """A list of constraints as compiled code reads it (``constraints/core.py``): ``array``
    (the header ``[nc, nr]``, then each constraint's ``row``), the first row of each
    constraint (``starts``, the total last) and the native slots it was registered in."""

    def __init__(self, model, constraints: tuple[Constraint, ...]):
        self.model, self.constraints = model, constraints
        self.starts = np.cumsum([0] + [c.size for c in constraints])
        self.nc, self.nr = len(constraints), int(self.starts[-1])
        self.array = np.concatenate([[self.nc, self.nr]] + [c.row for c in constraints])
        self.zero = np.zeros(model.nv)
        self.slots: dict[int, int] = {}
        self.given, self.items = None, None

    def remember(self, given) -> None:
        """Make this the pack of the last list asked for, ``given`` (a list or tuple)."""
        self.given, self.items = given, type(given)(given)
        _LAST[0] = self


_PACKS: dict[tuple, Pack] = {}
_LAST: list = [None]
"""The pack of the last list asked for, with that list and a copy of its items."""
PACKS_KEPT = 64


def pack(model, constraints) -> Pack:
    """The ``Pack`` of ``constraints`` (checked by ``check_constraints``) for ``model``, made
    once per list of constraint objects and kept (the last ``PACKS_KEPT`` lists)."""
    last = _LAST[0]
    if last is not None and model is last.model and constraints is last.given \
            and constraints == last.items:  # the same list, unchanged (compared by identity)
        return last
    key = (id(model), *map(id, constraints)) if type(constraints) in (list, tuple) else None
    found = _PACKS.get(key)
    if found is not None:  # the pack holds the objects, so their ids are still theirs
        found.remember(constraints)
        return found
    p = Pack(model, check_constraints(model, constraints))
    if key is not None:
        if len(_PACKS) >= PACKS_KEPT:
            _PACKS.clear()
        _PACKS[key] = p
        p.remember(constraints)
    return p
