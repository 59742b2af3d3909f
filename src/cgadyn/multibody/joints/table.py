"""Every joint type's record by its code, and the questions about a model's joints that
the other layers ask (``record.JointType``).

``TYPES[t]`` is the record of type code t; ``NQ``, ``NV``, ... its columns. The functions
walk a :class:`~cgadyn.multibody.Model`'s joints and ask each one's record. (The columns
that compiled code reads are in ``dispatch``, a file of compiled code, so that numba's cache
follows them.)
"""

from __future__ import annotations

import numpy as np

from . import free_flyer, helical, planar, prismatic, revolute, spherical, translation
from .record import JointType

TYPES: tuple[JointType, ...] = tuple(sorted(
    (*revolute.TYPES, *prismatic.TYPES, *free_flyer.TYPES, *spherical.TYPES, *planar.TYPES,
     *translation.TYPES, *helical.TYPES), key=lambda r: r.code))
"""The record of every joint type, indexed by its code."""
assert tuple(r.code for r in TYPES) == tuple(range(len(TYPES))), "codes 0, 1, 2, ..."

TYPE_NAMES = tuple(r.name for r in TYPES)
NQ = tuple(r.nq for r in TYPES)
"""Size of a joint's configuration, by type."""
NV = tuple(r.nv for r in TYPES)
"""Size of a joint's velocity, by type."""
ACTUATED = tuple(r.actuated for r in TYPES)
"""Whether a joint of this type has an actuator of its own, by type."""
SPEEDS = tuple(r.speeds for r in TYPES)
"""What each velocity coordinate of a joint is, by type (``record.JointType.speeds``)."""
KIND_TYPE = {r.kind: r.code for r in TYPES}
"""The joint kinds a model records (URDF's names, and ``free_flyer``) and their types."""
JOINT_KINDS = tuple(KIND_TYPE)
PINOCCHIO = {name: r for r in TYPES for name in r.pinocchio}
"""Pinocchio's ``JointModel`` short names and the record each converts to."""

def of_kind(kind: str) -> JointType:
    """The record of a joint kind (``joint_kinds``), or a ``ValueError`` naming the kinds."""
    if kind not in KIND_TYPE:
        raise ValueError(f"unknown joint kind {kind!r}, expected one of {JOINT_KINDS}")
    return TYPES[KIND_TYPE[kind]]


def joints_of(model) -> list[tuple[int, JointType, slice, slice]]:
    """``(j, record, q slice, v slice)`` for every joint of a model, in order."""
    iq, iv = model.idx_q, model.idx_v
    return [(j, TYPES[int(t)], slice(int(iq[j]), int(iq[j + 1])),
             slice(int(iv[j]), int(iv[j + 1]))) for j, t in enumerate(model.joint_types)]


def flat(joint_types) -> bool:
    """Whether every joint is additive: the whole configuration a vector of coordinates,
    ``q ⊕ v = q + v`` (the packed model's ``flat``, compiled code's shortcut)."""
    return all(TYPES[int(t)].additive for t in joint_types)


def coordinate_names(model, velocity: bool = False) -> list[str]:
    """One label per configuration (or velocity) coordinate: the joint's name, or
    ``joint.coordinate`` for a joint of several (a free flyer's ``x``, ``qx``, ``vx``...)."""
    labels = []
    for j, joint, _, _ in joints_of(model):
        names = joint.v_names if velocity else joint.q_names
        name = model.joint_names[j]
        labels += [f"{name}.{p}" for p in names] if names else [name]
    return labels


def describe(model, velocity: bool, k: int) -> str:
    """Which joint (and which of its coordinates) entry k of a configuration or velocity is."""
    offsets = model.idx_v if velocity else model.idx_q
    j = int(np.searchsorted(offsets, k, side="right") - 1)
    joint = TYPES[int(model.joint_types[j])]
    names = joint.v_names if velocity else joint.q_names
    where = f"joint {model.joint_names[j]!r}"
    return f"{where}, coordinate {names[k - offsets[j]]}" if names else where


