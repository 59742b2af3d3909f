"""Convert a compiled MuJoCo model (``mujoco.MjModel``) into a cgadyn :class:`Model`.

MuJoCo's own compiler is the reference for MJCF: it applies default classes, computes
inertias from geoms (``inertiafromgeom``), expands ``<include>``, converts angles, and
places every body. ``from_mujoco`` reads what it compiled, whole:

- **Joints**, with MuJoCo's names and order (so that q is MuJoCo's qpos and v its qvel,
  except for a free joint's layout, below): ``hinge`` becomes a revolute joint (an
  unbounded one when the joint is not limited), ``slide`` a prismatic joint, ``free`` the
  free flyer (of a top-level body: the root of its own tree; a model may float several
  bodies, a robot and the objects it handles), ``ball`` a spherical joint about its
  anchor ``jnt_pos`` (qpos ``[qw, qx, qy, qz]``, cgadyn's ``[qx, qy, qz, qw]``; qvel the
  angular velocity in the body frame, as cgadyn's). A limited ball joint's ``range`` is
  its cone limit, the largest angle of its rotation (``Model.cone_limit``; MuJoCo takes the
  larger of the two numbers).
- **Bodies.** Body b's frame at rest is its parent's composed with ``body_pos`` and
  ``body_quat`` (w, x, y, z). MuJoCo moves it by its joints in order, each about or along
  its axis ``jnt_axis`` through the point ``jnt_pos`` of the body frame as the previous
  joints left it, by ``qpos - qpos0`` (``qpos0`` is the joint's ``ref``): a hinge turns the
  body frame about the anchor, a slide translates it (``mj_kinematics``). cgadyn's joint
  frame k is the body frame translated to ``jnt_pos_k``; ``ref`` is folded into the joint's
  placement (``X M_J(q - ref) = (X M_J(-ref)) M_J(q)``). A body with several joints
  (Gymnasium's humanoid abdomen and hips) becomes a chain of joints whose intermediate
  bodies are massless; the body itself hangs from the last joint, at ``-jnt_pos``.
  A body without joints is welded to the body above it: its inertia merged there, its
  frame a link of that joint (bodies welded to the world carry no dynamics).
- **Inertias** as MuJoCo computed them: ``body_mass``, and ``body_inertia``, the diagonal
  in the frame ``body_iquat`` at ``body_ipos`` of the body frame.
- **Links**: the world (``world``) and every body, named as in MuJoCo (an unnamed body
  ``body<id>``), placed in the frame of the joint that moves it; so
  ``link_placements(model, q)`` are MuJoCo's ``xpos``/``xquat`` (``xmat``). Then every
  named site whose name no body has (``site_xpos``, ``site_xmat``).
- **Passive dynamics**: ``dof_armature`` (``Model.armature``), ``dof_damping``
  (``Model.damping``), ``jnt_stiffness`` and ``qpos_spring`` (``Model.stiffness``,
  ``Model.spring_reference``), and ``qpos0`` as ``Model.home``; ``jnt_range`` where
  ``jnt_limited`` (``Model.lower``, ``Model.upper`` for a hinge or a slide,
  ``Model.cone_limit`` for a ball) and ``dof_frictionloss`` (``Model.friction``), which the
  contact step enforces (``docs/contact.md``, "Joint limits", "Friction loss").
- **Actuators** with a fixed gain, an affine bias and no activation state, on a hinge, a
  slide or a fixed tendon: motors, and position and velocity servos (``Model.actuators``:
  gear, gain, bias, control and force ranges; a servo's force ``gain · ctrl + b₀ + b₁ L +
  b₂ L̇`` depends on its length L); other actuators (activation dynamics, muscles, a
  clamped servo force) are left out with a warning.
- **Tendons**: the springs and dampers of fixed tendons (``Model.tendon_*``, passive
  forces along ``L = Σ coef q``); a tendon's limit and friction loss, and fluid forces,
  are left out with a warning; a spatial tendon's spring or damper and a tendon's armature
  are refused by name.
- **Couplings**: the linear joint and tendon equalities active at the start
  (``Model.coupling_*``, held by the contact step, K45); others left out with a warning.
- **Ropes**: limited spatial tendons of two sites (``Model.rope_*``, held by the contact
  step, K46); other tendon limits are left out with a warning.

States: ``from_mujoco_state(model, qpos, qvel)`` and ``to_mujoco_state(model, q, v)``,
accelerations ``from_mujoco_acceleration(model, q, v, qacc)`` and
``to_mujoco_acceleration(model, q, v, a)``; the joint records (``multibody.joints``)
hold each type's layouts: a free joint's qpos is ``[x, y, z, qw, qx, qy, qz]`` (cgadyn's
and Pinocchio's ``[x, y, z, qx, qy, qz, qw]``) and its qvel's linear part is the body
origin's velocity in the world frame, where cgadyn's base twist is in the body frame
(``qvel = (R v, ω)``).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from cgadyn.multibody.joints import table
from cgadyn.multibody.model import Model, build_model, merge_inertias
from cgadyn.multibody.packed import DEFAULT_GRAVITY

WORLD = "world"
"""The name of MuJoCo's world body, the root link of a converted model."""

