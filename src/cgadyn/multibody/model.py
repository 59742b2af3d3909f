"""The immutable multibody :class:`Model`: a kinematic tree of joints.

A model holds, for every joint ``j = 0..n-1`` (in Pinocchio's order for the same URDF),
its type (``cgadyn.multibody.joints``: revolute, prismatic, or a free-flyer root), the
index of its parent joint, its placement as a CGA motor, its screw axis as a CGA twist
(one-dof joints) and the CGA inertia of its body (every link attached to it through fixed
joints merged in). It also keeps the raw physical data (4x4 placements, unit axes, mass,
centre of mass, rotational inertia) and the frames of every URDF link.

All arrays are read-only; build a model with :func:`build_model` (from raw data) or
:func:`cgadyn.multibody.load_urdf` (from a URDF).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .joints import ACTUATED, JOINT_KINDS, KIND_TYPE, NQ, NV, SPEEDS, TYPE_NAMES, TYPES
from .joints.dispatch import unit_axes
from .joints.table import coordinate_names, of_kind
from .packed import pack

_ARRAY_FIELDS = (
    "joint_types",
    "parents",
    "placements",
    "axes",
    "inertias",
    "body_mass",
    "body_com",
    "body_rotational_inertia",
    "lower",
    "upper",
    "velocity_limit",
    "effort_limit",
    "link_joint",
    "link_placements",
    "placement_matrices",
    "axis_vectors",
    "link_placement_matrices",
    "armature",
    "damping",
    "friction",
    "stiffness",
    "spring_reference",
    "home",
    "cone_limit",
    "actuator_dof",
    "actuator_gear",
    "actuator_gain",
    "actuator_bias",
    "actuator_tendon",
    "actuator_ctrlrange",
    "actuator_forcerange",
    "actuator_time_constant",
    "actuator_actrange",
    "tendon_coefficients",
    "tendon_stiffness",
    "tendon_damping",
    "tendon_spring_length",
    "tendon_range",
    "tendon_friction",
    "coupling_coefficients",
    "coupling_offset",
    "rope_links",
    "rope_points",
    "rope_range",
)


ACTIVATION_DYNAMICS = ("none", "integrator", "filter", "filterexact")
"""An actuator's activation dynamics (``Model.actuator_dynamics``; A2)."""