def layout(model, velocity: bool) -> str:
    """The order of a state's entries: the joints, each with its coordinates' names."""
    parts = []
    for j, joint, _, _ in joints_of(model):
        names = joint.v_names if velocity else joint.q_names
        name = model.joint_names[j]
        parts.append(f"{name} ({', '.join(names)})" if names else name)
    return "joint order " + ", ".join(parts)


def quaternions(model) -> list[tuple[int, int, int]]:
    """``(joint, first index in q, length)`` of every unit quaternion of a configuration
    (and of every planar joint's ``(cos θ, sin θ)``, of length 2)."""
    return [(j, s.start + joint.quaternion, joint.unit_length)
            for j, joint, s, _ in joints_of(model) if joint.quaternion >= 0]


def neutral(model) -> np.ndarray:
    """The neutral configuration: every joint's ``neutral``."""
    return neutral_of_types(model.joint_types)


def neutral_of_types(joint_types) -> np.ndarray:
    """The neutral configuration of joints of these types, in order."""
    return np.concatenate([np.asarray(TYPES[int(t)].neutral, dtype=float)
                           for t in joint_types] or [np.zeros(0)])


def additive_values(model, q) -> np.ndarray:
    """``q`` per velocity coordinate (..., nv) for the joints whose coordinates add, zero on
    the others: what springs and fixed tendons read (MuJoCo's ``qpos`` of hinges and
    slides)."""
    q = np.asarray(q, dtype=float)
    out = np.zeros(q.shape[:-1] + (model.nv,))
    for _, joint, s, t in joints_of(model):
        if joint.additive:
            out[..., t] = q[..., s]
    return out


def additive_index(model) -> np.ndarray:
    """(nv,) the index in q of each velocity coordinate of a joint whose coordinates add
    (one q per v), -1 on the others: where fixed tendons and couplings read q."""
    out = np.full(model.nv, -1, dtype=np.int64)
    for _, joint, s, t in joints_of(model):
        if joint.additive:
            out[t] = np.arange(s.start, s.stop)
    return out


def spring_deflection(model, q) -> np.ndarray:
    """``q - spring_reference`` per velocity coordinate (..., nv) for the joints whose
    coordinates add, zero on the others (which carry no spring: ``Model._check_passive``);
    MuJoCo's ``qpos - qpos_spring`` of hinges and slides."""
    return additive_values(model, q) - additive_values(model, model.spring_reference)


def random_configuration(model, rng: np.random.Generator, box: float) -> np.ndarray:
    """Every coordinate uniform within its limits (``[-π, π]`` where unbounded), then each
    joint's own ``random`` (a free flyer's position in the box, its rotation uniform)."""
    lower = np.where(np.isfinite(model.lower), model.lower, -np.pi)
    upper = np.where(np.isfinite(model.upper), model.upper, np.pi)
    q = rng.uniform(lower, upper)
    for _, joint, s, _ in joints_of(model):
        if joint.random is not None:
            joint.random(rng, q[s], box)
    return q


def normalize(model, q: np.ndarray) -> np.ndarray:
    """``q`` (a new array, (..., nq)) with every unit quaternion (and planar ``(cos θ,
    sin θ)``) scaled to unit length."""
    for j, i, n in quaternions(model):
        quat = q[..., i:i + n]
        norm = np.linalg.norm(quat, axis=-1, keepdims=True)
        if not np.all(norm > 0.0) or not np.all(np.isfinite(norm)):
            raise ValueError(f"q[..., {i}:{i + n}] (the unit coordinates of joint "
                             f"{model.joint_names[j]!r}) is zero or not finite: it has no "
                             f"direction to normalise")
        q[..., i:i + n] = quat / norm
    return q


def middle(model) -> np.ndarray:
    """The middle of every additive joint's range (0 where unbounded), every other joint
    neutral."""
    q = neutral(model)
    ok = np.isfinite(model.lower) & np.isfinite(model.upper)
    for _, joint, s, _ in joints_of(model):
        if joint.additive:
            for i in range(s.start, s.stop):
                if ok[i]:
                    q[i] = 0.5 * (model.lower[i] + model.upper[i])
    return q