_KINDS = {"free": "free_flyer", "slide": "prismatic", "ball": "spherical"}
"""MuJoCo's joint types and cgadyn's joint kinds (a hinge: ``_hinge_kind``)."""

_MJ_TYPES = ("free", "ball", "slide", "hinge")
"""``mjtJoint`` by value: mjJNT_FREE, mjJNT_BALL, mjJNT_SLIDE, mjJNT_HINGE."""


def _rotation(quat) -> np.ndarray:
    """The rotation matrix of MuJoCo's quaternion ``(w, x, y, z)``, normalised."""
    w, x, y, z = np.asarray(quat, dtype=float) / np.linalg.norm(quat)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _pose(pos=(0.0, 0.0, 0.0), rot=None) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = pos
    if rot is not None:
        T[:3, :3] = rot
    return T


def _axis_angle(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about the unit ``axis`` (Rodrigues)."""
    x, y, z = axis
    K = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def _name(mj, kind, i: int, fallback: str) -> str:
    import mujoco

    return mujoco.mj_id2name(mj, kind, i) or fallback


def _hinge_kind(mj, j: int) -> str:
    return "revolute" if mj.jnt_limited[j] else "continuous"


def _check_model(mj, where: str) -> None:
    """Refuse what a cgadyn model cannot hold, by name: a free joint that is not the first
    joint of a top-level body or that is offset in its body, a ball joint whose reference
    ``qpos0`` is not the identity. A gravity other
    than cgadyn's default is only warned of: the model does not hold gravity, calls take
    ``gravity=``."""
    for j in range(mj.njnt):
        kind = _MJ_TYPES[int(mj.jnt_type[j])]
        name = _name(mj, _obj("JOINT"), j, f"joint {j}")
        body = int(mj.jnt_bodyid[j])
        if kind == "ball" and np.any(mj.qpos0[mj.jnt_qposadr[j]:mj.jnt_qposadr[j] + 4] !=
                                     np.array([1.0, 0.0, 0.0, 0.0])):
            raise ValueError(f"{where}: ball joint {name!r} has the reference qpos0 "
                             f"{mj.qpos0[mj.jnt_qposadr[j]:mj.jnt_qposadr[j] + 4].tolist()}; "
                             f"cgadyn's spherical joint expects the identity [1, 0, 0, 0]")
        if kind == "free" and mj.body_parentid[body] != 0:
            raise ValueError(f"{where}: joint {name!r} is a free joint of a body that is "
                             f"not a child of the world; cgadyn's free joints float "
                             f"top-level bodies only (each the root of its own tree)")
        if kind == "free" and np.any(mj.jnt_pos[j] != 0.0):
            raise ValueError(f"{where}: free joint {name!r} has pos "
                             f"{mj.jnt_pos[j].tolist()}; expected the body's origin (0 0 0)")
    gravity = _gravity(mj)
    if not np.allclose(gravity, DEFAULT_GRAVITY, rtol=0.0, atol=1e-12):
        warnings.warn(f"{where}: the MuJoCo model's gravity is {gravity.tolist()}; a cgadyn "
                      f"model uses {list(DEFAULT_GRAVITY)} unless a call passes gravity= "
                      f"(pass gravity={gravity.tolist()} to use MuJoCo's)", stacklevel=3)


def _disabled(mj, flag: str) -> bool:
    """Whether ``<flag>`` disables ``flag`` (``mjtDisableBit``) in the compiled model."""
    import mujoco

    return bool(mj.opt.disableflags & int(getattr(mujoco.mjtDisableBit, f"mjDSBL_{flag}")))


def _gravity(mj) -> np.ndarray:
    """The gravity MuJoCo applies: ``opt.gravity``, or zero where ``<flag gravity=
    "disable"/>`` turns it off."""
    return np.zeros(3) if _disabled(mj, "GRAVITY") else np.asarray(mj.opt.gravity, dtype=float)


def _obj(name: str):
    import mujoco

    return getattr(mujoco.mjtObj, f"mjOBJ_{name}")


def from_mujoco(mj_model, name: str | None = None, check_inertia: bool = True) -> Model:
    """The cgadyn :class:`Model` of a compiled MuJoCo model (``mujoco.MjModel``), as the
    module's docstring describes. ``name`` defaults to the model's (``<mujoco model>``).

    Raises ``ValueError`` naming a free joint of a body that is not a top-level one, a ball
    joint whose ``qpos0`` is not the identity, or (with ``check_inertia``) a body whose
    inertia is not physical; warns of a gravity other than cgadyn's default
    (calls take ``gravity=``).
    """
    try:
        import mujoco
    except ImportError:  # pragma: no cover - mujoco is optional
        raise ImportError("from_mujoco needs MuJoCo: pip install mujoco") from None
    if not isinstance(mj_model, mujoco.MjModel):
        raise ValueError(f"from_mujoco expects a mujoco.MjModel, got "
                         f"{type(mj_model).__name__}")
    mj = mj_model
    model_name = name if name is not None else (
        bytes(mj.names).split(b"\0", 1)[0].decode() or "mujoco")  # the first name: the model's
    _check_model(mj, repr(model_name))

    joints = dict(names=[], kinds=[], parents=[], placements=[], axes=[], lower=[], upper=[],
                  armature=[], damping=[], friction=[], stiffness=[], spring=[], cone=[])
    pieces: list[list] = []  # per cgadyn joint: [(mass, com, rotational inertia)] in its frame
    attach = {0: (-1, np.eye(4))}  # body -> (cgadyn joint moving it, its pose in that frame)
    link_names, link_joint, link_poses = [WORLD], [-1], [np.eye(4)]
    used = set()
    joint_of = {}  # MuJoCo joint -> cgadyn joint
    no_damper, no_spring = _disabled(mj, "DAMPER"), _disabled(mj, "SPRING")  # <flag>s

    def add_joint(jname, kind, parent, placement, axis, lower, upper, mj_joint):
        joints["names"].append(jname)
        joints["kinds"].append(kind)
        joints["parents"].append(parent)
        joints["placements"].append(placement)
        joints["axes"].append(axis)
        joints["lower"] += lower
        joints["upper"] += upper
        joints["cone"].append(float(np.max(mj.jnt_range[mj_joint]))
                              if kind == _KINDS["ball"] and mj.jnt_limited[mj_joint]
                              else np.inf)  # a ball's range: its cone limit
        dofs = range(mj.jnt_dofadr[mj_joint], mj.jnt_dofadr[mj_joint] +
                     table.of_kind(kind).nv)
        joints["armature"] += [float(mj.dof_armature[d]) for d in dofs]
        joints["damping"] += [0.0 if no_damper else float(mj.dof_damping[d]) for d in dofs]
        joints["friction"] += [float(mj.dof_frictionloss[d]) for d in dofs]
        joints["stiffness"] += [0.0 if no_spring else float(mj.jnt_stiffness[mj_joint])] * \
            len(dofs)
        pieces.append([])
        joint_of[mj_joint] = len(joints["names"]) - 1
        return len(joints["names"]) - 1

    for b in range(1, mj.nbody):
        parent_joint, parent_pose = attach[int(mj.body_parentid[b])]
        rest = parent_pose @ _pose(mj.body_pos[b], _rotation(mj.body_quat[b]))
        body_name = _name(mj, _obj("BODY"), b, f"body{b}")
        first = int(mj.body_jntadr[b])
        count = int(mj.body_jntnum[b])
        frame, previous = rest, None  # the body frame at rest, in parent_joint's frame
        for j in range(first, first + count):
            mj_type = _MJ_TYPES[int(mj.jnt_type[j])]
            jname = _name(mj, _obj("JOINT"), j, f"{body_name}_joint{j - first}")
            if jname in used:
                raise ValueError(f"{model_name!r}: two joints are named {jname!r}")
            used.add(jname)
            if mj_type == "free":  # the body's pose in the world is q: placement identity
                parent_joint = add_joint(jname, _KINDS["free"], -1, np.eye(4), np.zeros(3),
                                         [-np.inf] * 7, [np.inf] * 7, j)
                frame, previous = np.eye(4), np.zeros(3)
                continue
            kind = _hinge_kind(mj, j) if mj_type == "hinge" else _KINDS[mj_type]
            pos = np.asarray(mj.jnt_pos[j], dtype=float)
            offset = frame @ _pose(pos) if previous is None else _pose(pos - previous)
            if mj_type == "ball":  # a rotation about the anchor; qpos0 the identity
                parent_joint = add_joint(jname, kind, parent_joint, offset, np.zeros(3),
                                         [-np.inf] * 4, [np.inf] * 4, j)
                previous = pos
                continue
            axis = np.asarray(mj.jnt_axis[j], dtype=float)
            ref = float(mj.qpos0[mj.jnt_qposadr[j]])
            folded = (_pose(rot=_axis_angle(axis, -ref)) if mj_type == "hinge"
                      else _pose(-ref * axis))  # X M_J(q - ref) = (X M_J(-ref)) M_J(q)
            limited = bool(mj.jnt_limited[j])
            lower, upper = ([float(mj.jnt_range[j, 0])], [float(mj.jnt_range[j, 1])]) \
                if limited else ([-np.inf], [np.inf])
            parent_joint = add_joint(jname, kind, parent_joint, offset @ folded, axis,
                                     lower, upper, j)
            previous = pos
        if count:
            frame = _pose(-previous)  # the body frame in its last joint's frame
        attach[b] = (parent_joint, frame)
        link_names.append(body_name)
        link_joint.append(parent_joint)
        link_poses.append(frame)
        if parent_joint >= 0:
            inertial = frame @ _pose(mj.body_ipos[b], _rotation(mj.body_iquat[b]))
            rot = inertial[:3, :3]
            pieces[parent_joint].append((float(mj.body_mass[b]), inertial[:3, 3].copy(),
                                         rot @ np.diag(mj.body_inertia[b]) @ rot.T))

    for site in range(mj.nsite):  # named sites: frames to ask Jacobians of
        site_name = _name(mj, _obj("SITE"), site, "")
        if site_name and site_name not in link_names:
            joint, pose = attach[int(mj.site_bodyid[site])]
            link_names.append(site_name)
            link_joint.append(joint)
            link_poses.append(pose @ _pose(mj.site_pos[site], _rotation(mj.site_quat[site])))
    n = len(joints["names"])
    mass, com, rotational = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3, 3))
    for j, body in enumerate(pieces):
        if body:
            mass[j], com[j], rotational[j] = merge_inertias(*map(np.array, zip(*body,
                                                                                strict=True)))
    try:
        model = build_model(
            name=model_name, joint_names=joints["names"], joint_kinds=joints["kinds"],
            parents=joints["parents"],
            placement_matrices=np.array(joints["placements"]).reshape(n, 4, 4),
            axis_vectors=np.array(joints["axes"]).reshape(n, 3),
            body_mass=mass, body_com=com, body_rotational_inertia=rotational,
            lower=joints["lower"], upper=joints["upper"], link_names=link_names,
            link_joint=link_joint, link_placement_matrices=np.array(link_poses),
            root_link=WORLD, check_inertia=check_inertia, armature=joints["armature"],
            damping=joints["damping"], stiffness=joints["stiffness"],
            friction=joints["friction"], cone_limit=joints["cone"])
        return dataclasses.replace(model, spring_reference=table.from_mujoco(
            model, mj.qpos_spring), home=table.from_mujoco(model, mj.qpos0),
            **_motors_and_tendons(mj, model, joint_of, model_name),
            **_couplings(mj, model, joint_of, model_name), **_ropes(mj, model))
    except ValueError as exc:
        raise ValueError(f"MuJoCo model {model_name!r}: {exc}") from None


def available() -> bool:
    """Whether MuJoCo is installed: ``cgadyn.load`` then reads MJCF through it."""
    import importlib.util

    return importlib.util.find_spec("mujoco") is not None


def _fixed(mj, t: int) -> bool:
    """Whether MuJoCo's tendon t is a fixed tendon (every wrap a joint: mjWRAP_JOINT)."""
    adr, num = int(mj.tendon_adr[t]), int(mj.tendon_num[t])
    return bool(np.all(mj.wrap_type[adr:adr + num] == 1))


def _motors_and_tendons(mj, model: Model, joint_of: dict, where: str) -> dict:
    """``_motors`` and ``_tendons``: the tendons that a motor pulls kept, the motors
    pointing at them."""
    motors, pulled = _motors(mj, model, joint_of, where)
    tendons, kept = _tendons(mj, model, joint_of, where, pulled)
    motors["actuator_tendon"] = np.array([kept.get(t, -1) for t in pulled], dtype=np.int64)
    return motors | tendons


def _motors(mj, model: Model, joint_of: dict, where: str) -> tuple[dict, list[int]]:
    """The ``Model.actuator_*`` fields of MuJoCo's actuators with a fixed gain, no bias or
    an affine one (``<motor>``, ``<position>``, ``<velocity>``, ``<general>`` so made) on a
    one-coordinate joint or a fixed tendon: the force ``clamp(gain · w + b₀ + b₁ L + b₂ L̇,
    forcerange)`` times ``gear`` on the joint's coordinate, or along the tendon
    (``algorithms.actuators``, A1), ``w`` the control clamped to ``ctrlrange``, or, with
    activation dynamics ``integrator``, ``filter`` or ``filterexact`` (one activation,
    not ``actearly``), the activation (A2); and the MuJoCo tendon of each (-1 for a joint).
    Any other actuator is left out, with a warning naming it: a muscle or user dynamics, a
    gain that depends on the state, or a force range on a force that depends on the
    state."""
    import mujoco

    names, dofs, gears, gains, biases, ctrl, force, skipped, pulled = ([] for _ in range(9))
    kinds, times, acts = [], [], []
    dynamics = {int(mujoco.mjtDyn.mjDYN_NONE): "none",
                int(mujoco.mjtDyn.mjDYN_INTEGRATOR): "integrator",
                int(mujoco.mjtDyn.mjDYN_FILTER): "filter",
                int(mujoco.mjtDyn.mjDYN_FILTEREXACT): "filterexact"}
    early = getattr(mj, "actuator_actearly", np.zeros(mj.nu))
    clamp = not _disabled(mj, "CLAMPCTRL")
    for a in range(mj.nu):
        name = _name(mj, _obj("ACTUATOR"), a, f"actuator{a}")
        target = int(mj.actuator_trnid[a, 0])
        on_joint = (mj.actuator_trntype[a] == mujoco.mjtTrn.mjTRN_JOINT
                    and target in joint_of and model.joint_dofs(joint_of[target]).stop
                    - model.joint_dofs(joint_of[target]).start == 1)
        on_tendon = (mj.actuator_trntype[a] == mujoco.mjtTrn.mjTRN_TENDON
                     and _fixed(mj, target))
        affine = mj.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_AFFINE
        bias = np.array(mj.actuator_biasprm[a, :3], dtype=float) if affine else np.zeros(3)
        clamped = bool(mj.actuator_forcelimited[a])
        kept = ((on_joint or on_tendon)
                and mj.actuator_gaintype[a] == mujoco.mjtGain.mjGAIN_FIXED
                and (mj.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_NONE or affine)
                and int(mj.actuator_dyntype[a]) in dynamics and not early[a]
                and not (clamped and np.any(bias[1:])))
        if not kept:
            skipped.append(name)
            continue
        names.append(name)
        dofs.append(model.joint_dofs(joint_of[target]).start if on_joint else -1)
        pulled.append(-1 if on_joint else target)
        gears.append(float(mj.actuator_gear[a, 0]))
        gains.append(float(mj.actuator_gainprm[a, 0]))
        biases.append(bias)
        limited = clamp and bool(mj.actuator_ctrllimited[a])
        ctrl.append(mj.actuator_ctrlrange[a] if limited else (-np.inf, np.inf))
        force.append(mj.actuator_forcerange[a] if clamped else (-np.inf, np.inf))
        kinds.append(dynamics[int(mj.actuator_dyntype[a])])
        times.append(float(mj.actuator_dynprm[a, 0]) if kinds[-1].startswith("filter")
                     else 0.0)
        acts.append(mj.actuator_actrange[a] if mj.actuator_actlimited[a]
                    else (-np.inf, np.inf))
    if skipped:
        warnings.warn(f"{where!r}: the actuators {', '.join(map(repr, skipped))} are left "
                      f"out of model.actuators: cgadyn models actuators of a fixed gain and "
                      f"an affine bias (motors, position and velocity servos, their force "
                      f"range only where the force does not depend on the state) on a hinge, "
                      f"a slide or a fixed tendon, without activation dynamics or through "
                      f"an integrator or a filter (no muscles)",
                      stacklevel=5)
    na = len(names)
    return dict(actuator_names=tuple(names), actuator_dof=np.array(dofs, dtype=np.int64),
                actuator_gear=np.array(gears, dtype=float),
                actuator_gain=np.array(gains, dtype=float),
                actuator_bias=np.array(biases, dtype=float).reshape(na, 3),
                actuator_ctrlrange=np.array(ctrl, dtype=float).reshape(na, 2),
                actuator_forcerange=np.array(force, dtype=float).reshape(na, 2),
                actuator_dynamics=tuple(kinds),
                actuator_time_constant=np.array(times, dtype=float),
                actuator_actrange=np.array(acts, dtype=float).reshape(na, 2)), pulled


def _tendons(mj, model: Model, joint_of: dict, where: str, pulled: list[int]
             ) -> tuple[dict, dict]:
    """The ``Model.tendon_*`` fields of MuJoCo's fixed tendons that carry a spring or a
    damper, that a motor pulls (``pulled``: MuJoCo's tendon ids) or that are limited or
    rub (``tendon_stiffness``, ``tendon_damping``, ``tendon_lengthspring``,
    ``tendon_range``, ``tendon_frictionloss``;
    the length ``Σ coef qpos`` of hinges and
    slides: ``wrap_prm``, ``wrap_objid``), and MuJoCo's id -> the index kept. A spatial tendon
    with a spring or damper, and a tendon's armature, are refused by name (they would change
    the passive forces or the mass matrix); a tendon's limit and friction loss, constraints
    that cgadyn does not hold, are warned of, as are fluid forces (``density``,
    ``viscosity``), which cgadyn does not compute."""
    names, rows, stiffness, damping, length, loose, kept = [], [], [], [], [], [], {}
    ranges, frictions = [], []
    armature = getattr(mj, "tendon_armature", np.zeros(mj.ntendon))
    k_on, b_on = float(not _disabled(mj, "SPRING")), float(not _disabled(mj, "DAMPER"))
    for t in range(mj.ntendon):
        name = _name(mj, _obj("TENDON"), t, f"tendon{t}")
        fixed = _fixed(mj, t)
        k, b = k_on * float(mj.tendon_stiffness[t]), b_on * float(mj.tendon_damping[t])
        passive = k != 0.0 or b != 0.0  # as <flag spring/damper="disable"> leave them
        if armature[t] != 0.0:
            raise ValueError(f"tendon {name!r} has armature {armature[t]}; cgadyn models "
                             f"the joints' armature only")
        if passive and not fixed:
            raise ValueError(f"tendon {name!r} is a spatial tendon with a spring or damper; "
                             f"cgadyn models those of fixed tendons only")
        limited, rubbing = bool(mj.tendon_limited[t]), mj.tendon_frictionloss[t] != 0.0
        if not fixed and (limited and _rope_sites(mj, t) is None or rubbing):
            loose.append(name)
        if not passive and t not in pulled and not (fixed and (limited or rubbing)):
            continue
        kept[t] = len(names)
        names.append(name)
        rows.append(_fixed_row(mj, model, joint_of, t))
        stiffness.append(k)
        damping.append(b)
        length.append(np.array(mj.tendon_lengthspring[t], dtype=float))
        ranges.append(mj.tendon_range[t] if limited and fixed else (-np.inf, np.inf))
        frictions.append(float(mj.tendon_frictionloss[t]))
    if loose:
        warnings.warn(f"{where!r}: the limits and friction loss of the tendons "
                      f"{', '.join(map(repr, loose))} are not held: cgadyn holds the limits "
                      f"and friction loss of joints and fixed tendons, and the limits of "
                      f"spatial tendons of two sites (ropes)", stacklevel=5)
    if mj.opt.density != 0.0 or mj.opt.viscosity != 0.0:
        warnings.warn(f"{where!r}: the fluid forces of density {mj.opt.density} and "
                      f"viscosity {mj.opt.viscosity} are left out: cgadyn computes no fluid "
                      f"forces", stacklevel=5)
    nt = len(names)
    return dict(tendon_names=tuple(names),
                tendon_coefficients=np.array(rows, dtype=float).reshape(nt, model.nv),
                tendon_stiffness=np.array(stiffness, dtype=float),
                tendon_damping=np.array(damping, dtype=float),
                tendon_spring_length=np.array(length, dtype=float).reshape(nt, 2),
                tendon_range=np.array(ranges, dtype=float).reshape(nt, 2),
                tendon_friction=np.array(frictions, dtype=float)), kept


def _rope_sites(mj, t: int) -> tuple[int, int] | None:
    """The two sites of MuJoCo's spatial tendon t where it is a straight segment between
    two sites (two wraps, each a site: ``mjWRAP_SITE``), else None."""
    import mujoco

    adr, num = int(mj.tendon_adr[t]), int(mj.tendon_num[t])
    if num != 2 or np.any(mj.wrap_type[adr:adr + 2] != int(mujoco.mjtWrap.mjWRAP_SITE)):
        return None
    return int(mj.wrap_objid[adr]), int(mj.wrap_objid[adr + 1])


def _ropes(mj, model: Model) -> dict:
    """The ``Model.rope_*`` fields of MuJoCo's limited spatial tendons of two sites: the
    links of the sites' bodies (body b is link b, the world link 0), the sites in their
    bodies' frames (``site_pos``) and ``tendon_range``; held by the contact step (K46)."""
    names, links, points, ranges = [], [], [], []
    for t in range(mj.ntendon):
        sites = _rope_sites(mj, t) if mj.tendon_limited[t] else None
        if sites is None:
            continue
        names.append(_name(mj, _obj("TENDON"), t, f"tendon{t}"))
        links.append([int(mj.site_bodyid[k]) for k in sites])
        points.append([np.array(mj.site_pos[k], dtype=float) for k in sites])
        ranges.append([max(0.0, float(mj.tendon_range[t, 0])), float(mj.tendon_range[t, 1])])
    nr = len(names)
    return dict(rope_names=tuple(names),
                rope_links=np.array(links, dtype=np.int64).reshape(nr, 2),
                rope_points=np.array(points, dtype=float).reshape(nr, 2, 3),
                rope_range=np.array(ranges, dtype=float).reshape(nr, 2))


def _fixed_row(mj, model: Model, joint_of: dict, t: int) -> np.ndarray:
    """The coefficients over cgadyn's velocity coordinates of MuJoCo's fixed tendon t, whose
    length is ``Σ coef qpos`` over its joints (``wrap_prm``, ``wrap_objid``)."""
    row = np.zeros(model.nv)
    for w in range(int(mj.tendon_adr[t]), int(mj.tendon_adr[t] + mj.tendon_num[t])):
        row[model.joint_dofs(joint_of[int(mj.wrap_objid[w])]).start] += mj.wrap_prm[w]
    return row


def _coupled(mj, model: Model, joint_of: dict, kind: str, i: int
             ) -> tuple[np.ndarray, float] | None:
    """``(a, x₀)`` of one end of a coupling: the coefficients of its length over cgadyn's
    velocity coordinates and its reference length, at ``qpos0`` (a hinge's or slide's
    ``qpos0``, a fixed tendon's ``tendon_length0``); None where it is not linear in
    ``qpos`` (a spatial tendon; a joint of several coordinates)."""
    import mujoco

    if kind == "joint":
        if int(mj.jnt_type[i]) not in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
            return None
        row = np.zeros(model.nv)
        row[model.joint_dofs(joint_of[i]).start] = 1.0
        return row, float(mj.qpos0[mj.jnt_qposadr[i]])
    if not _fixed(mj, i):
        return None
    return _fixed_row(mj, model, joint_of, i), float(mj.tendon_length0[i])


def _couplings(mj, model: Model, joint_of: dict, where: str) -> dict:
    """The ``Model.coupling_*`` fields of MuJoCo's active joint and tendon equalities
    (``<equality joint>``, ``<equality tendon>``): ``x₁ - x₁₀ = a₀ + a₁ (x₂ - x₂₀)``
    (``polycoef``; ``x₁ - x₁₀ = a₀`` without a second joint or tendon) over the values x of
    hinges, slides and fixed tendons, with their references at ``qpos0``, is the coupling
    ``(c₁ - a₁ c₂) · q = x₁₀ + a₀ - a₁ x₂₀``. A polynomial of higher degree, an end that is
    a spatial tendon, and an equality inactive at the start (``eq_active0`` 0) are left out
    with a warning."""
    import mujoco

    kinds = {int(mujoco.mjtEq.mjEQ_JOINT): "joint", int(mujoco.mjtEq.mjEQ_TENDON): "tendon"}
    names, rows, offsets, left = [], [], [], []
    for k in range(mj.neq):
        kind = kinds.get(int(mj.eq_type[k]))
        if kind is None:
            continue
        name = _name(mj, _obj("EQUALITY"), k, f"equality{k}")
        poly = np.asarray(mj.eq_data[k][:5], dtype=float)
        one = _coupled(mj, model, joint_of, kind, int(mj.eq_obj1id[k]))
        two = None if mj.eq_obj2id[k] < 0 else _coupled(mj, model, joint_of, kind,
                                                        int(mj.eq_obj2id[k]))
        nonlinear = mj.eq_obj2id[k] >= 0 and np.any(poly[2:] != 0.0)
        if (not mj.eq_active0[k] or one is None or nonlinear
                or (mj.eq_obj2id[k] >= 0 and two is None)):
            left.append(name)
            continue
        a, offset = one[0].copy(), one[1] + poly[0]
        if two is not None:
            a -= poly[1] * two[0]
            offset -= poly[1] * two[1]
        names.append(name)
        rows.append(a)
        offsets.append(offset)
    if left:
        warnings.warn(f"{where!r}: the joint and tendon couplings "
                      f"{', '.join(map(repr, left))} are left out: cgadyn holds the linear "
                      f"couplings of hinges, slides and fixed tendons active at the start",
                      stacklevel=4)
    ne = len(names)
    return dict(coupling_names=tuple(names),
                coupling_coefficients=np.array(rows, dtype=float).reshape(ne, model.nv),
                coupling_offset=np.array(offsets, dtype=float))


def load_mujoco(source, name: str | None = None, floating_base: bool | None = None,
                check_inertia: bool = True) -> Model:
    """The model of an MJCF file path or MJCF text, compiled by MuJoCo
    (``mujoco.MjModel.from_xml_path`` / ``from_xml_string``) and converted by
    ``from_mujoco``. The base is the file's own (a free joint floats the model);
    ``floating_base`` True or False must agree with it (a ``ValueError`` says what to change
    in the file). A ``ValueError`` carries MuJoCo's own message when it cannot compile
    the file."""
    mj = mujoco_model(source)
    model = from_mujoco(mj, name=name, check_inertia=check_inertia)
    if floating_base is not None and bool(floating_base) != model.floating_base:
        has = "has a free joint" if model.floating_base else "has no free joint"
        raise ValueError(f"{model.name!r}: floating_base={floating_base}, but the model "
                         f"{has} (MuJoCo compiles the file's own base); expected "
                         f"floating_base=None, or "
                         f"{'remove the' if model.floating_base else 'add a'} <freejoint/> "
                         f"{'from' if model.floating_base else 'to'} the top-level body")
    return model


def mujoco_model(source):
    """The compiled ``mujoco.MjModel`` of an MJCF path or MJCF text (a compiled model is
    returned as it is). A ``ValueError`` carries MuJoCo's own message when it cannot compile
    the file, a ``FileNotFoundError`` names a missing path."""
    import os
    from pathlib import Path

    import mujoco

    if isinstance(source, mujoco.MjModel):
        return source
    try:
        if isinstance(source, os.PathLike) or (isinstance(source, str) and "<" not in source):
            path = Path(source)
            if not path.is_file():
                raise FileNotFoundError(f"MJCF file not found: {str(path)!r}")
            return mujoco.MjModel.from_xml_path(str(path))
        text = source.decode() if isinstance(source, bytes) else source
        if not isinstance(text, str):
            raise ValueError(f"expected an MJCF path, MJCF text or a mujoco.MjModel, got "
                             f"{type(source).__name__}")
        return mujoco.MjModel.from_xml_string(text)
    except ValueError as exc:
        raise ValueError(f"MuJoCo could not compile the MJCF: {exc}") from None


def from_mujoco_state(model: Model, qpos, qvel) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's ``(qpos, qvel)`` ((..., nq), (..., nv)) as cgadyn's ``(q, v)``: each joint's
    record converts its block (a free joint's quaternion reordered to x, y, z, w and its
    linear velocity rotated into the body frame, ``v = Rᵀ qvel``)."""
    q = table.from_mujoco(model, qpos)
    return q, table.from_mujoco_velocity(model, q, qvel)


def to_mujoco_state(model: Model, q, v) -> tuple[np.ndarray, np.ndarray]:
    """cgadyn's ``(q, v)`` as MuJoCo's ``(qpos, qvel)``, the inverse of
    ``from_mujoco_state``."""
    return table.to_mujoco(model, q), table.mujoco_velocity(model, q, v)


def from_mujoco_acceleration(model: Model, q, v, qacc) -> np.ndarray:
    """MuJoCo's ``qacc`` (..., nv) as cgadyn's ``a`` at the state ``(q, v)`` (cgadyn's, e.g.
    from ``from_mujoco_state``): a free joint's linear part is ``Rᵀ qacc_lin - ω × v_lin``
    (MuJoCo's is the body origin's acceleration in the world frame), every other
    coordinate unchanged. So ``mj_forward``'s ``qacc`` compares with ``cgadyn.aba``."""
    return table.from_mujoco_acceleration(model, *_checked(model, q, v, qacc, "qacc"))


def to_mujoco_acceleration(model: Model, q, v, a) -> np.ndarray:
    """cgadyn's ``a`` at ``(q, v)`` as MuJoCo's ``qacc`` (a free joint's linear part
    ``R (v̇ + ω × v)``), the inverse of ``from_mujoco_acceleration``: what ``mj_inverse``
    reads."""
    return table.mujoco_acceleration(model, *_checked(model, q, v, a, "a"))


def _checked(model: Model, q, v, acc, name: str) -> tuple[np.ndarray, ...]:
    """``q``, ``v`` and an acceleration as float arrays whose last axes are nq, nv, nv."""
    out = []
    for x, label, n in ((q, "q", model.nq), (v, "v", model.nv), (acc, name, model.nv)):
        x = np.asarray(x, dtype=float)
        if x.ndim == 0 or x.shape[-1] != n:
            raise ValueError(f"{label} must have shape (..., {n}), got {x.shape}")
        out.append(x)
    return tuple(out)