@dataclass(frozen=True, eq=False)
class Model:
    """A robot: a tree of joints with rigid bodies.

    Joint ``j`` (``0 <= j < n``) moves body ``j``; its frame is the URDF child link frame
    of that joint (for a free-flyer root: the root link's frame). The order of the joints,
    and so of ``q``, ``v``, ``a`` and ``tau``, is Pinocchio's for the same URDF (see
    ``joint_names``); joint j's coordinates are ``q[idx_q[j]:idx_q[j+1]]`` and
    ``v[idx_v[j]:idx_v[j+1]]``. A one-dof joint takes one coordinate (a continuous joint
    one angle, not Pinocchio's cos and sin); a free-flyer root (``root_joint``) takes
    Pinocchio's ``[x, y, z, qx, qy, qz, qw]`` in q and the body twist ``[v, ω]`` in v
    (``multibody.joints``: every joint type's sizes and layout). Without a floating root
    the root link is fixed to the world.

    Mimic joints are treated as independent joints, as Pinocchio does by default; the
    ``mimic`` attribute records the URDF ``<mimic>`` data (leader joint name, multiplier,
    offset) or ``None`` per joint, for information only.

    Attributes
    ----------
    name : str
        The robot's name.
    joint_names : tuple[str, ...]
        Joints, in Pinocchio's order (``pin_model.names[1:]``).
    joint_kinds : tuple[str, ...]
        The kind of each joint (``multibody.joints.JOINT_KINDS``: URDF's type names, and
        ``'free_flyer'``).
    joint_types : int64 (n,)
        The type code of each joint (``multibody.joints.TYPES``: its record).
    parents : int64 (n,)
        Parent joint index, ``-1`` for the world; ``parents[j] < j``.
    placements : float64 (n, 8)
        CGA motor of joint frame ``j`` in its parent joint frame (the world for ``-1``)
        at ``q = 0``, fixed joints in between composed in (Pinocchio's
        ``model.jointPlacements[j + 1]``).
    axes : float64 (n, 6)
        Joint screw ``B_j`` as a CGA twist in joint frame ``j``, with a unit axis (zero for
        a free flyer, whose motion subspace is every twist).
    inertias : float64 (n, 6, 6)
        CGA inertia of body ``j`` in joint frame ``j`` (Pinocchio's ``model.inertias[j+1]``).
    body_mass : float64 (n,)
    body_com : float64 (n, 3)
        Centre of mass of body ``j`` in joint frame ``j``.
    body_rotational_inertia : float64 (n, 3, 3)
        Rotational inertia of body ``j`` about its centre of mass, axes of joint frame ``j``.
    lower, upper : float64 (nq,)
        Position limits per configuration coordinate (``-inf``/``inf`` for continuous joints
        and a free flyer's translation, ``±1`` for its quaternion).
    velocity_limit, effort_limit : float64 (nv,)
        Velocity and effort limits (``inf`` where the URDF gives none).
    link_names : tuple[str, ...]
        Every URDF link, in the order of the URDF file.
    link_joint : int64 (nl,)
        Index of the joint whose body the link is rigidly attached to, ``-1`` for the world.
    link_placements : float64 (nl, 8)
        CGA motor of the link frame in the frame of joint ``link_joint`` (or the world).
    root_link : str
        The URDF root link, fixed to the world.
    placement_matrices : float64 (n, 4, 4)
        ``placements`` as homogeneous 4x4 matrices.
    axis_vectors : float64 (n, 3)
        Unit joint axes in joint frame ``j`` (zero for a free flyer).
    link_placement_matrices : float64 (nl, 4, 4)
        ``link_placements`` as homogeneous 4x4 matrices.
    mimic : tuple
        ``None`` or ``(leader_joint_name, multiplier, offset)`` per joint (information only).
    armature : float64 (nv,)
        Rotor inertia per velocity coordinate, added to the mass matrix's diagonal
        (Pinocchio's ``model.armature``, MuJoCo's ``dof_armature``): every algorithm of
        the dynamics includes it.
    damping : float64 (nv,)
        Viscous damping per velocity coordinate (MuJoCo's ``dof_damping``, URDF's
        ``<dynamics damping>``, Pinocchio's ``model.damping``): the passive torque
        ``-damping * v`` (``cgadyn.passive_torques``), not part of rnea or aba.
    friction : float64 (nv,)
        Dry friction per velocity coordinate, the largest torque (force) a joint's friction
        loss opposes its motion with (MuJoCo's ``dof_frictionloss``, URDF's ``<dynamics
        friction>``, Pinocchio's ``model.friction``): enforced only by the contact step
        (``contact_step``, ``simulate(..., world=...)``) as a box-bounded row
        (``docs/contact.md``, "Friction loss", K30), never by rnea or aba.
    cone_limit : float64 (n,)
        The largest angle (rad) a joint's rotation may reach, ``inf`` for none: MuJoCo's
        ``ball`` ``range`` (finite only for a joint whose record has ``cone``). Enforced,
        as the joint limits are, only by the contact step (``docs/contact.md``, "Joint
        limits", K26).
    stiffness : float64 (nv,)
        Joint spring stiffness per velocity coordinate (MuJoCo's ``jnt_stiffness``),
        nonzero only on additive joints: the passive torque
        ``-stiffness * (q - spring_reference)``.
    spring_reference : float64 (nq,)
        The configuration at which the springs are relaxed (MuJoCo's ``qpos_spring``, in
        cgadyn's layout); defaults to the neutral configuration.
    home : float64 (nq,)
        The configuration the model's file draws the robot in: MuJoCo's ``qpos0`` (each
        joint's ``ref``, in cgadyn's layout; Gymnasium's and dm_control's episodes start
        there, the hopper's torso 1.25 m up its ``rootz`` slide), the neutral configuration
        for a URDF. ``cgadyn simulate`` starts there.
    actuator_names : tuple[str, ...]
        The actuators (MuJoCo's ``<motor>``, ``<position>``, ``<velocity>`` on a joint or a
        fixed tendon), none by default
        (``cgadyn.actuator_torques``, ``simulate(ctrl=...)``).
    actuator_dof : int64 (na,)
        The velocity coordinate each joint motor drives (-1 for a tendon's motor).
    actuator_tendon : int64 (na,)
        The fixed tendon each tendon motor pulls (its index in ``tendon_names``; MuJoCo's
        ``<motor tendon=...>``: the torque ``gear · force · c_t``), -1 for a joint motor.
    actuator_gear : float64 (na,)
        The transmission's ratio (MuJoCo's ``gear``): the actuator's length is ``gear``
        times the coordinate's (or the tendon's), its torque ``gear`` times its force.
    actuator_gain, actuator_bias : float64 (na,), (na, 3)
        The force ``gain · ctrl + b₀ + b₁ L + b₂ L̇`` of a control at the actuator's length
        L and its rate (MuJoCo's fixed ``gainprm[0]`` and affine ``biasprm[:3]``): a motor
        has gain 1 and no bias, a position servo ``kp`` and ``(0, -kp, -kv)``, a velocity
        servo ``kv`` and ``(0, 0, -kv)`` (``algorithms.actuators``, A1).
    actuator_ctrlrange, actuator_forcerange : float64 (na, 2)
        The control's range and the range of the force before the gear (``±inf``: none),
        as MuJoCo clamps them.
    actuator_dynamics : tuple[str, ...]
        Each actuator's activation dynamics (MuJoCo's ``dyntype``): ``"none"`` (the force
        takes the control), or an activation state ``w`` that the force takes in its
        place, moved by the control ``u``: ``"integrator"`` (``ẇ = u``), ``"filter"`` and
        ``"filterexact"`` (``ẇ = (u - w) / T``, stepped by Euler or exactly;
        ``cgadyn.activations``, ``docs/joints.md``, A2). ``"none"`` by default.
    actuator_time_constant : float64 (na,)
        A filter's time constant T (MuJoCo's ``dynprm[0]``); 0 for the others.
    actuator_actrange : float64 (na, 2)
        The range the activation is clamped to after each step (MuJoCo's ``actrange`` where
        ``actlimited``; ``±inf``: none).
    tendon_names : tuple[str, ...]
        The fixed tendons that carry a spring, a damper or a friction loss, that a motor
        pulls or that are limited (MuJoCo's ``<fixed>`` tendons), none by default.
    tendon_coefficients : float64 (nt, nv)
        Each tendon's length ``L = Σ_k c_k q_k`` over the coordinates of joints whose
        coordinates add (MuJoCo's ``coef`` of each ``<joint>`` of the tendon).
    tendon_stiffness, tendon_damping : float64 (nt,)
        The tendon's spring and damper: the passive force ``-k dev(L) - b L̇`` along it,
        ``dev(L)`` the length's distance outside ``tendon_spring_length``
        (``cgadyn.passive_torques``, ``docs/joints.md``, P2).
    tendon_spring_length : float64 (nt, 2)
        The lengths between which the spring is relaxed (MuJoCo's ``springlength``, a
        dead band; one length where the two are equal).
    tendon_range : float64 (nt, 2)
        The lengths the tendon is held between (MuJoCo's ``range`` where ``limited``;
        ``±inf``: none), a limit that the contact step enforces as a joint's
        (``docs/contact.md``, K26'').
    tendon_friction : float64 (nt,)
        The tendon's dry friction (MuJoCo's ``frictionloss``): a force of at most this
        along it, held by the contact step as a joint's friction loss (K30).
    coupling_names : tuple[str, ...]
        Linear couplings of coordinates (MuJoCo's ``<equality joint>`` and ``<equality
        tendon>`` of a linear polynomial), none by default: bilateral constraints that the
        contact step holds (``docs/contact.md``, "Couplings", K45).
    coupling_coefficients, coupling_offset : float64 (ne, nv), (ne,)
        Coupling c holds ``Σ_k a_ck q_k = b_c`` (``a_c`` its coefficients, ``b_c`` its
        offset) over the coordinates of joints whose coordinates add.
    rope_names : tuple[str, ...]
        Ropes: the distance between two points, each fixed on a link (or in the world),
        bounded (MuJoCo's limited spatial tendon of two sites: dm_control ball_in_cup's
        string), none by default: unilateral constraints that the contact step holds
        (``docs/contact.md``, "Ropes", K46).
    rope_links : int64 (nr, 2)
        The links of each rope's two ends (-1: the world).
    rope_points : float64 (nr, 2, 3)
        Each end's point in its link's frame (in the world's for -1).
    rope_range : float64 (nr, 2)
        The shortest and longest distance allowed (``0`` and ``inf``: no bound).
    """

    name: str
    joint_names: tuple
    joint_kinds: tuple
    joint_types: np.ndarray
    parents: np.ndarray
    placements: np.ndarray
    axes: np.ndarray
    inertias: np.ndarray
    body_mass: np.ndarray
    body_com: np.ndarray
    body_rotational_inertia: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    velocity_limit: np.ndarray
    effort_limit: np.ndarray
    link_names: tuple
    link_joint: np.ndarray
    link_placements: np.ndarray
    root_link: str
    placement_matrices: np.ndarray
    axis_vectors: np.ndarray
    link_placement_matrices: np.ndarray
    mimic: tuple
    armature: np.ndarray | None = None
    damping: np.ndarray | None = None
    friction: np.ndarray | None = None
    stiffness: np.ndarray | None = None
    spring_reference: np.ndarray | None = None
    home: np.ndarray | None = None
    cone_limit: np.ndarray | None = None
    actuator_names: tuple = ()
    actuator_dof: np.ndarray | None = None
    actuator_gear: np.ndarray | None = None
    actuator_gain: np.ndarray | None = None
    actuator_bias: np.ndarray | None = None
    actuator_tendon: np.ndarray | None = None
    actuator_ctrlrange: np.ndarray | None = None
    actuator_forcerange: np.ndarray | None = None
    actuator_dynamics: tuple = ()
    actuator_time_constant: np.ndarray | None = None
    actuator_actrange: np.ndarray | None = None
    tendon_names: tuple = ()
    tendon_coefficients: np.ndarray | None = None
    tendon_stiffness: np.ndarray | None = None
    tendon_damping: np.ndarray | None = None
    tendon_spring_length: np.ndarray | None = None
    tendon_range: np.ndarray | None = None
    tendon_friction: np.ndarray | None = None
    coupling_names: tuple = ()
    coupling_coefficients: np.ndarray | None = None
    coupling_offset: np.ndarray | None = None
    rope_names: tuple = ()
    rope_links: np.ndarray | None = None
    rope_points: np.ndarray | None = None
    rope_range: np.ndarray | None = None

    def __post_init__(self):
        nv = sum(NV[int(t)] for t in np.asarray(self.joint_types).reshape(-1))
        for field in ("armature", "damping", "friction", "stiffness"):  # none given: none
            if getattr(self, field) is None:
                object.__setattr__(self, field, np.zeros(nv))
        na = len(self.actuator_names)
        defaults = {"actuator_dof": np.zeros(na, dtype=np.int64), "actuator_gear": np.ones(na),
                    "actuator_gain": np.ones(na), "actuator_bias": np.zeros((na, 3)),
                    "actuator_tendon": np.full(na, -1, dtype=np.int64),
                    "actuator_ctrlrange": np.tile([-np.inf, np.inf], (na, 1)),
                    "actuator_forcerange": np.tile([-np.inf, np.inf], (na, 1)),
                    "actuator_time_constant": np.zeros(na),
                    "actuator_actrange": np.tile([-np.inf, np.inf], (na, 1))}
        if not self.actuator_dynamics:
            object.__setattr__(self, "actuator_dynamics", ("none",) * na)
        nt = len(self.tendon_names)
        defaults.update({"tendon_coefficients": np.zeros((nt, nv)),
                         "tendon_stiffness": np.zeros(nt), "tendon_damping": np.zeros(nt),
                         "tendon_spring_length": np.zeros((nt, 2)),
                         "tendon_range": np.tile([-np.inf, np.inf], (nt, 1)),
                         "tendon_friction": np.zeros(nt)})
        ne = len(self.coupling_names)
        defaults.update({"coupling_coefficients": np.zeros((ne, nv)),
                         "coupling_offset": np.zeros(ne)})
        nr = len(self.rope_names)
        defaults.update({"rope_links": np.zeros((nr, 2), dtype=np.int64),
                         "rope_points": np.zeros((nr, 2, 3)),
                         "rope_range": np.tile([0.0, np.inf], (nr, 1))})
        for field, value in defaults.items():
            if getattr(self, field) is None:
                object.__setattr__(self, field, value.reshape((len(value),) + value.shape[1:]))
        if self.cone_limit is None:
            object.__setattr__(self, "cone_limit",
                               np.full(len(np.asarray(self.joint_types).reshape(-1)), np.inf))
        for field in ("spring_reference", "home"):
            if getattr(self, field) is None:
                from .joints.table import neutral_of_types

                object.__setattr__(self, field,
                                   neutral_of_types(np.asarray(self.joint_types).reshape(-1)))
        for field in _ARRAY_FIELDS:
            arr = getattr(self, field)
            dtype = np.int64 if field in ("joint_types", "parents", "link_joint",
                                          "actuator_dof", "actuator_tendon",
                                          "rope_links") else np.float64
            arr = np.array(arr, dtype=dtype, copy=True)
            arr.flags.writeable = False
            object.__setattr__(self, field, arr)
        for field in ("joint_names", "joint_kinds", "link_names", "mimic", "actuator_names",
                      "actuator_dynamics", "tendon_names", "coupling_names", "rope_names"):
            object.__setattr__(self, field, tuple(getattr(self, field)))
        self._check()

    def _check(self):
        n = len(self.joint_names)
        nl = len(self.link_names)
        for t in self.joint_types:
            if not 0 <= t < len(TYPE_NAMES):
                raise ValueError(f"unknown joint type {t}, expected one of "
                                 f"{dict(enumerate(TYPE_NAMES))}")
        nq, nv = sum(NQ[t] for t in self.joint_types), sum(NV[t] for t in self.joint_types)
        shapes = {
            "joint_types": (n,),
            "parents": (n,),
            "placements": (n, 8),
            "axes": (n, 6),
            "inertias": (n, 6, 6),
            "body_mass": (n,),
            "body_com": (n, 3),
            "body_rotational_inertia": (n, 3, 3),
            "lower": (nq,),
            "upper": (nq,),
            "velocity_limit": (nv,),
            "effort_limit": (nv,),
            "link_joint": (nl,),
            "link_placements": (nl, 8),
            "placement_matrices": (n, 4, 4),
            "axis_vectors": (n, 3),
            "link_placement_matrices": (nl, 4, 4),
            "armature": (nv,),
            "damping": (nv,),
            "friction": (nv,),
            "stiffness": (nv,),
            "spring_reference": (nq,),
            "home": (nq,),
            "cone_limit": (n,),
            "actuator_dof": (len(self.actuator_names),),
            "actuator_gear": (len(self.actuator_names),),
            "actuator_tendon": (len(self.actuator_names),),
            "actuator_ctrlrange": (len(self.actuator_names), 2),
            "actuator_forcerange": (len(self.actuator_names), 2),
            "actuator_time_constant": (len(self.actuator_names),),
            "actuator_actrange": (len(self.actuator_names), 2),
            "tendon_coefficients": (len(self.tendon_names), nv),
            "tendon_stiffness": (len(self.tendon_names),),
            "tendon_damping": (len(self.tendon_names),),
            "tendon_spring_length": (len(self.tendon_names), 2),
            "tendon_range": (len(self.tendon_names), 2),
            "tendon_friction": (len(self.tendon_names),),
            "coupling_coefficients": (len(self.coupling_names), nv),
            "coupling_offset": (len(self.coupling_names),),
            "rope_links": (len(self.rope_names), 2),
            "rope_points": (len(self.rope_names), 2, 3),
            "rope_range": (len(self.rope_names), 2),
        }
        for field, shape in shapes.items():
            got = getattr(self, field).shape
            if got != shape:
                raise ValueError(f"Model.{field} has shape {got}, expected {shape}")
        for field in ("joint_kinds", "mimic"):
            if len(getattr(self, field)) != n:
                raise ValueError(f"Model.{field} has {len(getattr(self, field))} entries, "
                                 f"expected {n}")
        for kind, t in zip(self.joint_kinds, self.joint_types, strict=True):
            if kind not in KIND_TYPE or of_kind(kind).code != t:
                raise ValueError(f"joint kind {kind!r} does not match joint type {t}; "
                                 f"expected one of {JOINT_KINDS}")
        open_path = []  # the joints on the path from the root to the last one seen
        for j, p in enumerate(self.parents):
            if not -1 <= p < j:
                raise ValueError(f"parents[{j}] = {p}: a parent must come before its child "
                                 f"(-1 <= parents[j] < j)")
            while open_path and open_path[-1] != p:
                open_path.pop()
            if p >= 0 and not open_path:
                raise ValueError(f"parents[{j}] = {p}: joints must be in depth-first order "
                                 f"(every subtree contiguous, as Pinocchio orders them), but "
                                 f"joint {p}'s subtree was already closed")
            open_path.append(j)
        self._check_axes()
        self._check_inertias()
        self._check_passive()
        self._check_actuators()
        self._check_tendons()
        self._check_couplings()
        self._check_ropes()
        if np.any((self.link_joint < -1) | (self.link_joint >= n)):
            raise ValueError("link_joint entries must lie in [-1, n)")
        if len(set(self.joint_names)) != n:
            raise ValueError("joint names must be unique")

    def _check_inertias(self):
        """Each body's inertia is a rigid body's: the recursions read it from its ten
        parameters (``kernels.rigid``). In Pinocchio's order ``[v, ω]`` that is the
        symmetric ``[[m 1, -m [c]×], [m [c]×, Ī_O]]``."""
        from ..cga.conventions import inertia_to_pinocchio

        for j, P in enumerate(inertia_to_pinocchio(self.inertias)):
            tol = 1e-9 * max(1.0, float(np.abs(P).max()))
            skew = P[:3, 3:]
            if not (np.abs(P[:3, :3] - P[0, 0] * np.eye(3)).max() <= tol
                    and np.abs(skew + skew.T).max() <= tol and np.abs(P - P.T).max() <= tol):
                raise ValueError(
                    f"Model.inertias[{j}] (body of joint {self.joint_names[j]!r}) is not a "
                    f"rigid body's inertia: expected, in Pinocchio's order [v, ω], the "
                    f"symmetric [[m 1, -m [c]x], [m [c]x, I]], got "
                    f"{np.round(P, 6).tolist()}")

    def _check_passive(self):
        """Armature, damping, friction and stiffness are finite and non-negative (a negative
        armature, damping or friction would feed energy in); a spring only on a joint whose
        coordinates add (``q ⊕ v = q + v``), where ``-k (q - q_ref)`` is MuJoCo's spring;
        the spring reference finite; a cone limit positive, and only on a joint with a cone."""
        for field in ("armature", "damping", "friction", "stiffness"):
            values = getattr(self, field)
            bad = np.flatnonzero(~(np.isfinite(values) & (values >= 0.0)))
            if bad.size:
                k = int(bad[0])
                raise ValueError(f"Model.{field}[{k}] (joint "
                                 f"{self.joint_names[self.dof_joint[k]]!r}) is {values[k]}; "
                                 f"expected a finite number >= 0")
        for field in ("spring_reference", "home"):
            if not np.all(np.isfinite(getattr(self, field))):
                raise ValueError(f"Model.{field} has entries that are not finite; "
                                 f"expected a configuration")
        for j, t in enumerate(self.joint_types):
            limit = float(self.cone_limit[j])
            if not (limit > 0.0) or (np.isfinite(limit) and not TYPES[int(t)].cone):
                raise ValueError(f"Model.cone_limit[{j}] (joint {self.joint_names[j]!r}, "
                                 f"{TYPES[int(t)].label}) is {limit}; expected inf, or an "
                                 f"angle > 0 for a joint whose rotation a cone may bound "
                                 f"(spherical)")
            if not TYPES[int(t)].additive and np.any(self.stiffness[self.joint_dofs(j)]):
                raise ValueError(f"joint {self.joint_names[j]!r} ({TYPES[int(t)].label}) "
                                 f"has a nonzero stiffness; cgadyn models joint springs only "
                                 f"on joints whose coordinates add (revolute, prismatic)")

    def _check_actuators(self):
        """Each motor drives an existing velocity coordinate, or pulls an existing tendon
        (its coordinate then -1), with a finite gear; its ranges are ordered (``lower <=
        upper``)."""
        for a, name in enumerate(self.actuator_names):
            dof, tendon = int(self.actuator_dof[a]), int(self.actuator_tendon[a])
            if tendon >= 0 and (tendon >= len(self.tendon_names) or dof != -1):
                raise ValueError(f"actuator {name!r} pulls tendon {tendon} and drives "
                                 f"coordinate {dof}; expected a tendon in [0, "
                                 f"{len(self.tendon_names)}) and the coordinate -1")
            if tendon < 0 and not (tendon == -1 and 0 <= dof < self.nv):
                raise ValueError(f"actuator {name!r} drives velocity coordinate {dof}; "
                                 f"expected one in [0, {self.nv})")
            for what, x in (("gear", self.actuator_gear[a]), ("gain", self.actuator_gain[a]),
                            ("bias", self.actuator_bias[a])):
                if not np.all(np.isfinite(x)):
                    raise ValueError(f"actuator {name!r} has the {what} {x}; expected finite "
                                     f"numbers")
            if np.any(self.actuator_bias[a, 1:]) and np.any(
                    np.isfinite(self.actuator_forcerange[a])):
                raise ValueError(f"actuator {name!r} has a force range on a force that depends "
                                 f"on the state (bias {self.actuator_bias[a].tolist()}); "
                                 f"cgadyn clamps only a force of the control alone")
            for what in ("ctrlrange", "forcerange", "actrange"):
                lo, hi = getattr(self, f"actuator_{what}")[a]
                if not lo <= hi:
                    raise ValueError(f"actuator {name!r} has the {what} [{lo}, {hi}]; "
                                     f"expected lower <= upper")
        if len(self.actuator_dynamics) != len(self.actuator_names):
            raise ValueError(f"Model.actuator_dynamics has {len(self.actuator_dynamics)} "
                             f"entries, expected one per actuator "
                             f"({len(self.actuator_names)})")
        for name, kind, T in zip(self.actuator_names, self.actuator_dynamics,
                                 self.actuator_time_constant, strict=True):
            if kind not in ACTIVATION_DYNAMICS:
                raise ValueError(f"actuator {name!r} has the dynamics {kind!r}; expected one "
                                 f"of {ACTIVATION_DYNAMICS}")
            if kind.startswith("filter") and not (np.isfinite(T) and T > 0.0):
                raise ValueError(f"actuator {name!r} is a {kind} of time constant {T}; "
                                 f"expected a finite number > 0")

    def _additive(self) -> np.ndarray:
        """bool (nv,): the coordinates of joints whose coordinates add (``q ⊕ v = q + v``)."""
        additive = np.zeros(self.nv, dtype=bool)
        for j, t in enumerate(self.joint_types):
            additive[self.joint_dofs(j)] = TYPES[int(t)].additive
        return additive

    def _check_couplings(self):
        """Each coupling's coefficients are finite, not all zero and on coordinates that add
        (where ``Σ a_k q_k`` is linear in q and moves by ``dt Σ a_k v_k`` in a step); its
        offset finite."""
        additive = self._additive()
        for i, name in enumerate(self.coupling_names):
            a, b = self.coupling_coefficients[i], float(self.coupling_offset[i])
            if (not np.all(np.isfinite(a)) or np.any(a[~additive] != 0.0)
                    or not np.any(a != 0.0) or not np.isfinite(b)):
                raise ValueError(f"coupling {name!r} has the coefficients {a.tolist()} and "
                                 f"the offset {b}; expected finite numbers, not all zero, "
                                 f"zero on the coordinates of joints whose coordinates do "
                                 f"not add")

    def _check_ropes(self):
        """Each rope joins two different links of the model or the world, at finite points,
        and bounds its length by ``0 <= shortest <= longest`` (``inf``: no longest), one of
        them a bound (shortest > 0 or longest finite)."""
        for name, (a, b), P, (lo, hi) in zip(self.rope_names, self.rope_links,
                                             self.rope_points, self.rope_range, strict=True):
            nl = len(self.link_names)
            if not (-1 <= a < nl and -1 <= b < nl and a != b):
                raise ValueError(f"rope {name!r} joins the links {a} and {b}; expected two "
                                 f"different links in [-1, {nl}) (-1: the world)")
            if not np.all(np.isfinite(P)):
                raise ValueError(f"rope {name!r} has the points {P.tolist()}; expected "
                                 f"finite points")
            if not (0.0 <= lo <= hi and np.isfinite(lo) and (lo > 0.0 or np.isfinite(hi))):
                raise ValueError(f"rope {name!r} has the range [{lo}, {hi}]; expected 0 <= "
                                 f"shortest <= longest, a finite shortest, and a bound "
                                 f"(shortest > 0 or longest finite)")

    def _check_tendons(self):
        """Each tendon's coefficients are finite and on coordinates that add (where ``L = Σ
        c_k q_k`` is MuJoCo's fixed tendon); its stiffness and damping finite and ``>= 0``;
        its spring lengths finite and ordered."""
        additive = self._additive()
        for i, name in enumerate(self.tendon_names):
            c = self.tendon_coefficients[i]
            if not np.all(np.isfinite(c)) or np.any(c[~additive] != 0.0):
                raise ValueError(f"tendon {name!r} has the coefficients {c.tolist()}; "
                                 f"expected finite numbers, zero on the coordinates of "
                                 f"joints whose coordinates do not add")
            for field in ("stiffness", "damping", "friction"):
                x = float(getattr(self, f"tendon_{field}")[i])
                if not (np.isfinite(x) and x >= 0.0):
                    raise ValueError(f"tendon {name!r} has the {field} {x}; expected a "
                                     f"finite number >= 0")
            lo, hi = self.tendon_spring_length[i]
            if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
                raise ValueError(f"tendon {name!r} has the spring lengths [{lo}, {hi}]; "
                                 f"expected finite lengths, lower <= upper")
            lo, hi = self.tendon_range[i]
            if not lo <= hi or lo == np.inf or hi == -np.inf:
                raise ValueError(f"tendon {name!r} has the range [{lo}, {hi}]; expected "
                                 f"lower <= upper (±inf: no bound)")

    @property
    def actuators(self) -> list[dict]:
        """The actuators, one dict each: ``name``, ``joint`` and ``dof`` (the velocity
        coordinate) of a joint's, ``tendon`` of a tendon's (the others None), ``gear``,
        ``gain``, ``bias`` (``b₀, b₁, b₂``), ``ctrlrange``, ``forcerange``, ``dynamics``
        and ``time_constant`` (``Model.actuator_dynamics``)."""
        return [{"name": name,
                 "joint": None if t >= 0 else self.joint_names[self.dof_joint[int(dof)]],
                 "dof": None if t >= 0 else int(dof),
                 "tendon": self.tendon_names[t] if t >= 0 else None,
                 "gear": float(gear), "gain": float(gain), "bias": tuple(map(float, b)),
                 "ctrlrange": tuple(map(float, c)), "forcerange": tuple(map(float, f)),
                 "dynamics": kind, "time_constant": float(T)}
                for name, dof, t, gear, gain, b, c, f, kind, T in zip(
                    self.actuator_names, self.actuator_dof, self.actuator_tendon,
                    self.actuator_gear, self.actuator_gain, self.actuator_bias,
                    self.actuator_ctrlrange, self.actuator_forcerange, self.actuator_dynamics,
                    self.actuator_time_constant, strict=True)]

    def _check_axes(self):
        """Joint axes pass through the joint frame's origin (URDF's convention): a revolute
        axis is a line with no moment part, a prismatic one a direction (the record's
        ``axis``), a helical one a line plus its pitch times its own direction (``[h a, a]``,
        checked by ``v × ω = 0``). The recursions rely on it
        (``kernels.motors.joint_frame_motor``)."""
        from cgadyn.cga.conventions import motion_from_twist

        axis = [TYPES[int(t)].axis for t in self.joint_types]
        direction = np.array([a == "prismatic" for a in axis], dtype=bool)
        stray = np.where(direction[:, None], self.axes[:, :3], self.axes[:, 3:])
        stray[[a is None for a in axis]] = 0.0
        for j in np.flatnonzero([a == "helical" for a in axis]):
            motion = motion_from_twist(self.axes[j])
            off = np.cross(motion[:3], motion[3:])
            if np.any(np.abs(off) > 1e-12 * max(1.0, float(np.abs(motion).max()))):
                raise ValueError(f"Model.axes[{j}] (joint {self.joint_names[j]!r}, helical) = "
                                 f"{self.axes[j].tolist()}: expected a screw [h a, a] along "
                                 f"its own axis a through the joint frame's origin")
            stray[j] = 0.0
        for j in np.flatnonzero(np.any(stray != 0.0, axis=1)):
            kind, used, unused = ((axis[j], "3:", ":3") if direction[j] else
                                  (axis[j], ":3", "3:"))
            raise ValueError(
                f"Model.axes[{j}] (joint {self.joint_names[j]!r}, {kind}) = "
                f"{self.axes[j].tolist()}: expected an axis through the joint frame's origin, "
                f"nonzero only in axes[{j}, {used}], but axes[{j}, {unused}] is not zero")

    @cached_property
    def packed(self) -> np.ndarray:
        """The dynamics arrays and default gravity in one buffer for the compiled algorithms
        (``cgadyn.multibody.packed``). Not for users: read the public fields."""
        return pack(self)

    @cached_property
    def idx_q(self) -> np.ndarray:
        """int64 (n + 1,): joint j's configuration is ``q[idx_q[j]:idx_q[j + 1]]``."""
        return _offsets(self.joint_types, NQ)

    @cached_property
    def idx_v(self) -> np.ndarray:
        """int64 (n + 1,): joint j's velocity is ``v[idx_v[j]:idx_v[j + 1]]``."""
        return _offsets(self.joint_types, NV)

    @cached_property
    def dof_joint(self) -> np.ndarray:
        """int64 (nv,): the joint of each velocity coordinate."""
        out = np.repeat(np.arange(self.njoints), np.diff(self.idx_v))
        out.flags.writeable = False
        return out

    @cached_property
    def dof_parent(self) -> np.ndarray:
        """int64 (nv,): the velocity coordinate each one hangs from (Featherstone's expanded
        tree: a joint's coordinates form a chain, the first hanging from the parent joint's
        last coordinate), -1 at the root."""
        out = np.arange(-1, self.nv - 1)
        for j in range(self.njoints):
            p = int(self.parents[j])
            out[self.idx_v[j]] = -1 if p < 0 else self.idx_v[p + 1] - 1
        out.flags.writeable = False
        return out

    @cached_property
    def subtree_end(self) -> np.ndarray:
        """int64 (n,): one past the last velocity coordinate of joint j's subtree, whose
        coordinates are ``idx_v[j]:subtree_end[j]`` (joints in depth-first order)."""
        last = np.arange(self.njoints)
        for j in range(self.njoints - 1, -1, -1):
            p = int(self.parents[j])
            if p >= 0:
                last[p] = max(last[p], last[j])
        out = self.idx_v[last + 1].astype(np.int64)
        out.flags.writeable = False
        return out

    @cached_property
    def unit_axes(self) -> np.ndarray:
        """int64 (nv,): i where a one-dof joint's motion subspace column is ``±e_i``, else -1
        (``multibody.joints.unit_axes``)."""
        out = unit_axes(self.motion_subspace, self.joint_types)
        out.flags.writeable = False
        return out

    @cached_property
    def motion_subspace(self) -> np.ndarray:
        """float64 (nv, 6): the twist of each velocity coordinate in its joint's frame, the
        columns of the joints' motion subspaces ``S_j`` (``multibody.joints``)."""
        S = np.zeros((self.nv, 6))
        for j, t in enumerate(self.joint_types):
            S[self.idx_v[j]:self.idx_v[j + 1]] = TYPES[int(t)].subspace(self.axes[j])
        S.flags.writeable = False
        return S

    # --- sizes -----------------------------------------------------------------------

    @property
    def njoints(self) -> int:
        """Number of joints n (a free-flyer root counts as one)."""
        return len(self.joint_names)

    @property
    def nq(self) -> int:
        """Size of the configuration vector q (Σ nq_j, ``multibody.joints``)."""
        return int(self.idx_q[-1])

    @property
    def nv(self) -> int:
        """Size of the velocity vector v (Σ nv_j, ``multibody.joints``)."""
        return int(self.idx_v[-1])

    @property
    def floating_base(self) -> bool:
        """True when the root joint floats (moves its body by any rigid motion: a free
        flyer, ``root_joint``; the record's ``floating``)."""
        return bool(self.njoints) and TYPES[int(self.joint_types[0])].floating

    @property
    def actuated(self) -> np.ndarray:
        """(nv,) bool: the velocity coordinates an actuator drives (``joints.ACTUATED``):
        every joint's but a free flyer's. Controllers act on these alone."""
        return self._per_coordinate(ACTUATED).astype(bool)

    def coordinate_speeds(self) -> tuple[str, ...]:
        """What each velocity coordinate is (``joints.SPEEDS``): ``"angular"``,
        ``"linear"`` (a slide) or ``"free"`` (a free body's linear velocity)."""
        return tuple(kind for t in self.joint_types for kind in SPEEDS[int(t)])

    def coordinate_names(self, velocity: bool = False) -> list[str]:
        """One label per configuration (or velocity) coordinate: the joint's name, or
        ``joint.coordinate`` for a joint of several (``multibody.joints``)."""
        return coordinate_names(self, velocity)

    def _per_coordinate(self, table) -> np.ndarray:
        """A per-type table of ``joints`` spread over the velocity coordinates."""
        return np.repeat([table[int(t)] for t in self.joint_types],
                         np.diff(self.idx_v)) if self.njoints else np.zeros(0)

    @property
    def nlinks(self) -> int:
        """Number of URDF links."""
        return len(self.link_names)

    # --- look-ups --------------------------------------------------------------------

    def joint_index(self, name: str) -> int:
        """Index of the movable joint called ``name``."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise ValueError(f"no movable joint {name!r} in {self.name!r}; "
                             f"joints: {', '.join(self.joint_names)}") from None

    def link_index(self, name: str) -> int:
        """Index of the link called ``name`` (into ``link_names``)."""
        try:
            return self.link_names.index(name)
        except ValueError:
            raise ValueError(f"no link {name!r} in {self.name!r}; "
                             f"links: {', '.join(self.link_names)}") from None

    def children(self, j: int) -> tuple:
        """Indices of the joints whose parent is ``j`` (``-1``: the world)."""
        return tuple(int(i) for i in np.flatnonzero(self.parents == j))

    def subtree(self, j: int) -> tuple:
        """Indices of joint ``j`` and all joints below it, in increasing order."""
        inside = np.zeros(self.njoints, dtype=bool)
        inside[j] = True
        for i in range(j + 1, self.njoints):
            p = self.parents[i]
            inside[i] = p >= 0 and inside[p]
        return tuple(int(i) for i in np.flatnonzero(inside))

    @property
    def total_mass(self) -> float:
        """Mass of all moving bodies (links fixed to the world not included)."""
        return float(self.body_mass.sum())

    def joint_dofs(self, j: int) -> range:
        """The indices of joint ``j``'s velocity coordinates in v (and tau)."""
        return range(int(self.idx_v[j]), int(self.idx_v[j + 1]))

    def __repr__(self) -> str:
        counts = Counter(self.joint_kinds)
        kinds_s = ", ".join(f"{counts[k]} {k}" for k in JOINT_KINDS if counts[k])
        base = "free-flyer base" if self.floating_base else "fixed base"
        return (f"Model({self.name!r}, nq={self.nq}, nv={self.nv}, {base}, "
                f"{self.njoints} joints ({kinds_s}), links={self.nlinks}, "
                f"root={self.root_link!r})")


