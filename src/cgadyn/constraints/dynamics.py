"""Constrained forward dynamics (C6-C8) and impulse dynamics (C9), each one compiled call
(``constraints/core.py``: γ, G by the articulated-body recursion C12, the free motion and
M⁻¹ Jᵀ λ by its sweeps C13, and the forces), and contact inverse dynamics (C10) on the
compiled J and ``rnea``.

Forces come in Pinocchio's ``lambda_c`` layout: ``[f]`` per point constraint and ``[f, τ]``
per frame constraint, each in its constraint's frame, in constraint order. A batch of states
is one parallel compiled call.
"""

from __future__ import annotations

import numpy as np

from ..algorithms import _inputs
from ..algorithms.api import rnea
from .calls import DYNAMICS_GROUP, fast, run
from .core import FORWARD, IMPULSE, SYSTEM
from .model import pack
from .operators import (
    ACCURACY,
    NO_DAMPING,
    NO_RESTITUTION,
    PLAIN,
    checked_settings,
    states,
    zeros_like_v,
)
from .solve import solve_info

G0 = _inputs.DEFAULT_GRAVITY
DEFAULT = checked_settings(NO_DAMPING, None, ACCURACY, NO_RESTITUTION)
"""The settings of a call with the defaults (``operators.NO_DAMPING``)."""


def _finish(p, out, return_info):
    """``(x, λ)`` or ``(x, λ, info)`` from the core's outputs; a set with no solution is an
    error (``solve.solve_info``)."""
    x, lam, info = out
    if info.ndim == 1 and not return_info and info[4] < 0.0:
        return x, lam
    if info.ndim == 1:
        i = solve_info(p.constraints, p.starts, info)
    else:
        i = [solve_info(p.constraints, p.starts, row) for row in info]
    return (x, lam, i) if return_info else (x, lam)


def constrained_dynamics(model, q, v, tau, constraints, damping=NO_DAMPING, iterations=None,
                         accuracy=ACCURACY, return_info=False, gravity=G0):
    """``q̈, forces`` of ``M q̈ = τ - h + Jᵀ λ``, ``J q̈ = -γ`` (C6); Pinocchio's
    ``constraintDynamics``.

    ``damping`` (Pinocchio's ``ProximalSettings.mu``): 0 solves the system once, and a
    singular Delassus matrix (redundant or conflicting constraints) is an error naming the
    constraint; ``damping > 0`` runs at most ``iterations`` proximal iterations (C8; default
    100), which give the least-norm forces of a redundant set and stop when ``|J q̈ + γ|∞``
    or the change of λ is at most ``accuracy``. A set with no solution is an error naming the
    constraint with the largest violation. ``return_info=True`` adds a ``SolveInfo``
    (``iterations``, ``residual``, ``change``, ``converged``; a list for a batch).
    ``q`` (nq,) or (B, nq), ``v``, ``tau`` (nv,) or (B, nv).
    """
    p = pack(model, constraints)
    s = DEFAULT if damping is NO_DAMPING and iterations is None and accuracy is ACCURACY \
        else checked_settings(damping, iterations, accuracy)
    if DYNAMICS_GROUP in p.slots and gravity is G0:  # the fast path: one canonical sample
        r = fast(p.slots[DYNAMICS_GROUP], model.packed, p.array, q, v, tau, s, FORWARD)
        if type(r) is tuple:
            return _finish(p, r, return_info)
    q, v, tau = states(model, (q, v, tau), ("q", "v", "tau"))
    return _finish(p, run(model, p, FORWARD, q, v, tau, s, gravity), return_info)


def impulse_dynamics(model, q, v, constraints, restitution=NO_RESTITUTION, damping=NO_DAMPING,
                     iterations=None, accuracy=ACCURACY, return_info=False):
    """``v⁺, impulses`` of an impact (C9): ``M (v⁺ - v) = Jᵀ Λ`` with ``J v⁺ = -e J v``;
    Pinocchio's ``impulseDynamics``. ``restitution`` e in [0, 1]; ``damping``,
    ``iterations``, ``accuracy`` and ``return_info`` as in ``constrained_dynamics``."""
    p = pack(model, constraints)
    s = DEFAULT if (damping is NO_DAMPING and iterations is None and accuracy is ACCURACY
                    and restitution is NO_RESTITUTION) \
        else checked_settings(damping, iterations, accuracy, restitution)
    if DYNAMICS_GROUP in p.slots:  # the fast path: one canonical sample
        r = fast(p.slots[DYNAMICS_GROUP], model.packed, p.array, q, v, v, s, IMPULSE)
        if type(r) is tuple:
            return _finish(p, r, return_info)
    q, v = states(model, (q, v), ("q", "v"))
    return _finish(p, run(model, p, IMPULSE, q, v, v, s), return_info)


def contact_inverse_dynamics(model, q, v, a, constraints, gravity=G0):
    """``τ, forces`` that produce the acceleration ``a`` (C10): ``τ = M a + h - Jᵀ λ`` with
    ``τ`` zero on the coordinates no actuator drives (a free flyer's six) and ``λ`` the
    least-norm forces that balance them (zero where every coordinate is actuated). An
    unactuated part the constraints cannot balance is an error. ``a`` should satisfy
    ``J a + γ = 0`` for ``constrained_dynamics(τ)`` to give it back."""
    p = pack(model, constraints)
    q, v, a = states(model, (q, v, a), ("q", "v", "a"))
    free = ~np.asarray(model.actuated, dtype=bool)
    z = zeros_like_v(model, q)
    Js = run(model, p, SYSTEM, q, z, z, PLAIN)[0]
    taus = rnea(model, q, v, a, gravity)

    def one(J, tau):
        if not free.any() or len(J) == 0:
            lam = np.zeros(len(J))
        else:
            lam = np.linalg.lstsq(J[:, free].T, tau[free], rcond=None)[0]  # C10
        tau = tau - J.T @ lam
        scale = max(1.0, float(np.abs(tau).max()))
        if free.any() and np.abs(tau[free]).max() > 1e-9 * scale:
            raise ValueError(f"the constraints cannot balance the unactuated coordinates "
                             f"({', '.join(np.array(model.coordinate_names(True))[free])}): "
                             f"a force of {np.abs(tau[free]).max():.3g} is left on them")
        tau[free] = 0.0
        return tau, lam

    if q.ndim == 1:
        return one(Js, taus)
    if len(q) == 0:
        return np.empty((0, model.nv)), np.empty((0, p.nr))
    out = [one(J, t) for J, t in zip(Js, taus, strict=True)]
    return np.stack([o[0] for o in out]), np.stack([o[1] for o in out])
