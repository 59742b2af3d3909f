"""The operators of a list of constraints: the Jacobian J (C1, C2), the drift γ (C3-C5) and the
Delassus matrix G = J M⁻¹ Jᵀ (C7), for one state or a batch.

Rows follow the constraints in their order, each in its own frame (``Constraint.frame``), as
Pinocchio's ``getConstraintsJacobian`` gives them. A batch ``(B, nq)`` runs the compiled
calls (placements, Jacobians, M⁻¹) once for all samples and assembles each sample's
matrices in a Python loop.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..algorithms import _inputs
from ..algorithms.derivatives_api import minverse
from .kinematics import drift, ends, placements, rows
from .model import check_constraints


def states(model, arrays: tuple, names: tuple[str, ...]) -> tuple[np.ndarray, ...]:
    """The state arrays (q first, then nv-sized ones), checked, one sample each or batches of
    the same size."""
    sizes = {"q": model.nq}
    out = tuple(_inputs.state(model, a, n, sizes.get(n, model.nv))
                for a, n in zip(arrays, names, strict=True))
    if any(a.shape[:-1] != out[0].shape[:-1] for a in out):
        detail = ", ".join(f"{n} {a.shape}" for n, a in zip(names, out, strict=True))
        raise ValueError(f"inputs must be one sample each or batches of the same size: {detail}")
    return out


def each(function: Callable, kinematics: list, arrays: tuple[np.ndarray, ...]):
    """``function(kinematics, *sample)`` on one sample, or on each sample of a batch with its
    results stacked (each array of a tuple of results stacked; other results listed)."""
    if arrays[0].ndim == 1:
        return function(kinematics[0], *arrays)
    results = [function(k, *x) for k, x in zip(kinematics, zip(*arrays, strict=True),
                                                strict=True)]
    if not results:
        return np.empty((0,))
    if not isinstance(results[0], tuple):
        return np.stack(results)
    return tuple(np.stack(r) if isinstance(r[0], np.ndarray) else list(r)
                 for r in zip(*results, strict=True))


def kinematics(model, q: np.ndarray, constraints) -> list:
    """The compiled part of the rows, one call for all samples (``placements``), split into
    one ``(T, {link: J})`` per sample."""
    T, jacobians = placements(model, q, constraints)
    if q.ndim == 1:
        return [(T, jacobians)]
    return [(T[b], {i: J[b] for i, J in jacobians.items()}) for b in range(len(q))]


def system(model, kinematics: tuple, v: np.ndarray | None, constraints) -> tuple:
    """``J`` (m, nv) and, with v, ``γ`` (m,) at one state."""
    pairs = ends(model, *kinematics, constraints, v)
    J = np.concatenate([rows(c, *e) for c, e in zip(constraints, pairs, strict=True)]
                       or [np.zeros((0, model.nv))])
    if v is None:
        return J, None
    g = np.concatenate([drift(c, *e) for c, e in zip(constraints, pairs, strict=True)]
                       or [np.zeros(0)])
    return J, g


def constraint_jacobian(model, q, constraints) -> np.ndarray:
    """The constraint Jacobian ``J`` (m, nv), or (B, m, nv): C1 rows for a point, C2 for a
    frame, in constraint order; Pinocchio's ``getConstraintsJacobian``."""
    constraints = check_constraints(model, constraints)
    (q,) = states(model, (q,), ("q",))
    return each(lambda k, x: system(model, k, None, constraints)[0],
                kinematics(model, q, constraints), (q,))


def constraint_drift(model, q, v, constraints) -> np.ndarray:
    """``γ`` (m,) or (B, m): the acceleration of the constraint rows at ``q̈ = 0`` (C3, C4)
    with the Baumgarte terms of each constraint's corrector (C5), so that the constrained
    motion has ``J q̈ + γ = 0`` (C6), Pinocchio's convention."""
    constraints = check_constraints(model, constraints)
    q, v = states(model, (q, v), ("q", "v"))
    return each(lambda k, x, y: system(model, k, y, constraints)[1],
                kinematics(model, q, constraints), (q, v))


def damping_value(damping) -> float:
    try:
        mu = float(damping)
    except (TypeError, ValueError):
        mu = float("nan")
    if not np.isfinite(mu) or mu < 0.0:
        raise ValueError(f"damping must be a finite number >= 0, got {damping!r}")
    return mu


def delassus_matrix(Minv: np.ndarray, J: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``G = J M⁻¹ Jᵀ`` (C7) and ``M⁻¹ Jᵀ`` at one configuration, M⁻¹ from the
    articulated-body recursion (``cgadyn.minverse``)."""
    MinvJt = Minv @ J.T
    return J @ MinvJt, MinvJt


def delassus(model, q, constraints, damping=0.0) -> np.ndarray:
    """The Delassus matrix ``G + damping·I`` (m, m) or (B, m, m), ``G = J M⁻¹ Jᵀ`` (C7), in
    the constraints' frames. Pinocchio 4.1's ``computeDelassusMatrix`` at ``mu = 0`` gives G
    for constraints anchored to the world, in their local frames (docs/constraints.md); its
    ``mu`` is not a shift of the diagonal."""
    constraints = check_constraints(model, constraints)
    mu = damping_value(damping)
    (q,) = states(model, (q,), ("q",))

    def one(k, x, Minv):
        G = delassus_matrix(Minv, system(model, k, None, constraints)[0])[0]
        return G + mu * np.eye(len(G))

    return each(one, kinematics(model, q, constraints), (q, minverse(model, q)))
