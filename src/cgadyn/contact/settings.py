"""How a contact step solves its contact problem (``docs/contact.md``, "The stopping rule",
"Rollouts with contact"): one frozen record, ``ContactSettings``, that ``simulate`` and
``contact_step`` take, instead of one keyword each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ContactSettings", "SOLVERS", "other_solver", "residual"]

SOLVERS = ("admm", "pgs")
"""The contact solvers by name (``contact.solver``: ADMM, K16-K17; PGS, K18)."""


def _number(name: str, value, low: float, strict: bool = False) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and \
        math.isfinite(value) and (value > low if strict else value >= low)
    if not ok:
        raise ValueError(f"ContactSettings: {name} must be a finite number "
                         f"{'>' if strict else '>='} {low:g}, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class ContactSettings:
    """The contact step's settings.

    ``solver``: the solver tried first, ``"pgs"`` (K18) or ``"admm"`` (K16-K17); where it
    does not converge the other goes on from its last forces. PGS first: on the redundant
    contacts of a robot standing on patches (a box's four corners, two per lying capsule;
    ``G`` far from full rank) it meets the tolerance in tens of sweeps where ADMM takes
    hundreds of iterations (``validation/contact_benchmark.py`` measures both).
    ``tolerance``: the stopping rule's absolute tolerance on each residual (K19; velocities
    in m/s and rad/s).
    ``max_iterations``: per solver. ``accept``: where neither solver meets ``tolerance``
    within ``max_iterations``, a step whose residuals are all at most ``accept`` keeps the
    last forces and goes on (a rollout counts such steps, ``Trajectory.contact_residual``
    shows their residuals); a larger residual stops the rollout, naming it. ``accept`` below
    ``tolerance`` is refused. ``margin``: a point whose gap, less the way it may travel in
    the step at its speed, is below it is a contact (m, K21a).
    ``patch``: a contact patch's points closer than it to one kept are not kept (m, K22):
    the flat facets of a curved shape's hull (a round foot's) are millimetres wide, and
    their corners would be nearly dependent rows on which both solvers take thousands of
    iterations, for a torque about the facet worth nothing; a patch narrower than ``patch``
    is one point. ``stabilization``: the fraction of a penetration, or of a joint's
    overshoot past its limit, taken back per step by the position update (K43, K26a), in
    [0, 1]. ``warm_start``: a contact that stays starts from its force of the step before
    (K25)."""

    solver: str = "pgs"
    tolerance: float = 1e-10
    max_iterations: int = 1000
    accept: float = 1e-6
    margin: float = 1e-3
    patch: float = 1e-2
    stabilization: float = 0.2
    warm_start: bool = True

    def __post_init__(self):
        if self.solver not in SOLVERS:
            raise ValueError(f"ContactSettings: solver must be one of {SOLVERS}, got "
                             f"{self.solver!r}")
        tol = _number("tolerance", self.tolerance, 0.0, strict=True)
        accept = _number("accept", self.accept, 0.0)
        if accept < tol:
            raise ValueError(f"ContactSettings: accept ({accept:g}) must be at least the "
                             f"tolerance ({tol:g}): it is the residual a step may end "
                             f"with when the solvers stop short of the tolerance")
        if isinstance(self.max_iterations, bool) or not isinstance(self.max_iterations, int) \
                or self.max_iterations < 1:
            raise ValueError(f"ContactSettings: max_iterations must be an integer >= 1, got "
                             f"{self.max_iterations!r}")
        _number("margin", self.margin, 0.0)
        _number("patch", self.patch, 0.0)
        stab = _number("stabilization", self.stabilization, 0.0)
        if stab > 1.0:
            raise ValueError(f"ContactSettings: stabilization must lie in [0, 1], got "
                             f"{self.stabilization!r}")
        if not isinstance(self.warm_start, bool):
            raise ValueError(f"ContactSettings: warm_start must be True or False, got "
                             f"{self.warm_start!r}")


def other_solver(solver: str) -> str:
    """The solver that goes on where ``solver`` stops short of the tolerance."""
    return SOLVERS[1 - SOLVERS.index(solver)]


def residual(info) -> float:
    """The largest of a solve's three residuals (K19), which ``accept`` bounds."""
    return max(float(info.primal), float(info.dual), float(info.complementarity))
