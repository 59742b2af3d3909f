"""The operators of a list of constraints: the Jacobian J (C1, C2), the drift γ (C3-C5) and the
Delassus matrix G = J M⁻¹ Jᵀ (C7), for one state or a batch.

Rows follow the constraints in their order, each in its own frame (``Constraint.frame``), as
Pinocchio's ``getConstraintsJacobian`` gives them. Each is one compiled call
(``constraints/core.py``), a batch one parallel call.
"""

from __future__ import annotations

import numpy as np

from ..algorithms import _inputs
from .calls import DELASSUS_GROUP, SYSTEM_GROUP, fast, run
from .core import DELASSUS, DRIFT, SYSTEM
from .model import pack


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


def zeros_like_v(model, q: np.ndarray) -> np.ndarray:
    """A velocity-sized zero array for the modes that read none, shaped like q's batch."""
    return np.zeros(q.shape[:-1] + (model.nv,))


_SETTINGS: dict = {}


def checked_settings(damping, iterations=1, accuracy=0.0, restitution=0.0) -> np.ndarray:
    """The core's settings ``[μ, iterations, accuracy, restitution]`` of these arguments,
    checked, as one array made once per set of values (``iterations`` None: 1 without damping,
    else 100)."""
    try:
        key = (damping, iterations, type(iterations), accuracy, restitution)
        found = _SETTINGS.get(key)
    except TypeError:  # an unhashable argument
        key = found = None
    if found is not None:
        return found
    mu = damping_value(damping)
    if iterations is None:
        iterations = 1 if mu == 0.0 else 100
    if isinstance(iterations, bool) or not isinstance(iterations, int | np.integer) \
            or iterations < 1:
        raise ValueError(f"iterations must be an integer >= 1, got {iterations!r}")
    acc = _inputs.nonnegative(accuracy, "accuracy")
    try:
        e = float(restitution)
    except (TypeError, ValueError):
        e = float("nan")
    if not 0.0 <= e <= 1.0:
        raise ValueError(f"restitution must be a number in [0, 1], got {restitution!r}")
    found = np.array([mu, int(iterations), acc, e], dtype=float)
    if key is not None:
        if len(_SETTINGS) > 256:
            _SETTINGS.clear()
        _SETTINGS[key] = found
    return found


NO_DAMPING, NO_RESTITUTION, ACCURACY = 0.0, 0.0, 1e-12
"""The defaults of the public functions' ``damping``, ``restitution`` and ``accuracy``: an
argument that *is* its default object skips ``checked_settings`` (a call's own cost)."""
def constraint_jacobian(model, q, constraints) -> np.ndarray:
    """The constraint Jacobian ``J`` (m, nv), or (B, m, nv): C1 rows for a point, C2 for a
    frame, in constraint order; Pinocchio's ``getConstraintsJacobian``."""
    p = pack(model, constraints)
    if SYSTEM_GROUP in p.slots:  # the fast path: the C entry takes one canonical sample
        r = fast(p.slots[SYSTEM_GROUP], model.packed, p.array, q, p.zero, p.zero,
                 PLAIN, SYSTEM)
        if type(r) is tuple:
            return r[0]
    (q,) = states(model, (q,), ("q",))
    z = zeros_like_v(model, q)
    return run(model, p, SYSTEM, q, z, z, PLAIN)[0]


def constraint_drift(model, q, v, constraints) -> np.ndarray:
    """``γ`` (m,) or (B, m): the acceleration of the constraint rows at ``q̈ = 0`` (C3, C4)
    with the Baumgarte terms of each constraint's corrector (C5), so that the constrained
    motion has ``J q̈ + γ = 0`` (C6), Pinocchio's convention."""
    p = pack(model, constraints)
    if SYSTEM_GROUP in p.slots:  # the fast path, as constraint_jacobian's
        r = fast(p.slots[SYSTEM_GROUP], model.packed, p.array, q, v, v, PLAIN,
                 DRIFT)
        if type(r) is tuple:
            return r[1]
    q, v = states(model, (q, v), ("q", "v"))
    return run(model, p, DRIFT, q, v, v, PLAIN)[1]


def damping_value(damping) -> float:
    return _inputs.nonnegative(damping, "damping")


PLAIN = checked_settings(NO_DAMPING)
"""The settings of a call with the defaults: no damping, one solve."""


def delassus(model, q, constraints, damping=NO_DAMPING) -> np.ndarray:
    """The Delassus matrix ``G + damping·I`` (m, m) or (B, m, m), ``G = J M⁻¹ Jᵀ`` (C7), in
    the constraints' frames. Pinocchio 4.1's ``computeDelassusMatrix`` at ``mu = 0`` gives G
    for constraints anchored to the world, in their local frames (docs/constraints.md); its
    ``mu`` is not a shift of the diagonal."""
    p = pack(model, constraints)
    s = PLAIN if damping is NO_DAMPING else checked_settings(damping)
    if DELASSUS_GROUP in p.slots:  # the fast path: the C entry takes one canonical sample
        G = fast(p.slots[DELASSUS_GROUP], model.packed, p.array, q, p.zero, p.zero, s,
                 DELASSUS)
        if type(G) is np.ndarray:
            return G
    (q,) = states(model, (q,), ("q",))
    z = zeros_like_v(model, q)
    return run(model, p, DELASSUS, q, z, z, s)
