"""The public algorithms: one sample ``(nq,)``/``(nv,)`` or a batch ``(B, ...)`` in, arrays out.

Every function takes the model first. ``q`` has ``model.nq`` entries and ``v, a, tau``
``model.nv``, ordered like ``model.joint_names`` (Pinocchio's order; a free-flyer root
first); gravity is a world-frame 3-vector. A batch runs as one compiled call in parallel
over its samples and returns the same leading shape. The path of a call is described in
``calls.py``: ``rnea``, ``aba`` and ``crba`` try the fast path first, the
others call ``calls.run``.
"""

from __future__ import annotations

import numpy as np

from ..cga.conventions import twist_from_motion
from . import _inputs
from .calls import SLOTS, fast, run
from .jacobian import LOCAL, LOCAL_WORLD_ALIGNED, WORLD

G = _inputs.DEFAULT_GRAVITY
_RNEA, _ABA, _CRBA = SLOTS["rnea"], SLOTS["aba"], SLOTS["crba"]
_ndarray = np.ndarray  # a module global: one lookup less per call


def rnea(model, q, v, a, gravity=G, f_ext=None) -> np.ndarray:
    """Joint torques ``τ`` of inverse dynamics (Algorithm 2): ``M(q) a + C(q, v) v + g(q)``.

    ``f_ext``: optional external force per joint, Pinocchio's ``[f, τ]`` in the joint frame,
    shape (n, 6) (``n = model.njoints``) or (B, n, 6).
    """
    if gravity is G and f_ext is None:
        tau = fast(_RNEA, model.packed, q, v, a, None)
        if tau.__class__ is _ndarray:
            return tau
    return run("rnea", model, (q, v, a), gravity, f_ext)


def aba(model, q, v, tau, gravity=G, f_ext=None) -> np.ndarray:
    """Joint accelerations ``q̈`` of forward dynamics (Algorithms 1 and 3)."""
    if gravity is G and f_ext is None:
        qdd = fast(_ABA, model.packed, q, v, tau, None)
        if qdd.__class__ is _ndarray:
            return qdd
    return run("aba", model, (q, v, tau), gravity, f_ext)


def crba(model, q) -> np.ndarray:
    """Joint-space mass matrix ``M(q)``, full and symmetric, (nv, nv) or (B, nv, nv)."""
    H = fast(_CRBA, model.packed, q)
    if H.__class__ is _ndarray:
        return H
    return run("crba", model, (q,))


def gravity_torques(model, q, gravity=G) -> np.ndarray:
    """Generalized gravity ``g(q)``: RNEA with zero velocity and acceleration."""
    q = _inputs.state(model, q, "q", model.nq)
    z = np.zeros(q.shape[:-1] + (model.nv,))
    return rnea(model, q, z, z, gravity)


def nonlinear_effects(model, q, v, gravity=G) -> np.ndarray:
    """``C(q, v) v + g(q)``: RNEA with zero acceleration."""
    v = _inputs.state(model, v, "v", model.nv)
    return rnea(model, q, v, np.zeros_like(v), gravity)


def forward_kinematics(model, q) -> tuple[np.ndarray, np.ndarray]:
    """World motors of the joint frames (..., n, 8) and of every link frame (..., nl, 8)."""
    return run("motors", model, (q,))


def link_placements(model, q) -> np.ndarray:
    """World 4x4 homogeneous matrices of every link frame, (..., nl, 4, 4)."""
    return run("placements", model, (q,))


_FRAMES = {"world": WORLD, "local": LOCAL, "local_world_aligned": LOCAL_WORLD_ALIGNED}


def jacobian(model, q, link: str | int, frame: str = "world", layout: str = "pinocchio"):
    """Geometric Jacobian of a link.

    ``frame``: ``'world'`` (twists at the world origin, Pinocchio's WORLD), ``'local'`` (in
    the link frame, LOCAL) or ``'local_world_aligned'`` (at the link origin, world axes).
    ``layout='pinocchio'`` returns Pinocchio's (..., 6, nv) matrix, rows ``[v, ω]``;
    ``layout='twist'`` returns the CGA twist of each velocity coordinate, (..., nv, 6).
    """
    if frame not in _FRAMES:
        raise ValueError(f"frame must be one of {sorted(_FRAMES)}, got {frame!r}")
    if layout not in ("pinocchio", "twist"):
        raise ValueError(f"layout must be 'pinocchio' or 'twist', got {layout!r}")
    J = run("jacobian", model, (q,), options=(_inputs.link_index(model, link), _FRAMES[frame]))
    return twist_from_motion(np.swapaxes(J, -1, -2)) if layout == "twist" else J


def energy(model, q, v, gravity=G) -> np.ndarray:
    """Kinetic and potential energy, ``[..., (T, U)]``; ``U = -Σ m g·c`` as in Pinocchio."""
    return run("energy", model, (q, v), gravity)


def kinetic_energy(model, q, v) -> np.ndarray | float:
    """``T = ½ Σ_j p(V_j, I_j[V_j])`` (eqs. 9, 15)."""
    e = energy(model, q, v)
    return e[..., 0] if e.ndim > 1 else float(e[0])


def potential_energy(model, q, gravity=G) -> np.ndarray | float:
    """``U = -Σ_j m_j g · c_j`` with c_j the world centre of mass of body j."""
    q = _inputs.state(model, q, "q", model.nq)
    e = energy(model, q, np.zeros(q.shape[:-1] + (model.nv,)), gravity)
    return e[..., 1] if e.ndim > 1 else float(e[1])


__all__ = ["aba", "crba", "energy", "forward_kinematics", "gravity_torques", "jacobian",
           "kinetic_energy", "link_placements", "nonlinear_effects",
           "potential_energy", "rnea"]