def _limits(values, size: int, name: str) -> np.ndarray:
    out = np.array(values, dtype=float).reshape(-1)
    if out.shape != (size,):
        raise ValueError(f"{name} must have {size} entries (one per coordinate), got "
                         f"{out.shape}")
    return out


def _offsets(types, sizes) -> np.ndarray:
    out = np.zeros(len(types) + 1, dtype=np.int64)
    out[1:] = np.cumsum([sizes[t] for t in types])
    out.flags.writeable = False
    return out


def merge_inertias(masses, coms, rotational_inertias):
    """Merge rigid pieces given in one frame into one body.

    ``masses (k,)``, ``coms (k, 3)``, ``rotational_inertias (k, 3, 3)`` (about each
    piece's centre of mass, in the common frame's axes). Returns ``(mass, com, inertia
    about com)``; a massless result has its com at the origin.
    """
    masses = np.asarray(masses, dtype=float).reshape(-1)
    coms = np.asarray(coms, dtype=float).reshape(-1, 3)
    rot = np.asarray(rotational_inertias, dtype=float).reshape(-1, 3, 3)
    mass = float(masses.sum())
    if mass > 0.0:
        com = (masses[:, None] * coms).sum(axis=0) / mass
    else:
        com = np.zeros(3)
    inertia = np.zeros((3, 3))
    eye = np.eye(3)
    for m, c, ic in zip(masses, coms, rot, strict=True):
        d = c - com
        inertia += ic + m * (d @ d * eye - np.outer(d, d))
    return mass, com, 0.5 * (inertia + inertia.T)


