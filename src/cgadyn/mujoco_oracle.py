"""MuJoCo, the second oracle: an MJCF model's smooth dynamics in MuJoCo and in cgadyn, in
cgadyn's layout, for ``cgadyn validate`` and the tests.

The model is compiled by MuJoCo and converted by ``multibody.mujoco_model.from_mujoco``;
the comparison runs on a copy of the compiled model (``smooth``) with contacts, joint
limits, equality constraints, friction loss and actuation disabled
(``opt.disableflags``), fluid forces and gravity compensation off (``opt.density``,
``opt.viscosity``, ``body_gravcomp`` zero) and cgadyn's default gravity, so that what
remains is the rigid-body dynamics with armature, damping and springs:

- ``mj_placements``: ``link_placements`` against ``xpos``/``xmat`` after ``mj_kinematics``;
- ``mj_mass_matrix``: ``crba`` against ``mj_fullM`` (armature included);
- ``mj_rnea``: ``rnea(q, v, a)`` against ``qfrc_inverse + qfrc_passive`` of ``mj_inverse``
  (MuJoCo subtracts the passive forces; cgadyn's rnea does not include them);
- ``mj_aba``: ``aba(q, v, τ + passive_torques)`` against ``qacc`` of ``mj_forward`` with
  ``qfrc_applied = τ``;
- ``mj_passive``: ``passive_torques`` against ``qfrc_passive``.

MuJoCo's quantities are moved into cgadyn's layout by the joint records' maps
(``multibody.joints``): ``qvel = T(q) v`` with T orthogonal (a free joint's linear velocity
rotated into the world), so forces, dual to velocities, map as ``τ = Tᵀ τ_mj`` (the same
map as the velocity's inverse), the mass matrix as ``Tᵀ M_mj T``, and accelerations as
``qacc = T a + Ṫ v``.
"""

from __future__ import annotations

import numpy as np

from .multibody.joints import table
from .multibody.packed import DEFAULT_GRAVITY

CHECKS = {
    "mj_placements": "MuJoCo: body placements (xpos, xmat)",
    "mj_mass_matrix": "MuJoCo: mass matrix (mj_fullM)",
    "mj_rnea": "MuJoCo: inverse dynamics (mj_inverse)",
    "mj_aba": "MuJoCo: forward dynamics (qacc)",
    "mj_passive": "MuJoCo: passive torques (qfrc_passive)",
}
"""What is compared with MuJoCo: key -> label."""
SCALED = ("mj_aba",)
"""The checks judged against tolerance × cond(M), as ``oracle.SCALED`` says."""

_DISABLED = ("CONTACT", "LIMIT", "EQUALITY", "FRICTIONLOSS", "ACTUATION")


def applies(robot) -> bool:
    """Whether MuJoCo checks ``robot``: an MJCF model, with MuJoCo installed."""
    from .multibody import mujoco_model, registry

    return registry.resolve(robot)[0] == "mjcf" and mujoco_model.available()


def compiled(robot):
    """The compiled ``mujoco.MjModel`` of an MJCF path, text or registered name
    (``registry.resolve`` decides)."""
    from .multibody import registry
    from .multibody.mujoco_model import mujoco_model

    kind, value, _ = registry.resolve(robot)
    if kind != "mjcf":
        raise ValueError(f"{robot!r} is not an MJCF model: MuJoCo compares MJCF models only")
    return mujoco_model(value)


def smooth(mj_model):
    """A copy of ``mj_model`` whose forward dynamics are the smooth ones cgadyn computes
    (the module's docstring)."""
    import copy

    import mujoco

    mj = copy.copy(mj_model)
    for flag in _DISABLED:
        mj.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, f"mjDSBL_{flag}"))
    mj.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)  # cgadyn's gravity
    mj.opt.density = 0.0
    mj.opt.viscosity = 0.0
    mj.opt.gravity[:] = DEFAULT_GRAVITY
    mj.body_gravcomp[:] = 0.0
    return mj


def velocity_map(model, q) -> np.ndarray:
    """``T(q)`` (nv, nv) with ``qvel = T v`` (the joint records' ``mujoco_velocity``)."""
    return table.mujoco_velocity(model, np.broadcast_to(q, (model.nv, model.nq)),
                                 np.eye(model.nv)).T


def body_links(model, mj) -> list[int]:
    """The index in ``model.link_names`` of every MuJoCo body (the world first)."""
    import mujoco

    names = [mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
             for b in range(mj.nbody)]
    names[0] = model.link_names[0]
    return [model.link_names.index(name) for name in names]


def references(model, mj_model, states) -> dict[str, np.ndarray]:
    """MuJoCo's side of every check of ``CHECKS`` for a batch of cgadyn states (``oracle``
    ``States``: q, v, a, τ), in cgadyn's layout; one sample at a time."""
    import mujoco

    mj = smooth(mj_model)
    d = mujoco.MjData(mj)
    out = {key: [] for key in CHECKS}
    M = np.zeros((mj.nv, mj.nv))
    for i in range(states.q.shape[0]):
        q, v, a, tau = states.q[i], states.v[i], states.a[i], states.tau[i]
        T = velocity_map(model, q)
        qpos, qvel = table.to_mujoco(model, q), T @ v
        mujoco.mj_resetData(mj, d)
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_kinematics(mj, d)
        out["mj_placements"].append(np.concatenate(
            [d.xmat.reshape(-1, 3, 3), d.xpos.reshape(-1, 3, 1)], axis=2))
        d.qacc[:] = table.mujoco_acceleration(model, q, v, a)
        mujoco.mj_inverse(mj, d)
        mujoco.mj_fullM(mj, d, M)  # MuJoCo 4: (m, d, dst)
        out["mj_mass_matrix"].append(T.T @ M @ T)
        out["mj_rnea"].append(T.T @ (d.qfrc_inverse + d.qfrc_passive))
        out["mj_passive"].append(T.T @ d.qfrc_passive)
        d.qfrc_applied[:] = T @ tau  # τ_mj with Tᵀ τ_mj = τ (T orthogonal)
        mujoco.mj_forward(mj, d)
        out["mj_aba"].append(table.from_mujoco_acceleration(model, q, v, d.qacc))
    return {key: np.array(value) for key, value in out.items()}


def mine(model, mj_model, states) -> dict[str, np.ndarray]:
    """cgadyn's side of every check of ``CHECKS``, batch calls."""
    import cgadyn

    passive = cgadyn.passive_torques(model, states.q, states.v)
    placements = cgadyn.link_placements(model, states.q)[:, body_links(model, mj_model)]
    return {"mj_placements": placements[:, :, :3, :],
            "mj_mass_matrix": cgadyn.crba(model, states.q),
            "mj_rnea": cgadyn.rnea(model, states.q, states.v, states.a),
            "mj_aba": cgadyn.aba(model, states.q, states.v, states.tau + passive),
            "mj_passive": passive}
