"""What a joint type is, as Python reads it: one record of facts and maps per type.

Compiled code reads a joint's type as an integer and branches on it (``dispatch``); every
other layer (the model, the manifold, the tasks, the rollouts, the converters) asks the
record of that integer (``table.TYPES[t]``) and never names a type itself. Each type's
file (``revolute``, ``prismatic``, ``free_flyer``) builds its records; ``docs/joints.md``
says what each field means in CGA terms and how to add a type.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def _same(x: np.ndarray) -> np.ndarray:
    return x


def _kept(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return lower, upper


def unit_limits(start: int, stop: int) -> Callable:
    """The ``limits`` map of a joint whose coordinates ``start:stop`` are the components of a
    unit vector (a quaternion, a direction ``(cos θ, sin θ)``): the limits given, with those
    components' cut to ``[-1, 1]``, the most they can reach."""

    def limits(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lower, upper = lower.copy(), upper.copy()
        lower[start:stop] = np.maximum(lower[start:stop], -1.0)
        upper[start:stop] = np.minimum(upper[start:stop], 1.0)
        return lower, upper

    return limits


def _unchanged_velocity(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    return v


def _unchanged_acceleration(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    return a


@dataclass(frozen=True)
class JointType:
    """The facts of one joint type. Arrays passed to the maps are one joint's coordinates,
    ``(..., nq)`` or ``(..., nv)``; they return new arrays (``random`` fills in place).

    code: the integer stored in ``Model.joint_types`` and branched on by compiled code.
    name: the type's name (``TYPE_NAMES``); kind: the name a model records in
    ``joint_kinds`` (URDF's joint type where URDF has one); label: how messages call it.
    nq, nv: sizes of the joint's configuration ``q_j`` and velocity ``v_j``.
    q_names, v_names: the coordinates' names, ``()`` for a joint of one coordinate (named
    after the joint itself).
    speeds: per velocity coordinate, ``"angular"``, ``"linear"`` (a slide inside the robot)
    or ``"free"`` (a free body's linear velocity): what a rollout bounds it by.
    actuated: whether an actuator drives the joint (controllers act on these alone).
    floating: whether the joint moves its body by any rigid motion (a floating base; its
    subtree may be computed in its own frame where a quantity is invariant).
    additive: whether ``q ⊕ v = q + v`` coordinate by coordinate (then ``nq == nv``, and
    limits are boxes on the coordinates).
    quaternion: the offset in ``q_j`` of a unit quaternion ``(x, y, z, w)``, -1 for none;
    unit_length: how many coordinates that unit block has, 4 for a quaternion, 2 for a
    planar joint's ``(cos θ, sin θ)`` (a unit complex number, the quaternion of a rotation
    in the plane): checked and normalised alike.
    axis: ``"revolute"`` (a line) or ``"prismatic"`` (a direction) for a joint about or
    along one axis, ``None`` for a joint without one.
    cone: whether the angle of the joint's rotation (its quaternion's, ``v_j`` its angular
    velocity) may be bounded by ``Model.cone_limit``: MuJoCo's ``ball`` ``range``.
    neutral: ``q_j`` at rest (Pinocchio's ``neutral``).
    subspace: the motion subspace ``S_j`` (nv, 6) as CGA twists, from the joint's axis
    twist ``B_j`` (``Model.axes[j]``: ``cga.conventions.twist_from_axis`` of ``axis``;
    zeros for a joint without one).
    limits: the position limits the model keeps, from those given (per q coordinate).
    random: redraws ``q_j`` in place after the uniform draw within the limits (``None``:
    the uniform draw stands); ``(rng, q_j, box)``.
    pinocchio: Pinocchio's ``JointModel`` short names converted to this type;
    pinocchio_nq, to_pinocchio, from_pinocchio: Pinocchio's size of ``q_j`` and the maps.
    mujoco: MuJoCo's joint type (``None``: not in MuJoCo's vocabulary);
    to_mujoco, from_mujoco: ``q_j`` to MuJoCo's qpos and back; mujoco_velocity,
    from_mujoco_velocity: ``(q_j, v_j)`` to MuJoCo's qvel and ``(q_j, qvel_j)`` back
    (a linear map ``qvel = T(q) v`` with T orthogonal, so that generalised forces, dual to
    velocities, convert by the same maps: ``τ = Tᵀ τ_mj`` is ``from_mujoco_velocity``);
    mujoco_acceleration, from_mujoco_acceleration: ``(q_j, v_j, a_j)`` to MuJoCo's qacc
    (``T a + Ṫ v``) and ``(q_j, v_j, qacc_j)`` back.
    """

    code: int
    name: str
    kind: str
    label: str
    nq: int
    nv: int
    speeds: tuple[str, ...]
    actuated: bool
    floating: bool
    additive: bool
    neutral: tuple[float, ...]
    subspace: Callable[[np.ndarray], np.ndarray]
    pinocchio: tuple[str, ...]
    mujoco: str | None
    q_names: tuple[str, ...] = ()
    v_names: tuple[str, ...] = ()
    quaternion: int = -1
    unit_length: int = 4
    axis: str | None = None
    cone: bool = False
    limits: Callable = _kept
    random: Callable | None = None
    pinocchio_nq: int | None = None
    to_pinocchio: Callable = _same
    from_pinocchio: Callable = _same
    to_mujoco: Callable = _same
    from_mujoco: Callable = _same
    mujoco_velocity: Callable = _unchanged_velocity
    from_mujoco_velocity: Callable = _unchanged_velocity
    mujoco_acceleration: Callable = _unchanged_acceleration
    from_mujoco_acceleration: Callable = _unchanged_acceleration

    def __post_init__(self):
        if self.pinocchio_nq is None:
            object.__setattr__(self, "pinocchio_nq", self.nq)
        sizes = {"speeds": (len(self.speeds), self.nv), "neutral": (len(self.neutral), self.nq),
                 "q_names": (len(self.q_names) or 1, self.nq),
                 "v_names": (len(self.v_names) or 1, self.nv)}
        for field, (got, expected) in sizes.items():
            if got != expected:
                raise ValueError(f"joint type {self.name!r}: {field} has {got} entries, "
                                 f"expected {expected}")
        if self.additive and self.nq != self.nv:
            raise ValueError(f"joint type {self.name!r} is additive with nq {self.nq} != "
                             f"nv {self.nv}")
