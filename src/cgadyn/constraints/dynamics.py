"""Constrained forward dynamics (C6-C8), impulse dynamics (C9) and contact inverse dynamics
(C10), built on the compiled ``aba``, ``minverse`` and ``rnea``.

Forces come in Pinocchio's ``lambda_c`` layout: ``[f]`` per point constraint and ``[f, τ]``
per frame constraint, each in its constraint's frame, in constraint order. A batch of states
runs the compiled calls once for all samples and assembles each sample in a Python loop.
"""

from __future__ import annotations

import numpy as np

from ..algorithms import _inputs
from ..algorithms.api import aba, rnea
from ..algorithms.derivatives_api import minverse
from .model import check_constraints
from .operators import damping_value, delassus_matrix, each, kinematics, states, system
from .solve import solve

G0 = _inputs.DEFAULT_GRAVITY


def _settings(damping, iterations, accuracy) -> tuple[float, int, float]:
    mu = damping_value(damping)
    if iterations is None:
        iterations = 1 if mu == 0.0 else 100
    if isinstance(iterations, bool) or not isinstance(iterations, int | np.integer) \
            or iterations < 1:
        raise ValueError(f"iterations must be an integer >= 1, got {iterations!r}")
    try:
        acc = float(accuracy)
    except (TypeError, ValueError):
        acc = float("nan")
    if not np.isfinite(acc) or acc < 0.0:
        raise ValueError(f"accuracy must be a finite number >= 0, got {accuracy!r}")
    return mu, int(iterations), acc


def constrained_dynamics(model, q, v, tau, constraints, damping=0.0, iterations=None,
                         accuracy=1e-12, return_info=False, gravity=G0):
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
    constraints = check_constraints(model, constraints)
    mu, n, acc = _settings(damping, iterations, accuracy)
    q, v, tau = states(model, (q, v, tau), ("q", "v", "tau"))

    def one(k, y, a_free, Minv):
        J, g = system(model, k, y, constraints)
        G, MinvJt = delassus_matrix(Minv, J)
        lam, info = solve(G, -g - J @ a_free, constraints, mu, n, acc)  # C6, C8
        return a_free + MinvJt @ lam, lam, info

    out = each(one, kinematics(model, q, constraints),
               (v, aba(model, q, v, tau, gravity), minverse(model, q)))
    return out if return_info else out[:2]


def impulse_dynamics(model, q, v, constraints, restitution=0.0, damping=0.0, iterations=None,
                     accuracy=1e-12, return_info=False):
    """``v⁺, impulses`` of an impact (C9): ``M (v⁺ - v) = Jᵀ Λ`` with ``J v⁺ = -e J v``;
    Pinocchio's ``impulseDynamics``. ``restitution`` e in [0, 1]; ``damping``,
    ``iterations``, ``accuracy`` and ``return_info`` as in ``constrained_dynamics``."""
    constraints = check_constraints(model, constraints)
    mu, n, acc = _settings(damping, iterations, accuracy)
    try:
        e = float(restitution)
    except (TypeError, ValueError):
        e = float("nan")
    if not 0.0 <= e <= 1.0:
        raise ValueError(f"restitution must be a number in [0, 1], got {restitution!r}")
    q, v = states(model, (q, v), ("q", "v"))

    def one(k, y, Minv):
        J, _ = system(model, k, None, constraints)
        G, MinvJt = delassus_matrix(Minv, J)
        lam, info = solve(G, -(1.0 + e) * (J @ y), constraints, mu, n, acc)  # C9
        return y + MinvJt @ lam, lam, info

    out = each(one, kinematics(model, q, constraints), (v, minverse(model, q)))
    return out if return_info else out[:2]


def contact_inverse_dynamics(model, q, v, a, constraints, gravity=G0):
    """``τ, forces`` that produce the acceleration ``a`` (C10): ``τ = M a + h - Jᵀ λ`` with
    ``τ`` zero on the coordinates no actuator drives (a free flyer's six) and ``λ`` the
    least-norm forces that balance them (zero where every coordinate is actuated). An
    unactuated part the constraints cannot balance is an error. ``a`` should satisfy
    ``J a + γ = 0`` for ``constrained_dynamics(τ)`` to give it back."""
    constraints = check_constraints(model, constraints)
    q, v, a = states(model, (q, v, a), ("q", "v", "a"))
    free = ~np.asarray(model.actuated, dtype=bool)

    def one(k, tau):
        J, _ = system(model, k, None, constraints)
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

    return each(one, kinematics(model, q, constraints), (rnea(model, q, v, a, gravity),))