def _convert(model, x: np.ndarray, sizes, convert, what: str, size: str) -> np.ndarray:
    """Each joint's block of ``x`` (..., Σ sizes(joint)) through ``convert(joint, block)``;
    ``what`` and ``size`` name the layout and its size in the error for a wrong one."""
    parts, i = [], 0
    for _, joint, _, _ in joints_of(model):
        length = sizes(joint)
        parts.append(convert(joint, x[..., i:i + length]))
        i += length
    if i != x.shape[-1]:
        raise ValueError(f"a {what} of {model.name!r} has {i} entries ({size}), got "
                         f"{x.shape[-1]}")
    return np.concatenate(parts, axis=-1) if parts else x


def to_pinocchio(model, q) -> np.ndarray:
    """cgadyn's configuration(s) (..., nq) in Pinocchio's layout (``to_pinocchio``)."""
    return _convert(model, np.asarray(q, dtype=float), lambda r: r.nq,
                    lambda r, b: r.to_pinocchio(b), "configuration", "nq")


def from_pinocchio(model, qp) -> np.ndarray:
    """Pinocchio's configuration(s) (..., Pinocchio's nq) in cgadyn's layout."""
    return _convert(model, np.asarray(qp, dtype=float), lambda r: r.pinocchio_nq,
                    lambda r, b: r.from_pinocchio(b), "Pinocchio configuration",
                    "Pinocchio's nq")


def to_mujoco(model, q) -> np.ndarray:
    """cgadyn's configuration(s) (..., nq) as MuJoCo's qpos (``to_mujoco``)."""
    return _convert(model, np.asarray(q, dtype=float), lambda r: r.nq,
                    lambda r, b: r.to_mujoco(b), "configuration", "nq")


def from_mujoco(model, qpos) -> np.ndarray:
    """MuJoCo's qpos (..., nq) in cgadyn's layout."""
    return _convert(model, np.asarray(qpos, dtype=float), lambda r: r.nq,
                    lambda r, b: r.from_mujoco(b), "MuJoCo qpos", "nq")


def mujoco_velocity(model, q, v) -> np.ndarray:
    """cgadyn's velocity (..., nv) at q as MuJoCo's qvel (a free joint's linear velocity
    in the parent frame)."""
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    parts = [joint.mujoco_velocity(q[..., s], v[..., t]) for _, joint, s, t in joints_of(model)]
    return np.concatenate(parts, axis=-1) if parts else v


def from_mujoco_velocity(model, q, qvel) -> np.ndarray:
    """MuJoCo's qvel (..., nv) at q in cgadyn's layout."""
    q, qvel = np.asarray(q, dtype=float), np.asarray(qvel, dtype=float)
    parts = [joint.from_mujoco_velocity(q[..., s], qvel[..., t])
             for _, joint, s, t in joints_of(model)]
    return np.concatenate(parts, axis=-1) if parts else qvel


def mujoco_acceleration(model, q, v, a) -> np.ndarray:
    """cgadyn's acceleration (..., nv) at (q, v) as MuJoCo's qacc (a free joint's linear
    part ``R (v̇ + ω × v)``)."""
    q, v, a = (np.asarray(x, dtype=float) for x in (q, v, a))
    parts = [joint.mujoco_acceleration(q[..., s], v[..., t], a[..., t])
             for _, joint, s, t in joints_of(model)]
    return np.concatenate(parts, axis=-1) if parts else a


def from_mujoco_acceleration(model, q, v, qacc) -> np.ndarray:
    """MuJoCo's qacc (..., nv) at (q, v) (cgadyn's layout) in cgadyn's layout."""
    q, v, qacc = (np.asarray(x, dtype=float) for x in (q, v, qacc))
    parts = [joint.from_mujoco_acceleration(q[..., s], v[..., t], qacc[..., t])
             for _, joint, s, t in joints_of(model)]
    return np.concatenate(parts, axis=-1) if parts else qacc