def build_model(
    name,
    joint_names,
    joint_kinds,
    parents,
    placement_matrices,
    axis_vectors,
    body_mass,
    body_com,
    body_rotational_inertia,
    lower=None,
    upper=None,
    velocity_limit=None,
    effort_limit=None,
    link_names=None,
    link_joint=None,
    link_placement_matrices=None,
    root_link="world",
    mimic=None,
    check_inertia=True,
    armature=None,
    damping=None,
    stiffness=None,
    spring_reference=None,
    pitch=None,
    friction=None,
    cone_limit=None,
) -> Model:
    """Build a :class:`Model` from raw physical data; computes the CGA fields.

    ``placement_matrices (n,4,4)`` are the joint placements at q = 0 in the parent joint
    frame; ``axis_vectors (n,3)`` the joint axes in the joint frames (normalised here,
    a zero axis raises ``ValueError``); ``body_*`` the merged bodies in the joint frames.
    Links default to one per joint (named after the joint) plus the root link.
    ``armature``, ``damping``, ``friction``, ``stiffness`` (nv,) and ``spring_reference``
    (nq,) default to zero and the neutral configuration (``Model``). ``pitch`` (n,), default
    zero: the pitch of each helical joint (length per radian; read only for those).
    ``cone_limit`` (n,), default inf: each joint's largest rotation angle (``Model``).
    """
    from cgadyn.cga.conventions import (
        inertia_from_parameters,
        motor_from_matrix,
        twist_from_axis,
    )

    joint_names = tuple(str(s) for s in joint_names)
    joint_kinds = tuple(str(s) for s in joint_kinds)
    n = len(joint_names)
    records = [of_kind(kind) for kind in joint_kinds]
    joint_types = np.array([r.code for r in records], dtype=np.int64)
    free = np.array([r.axis is None for r in records], dtype=bool).reshape(n)
    nq, nv = int(sum(NQ[t] for t in joint_types)), int(sum(NV[t] for t in joint_types))
    placement_matrices = np.asarray(placement_matrices, dtype=float).reshape(n, 4, 4)
    axis_vectors = np.asarray(axis_vectors, dtype=float).reshape(n, 3).copy()
    axis_vectors[free] = 0.0  # a joint without an axis (a free flyer: every twist)
    norms = np.linalg.norm(axis_vectors, axis=1)
    for j in np.flatnonzero(~free):
        if not norms[j] > 1e-12 or not np.isfinite(norms[j]):
            raise ValueError(f"joint {joint_names[j]!r} has a zero (or invalid) axis "
                             f"{axis_vectors[j].tolist()}; expected a non-zero 3-vector")
    axis_vectors[~free] /= norms[~free, None]
    body_mass = np.asarray(body_mass, dtype=float).reshape(n)
    body_com = np.asarray(body_com, dtype=float).reshape(n, 3)
    body_rot = np.asarray(body_rotational_inertia, dtype=float).reshape(n, 3, 3)

    idx_q = _offsets(joint_types, NQ)
    lower = np.full(nq, -np.inf) if lower is None else _limits(lower, nq, "lower")
    upper = np.full(nq, np.inf) if upper is None else _limits(upper, nq, "upper")
    for j, record in enumerate(records):  # what each joint type keeps of the limits given
        s = slice(idx_q[j], idx_q[j + 1])
        lower[s], upper[s] = record.limits(lower[s], upper[s])
    velocity_limit = (np.full(nv, np.inf) if velocity_limit is None
                      else _limits(velocity_limit, nv, "velocity_limit"))
    effort_limit = (np.full(nv, np.inf) if effort_limit is None
                    else _limits(effort_limit, nv, "effort_limit"))

    if link_names is None:
        link_names = (root_link, *joint_names)
        link_joint = np.arange(-1, n)
        link_placement_matrices = np.broadcast_to(np.eye(4), (n + 1, 4, 4))
    link_names = tuple(str(s) for s in link_names)
    nl = len(link_names)
    link_placement_matrices = np.asarray(link_placement_matrices, dtype=float).reshape(nl, 4, 4)

    placements = np.array([motor_from_matrix(T) for T in placement_matrices]).reshape(n, 8)
    pitch = np.zeros(n) if pitch is None else np.asarray(pitch, dtype=float).reshape(n)
    if not np.all(np.isfinite(pitch)):
        raise ValueError(f"pitch must be finite numbers (n,), got {pitch.tolist()}")
    axes = np.array([np.zeros(6) if r.axis is None else twist_from_axis(r.axis, a, h)
                     for r, a, h in zip(records, axis_vectors, pitch, strict=True)]
                    ).reshape(n, 6)
    inertias = np.array([inertia_from_parameters(m, c, i, check_inertia)
                         for m, c, i in zip(body_mass, body_com, body_rot, strict=True)]
                         ).reshape(n, 6, 6)
    link_placements = np.array([motor_from_matrix(T)
                                for T in link_placement_matrices]).reshape(nl, 8)

    return Model(
        name=str(name),
        joint_names=joint_names,
        joint_kinds=joint_kinds,
        joint_types=joint_types,
        parents=np.asarray(parents, dtype=np.int64).reshape(n),
        placements=placements,
        axes=axes,
        inertias=inertias,
        body_mass=body_mass,
        body_com=body_com,
        body_rotational_inertia=body_rot,
        lower=lower,
        upper=upper,
        velocity_limit=velocity_limit,
        effort_limit=effort_limit,
        link_names=link_names,
        link_joint=np.asarray(link_joint, dtype=np.int64).reshape(nl),
        link_placements=link_placements,
        root_link=str(root_link),
        placement_matrices=placement_matrices,
        axis_vectors=axis_vectors,
        link_placement_matrices=link_placement_matrices,
        mimic=tuple(mimic) if mimic is not None else (None,) * n,
        armature=None if armature is None else _limits(armature, nv, "armature"),
        damping=None if damping is None else _limits(damping, nv, "damping"),
        friction=None if friction is None else _limits(friction, nv, "friction"),
        stiffness=None if stiffness is None else _limits(stiffness, nv, "stiffness"),
        spring_reference=(None if spring_reference is None
                          else _limits(spring_reference, nq, "spring_reference")),
        cone_limit=None if cone_limit is None else _limits(cone_limit, n, "cone_limit"),
    )
