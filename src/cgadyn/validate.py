"""Cross-validation of cgadyn against Pinocchio, in the style of Table 1 of the CGA paper,
and of an MJCF model against MuJoCo as well (``mujoco_oracle``).

For ``samples`` random states (``oracle.sample``) every check of ``oracle.CHECKS`` runs in
cgadyn, as one batch call, and per sample in Pinocchio; the result reports per check the
mean norm of the difference (the paper's measure), the largest absolute difference and the
largest relative difference (``oracle.RELATIVE``), judged against the tolerance, or for
forward dynamics and M⁻¹ against the tolerance times cond(M) of the sample
(``oracle.SCALED``).

    >>> from cgadyn.validate import validate_robot
    >>> result = validate_robot("panda", samples=100)
    >>> result["pass"], result["checks"]["aba"]["mean_norm"]

The paper (section 5.3) averaged over 1000 samples; the default here is 100.
"""

from __future__ import annotations

import math
import time

import numpy as np

from . import mujoco_oracle, oracle

DEFAULT_SAMPLES = 100
PAPER_SAMPLES = 1000
DEFAULT_SEED = 0
DEFAULT_TOLERANCE = 1e-10

#: The paper's Table 1, gafro (CGA) against Pinocchio on the Franka Emika Panda.
PAPER_PANDA = {"rnea": 1.28015e-14, "aba": 6.73759e-14}

FOOT_BAND = 0.02
"""Leaf links within this height (m) of the lowest at the neutral configuration are feet."""

CONSTRAINED = "constrained"
"""The key of the constrained-dynamics check (``constrained_row``)."""

__all__ = ["CONSTRAINED", "DEFAULT_SAMPLES", "DEFAULT_SEED", "DEFAULT_TOLERANCE",
           "FOOT_BAND", "PAPER_PANDA", "PAPER_SAMPLES", "held_feet", "leaf_links",
           "validate_robot", "versions"]


def versions() -> dict[str, str]:
    """Versions of cgadyn, Pinocchio, numpy and numba."""
    import numba
    import pinocchio

    import cgadyn

    return {"cgadyn": cgadyn.__version__, "pinocchio": pinocchio.__version__,
            "numpy": np.__version__, "numba": numba.__version__}


def leaf_links(model) -> list[str]:
    """One link per leaf joint (a joint without children): the last link, in URDF order,
    rigidly attached to its body. Falls back to the model's last link."""
    link_joint = np.asarray(model.link_joint)
    leaves = []
    for j in range(model.njoints):
        attached = np.flatnonzero(link_joint == j)
        if not model.children(j) and attached.size:
            leaves.append(model.link_names[attached[-1]])
    return leaves or [model.link_names[-1]]


def held_feet(model) -> list:
    """Point constraints holding a floating robot's feet where they stand at its neutral
    configuration: the leaf links (``leaf_links``) within ``FOOT_BAND`` of the lowest."""
    import cgadyn

    q0 = cgadyn.neutral(model)
    T = cgadyn.link_placements(model, q0)
    leaves = [model.link_names.index(name) for name in leaf_links(model)]
    low = min(T[i][2, 3] for i in leaves)
    return [cgadyn.Constraint(model, "point", i, q=q0) for i in leaves
            if T[i][2, 3] <= low + FOOT_BAND]


def _constraints_of(robot, model) -> tuple[list, str, float]:
    """The constraints the constrained check holds, what they are, and the proximal damping
    it solves with: an MJCF model's point and frame equalities (``mujoco_constraints``;
    damped, as a planar loop closed by a point has a row no joint moves; joint and tendon
    couplings, the model's own rows of the contact step (K45), left out), else a floating
    robot's feet where their rows are independent (solo's two-joint legs cannot hold a
    point foot at every state: no check there)."""
    import cgadyn

    if mujoco_oracle.applies(robot):
        mj = mujoco_oracle.compiled(robot)
        held = cgadyn.mujoco_constraints(model, mj, skip_couplings=True) if mj.neq else []
        if held:
            return held, "MJCF equalities", 1e-10
    if model.floating_base:
        feet = held_feet(model)
        J = cgadyn.constraint_jacobian(model, cgadyn.neutral(model), feet)
        if np.linalg.matrix_rank(J) == J.shape[0]:  # else legs of too few joints (solo's
            return feet, "feet held", 0.0  # two) cannot hold their feet at every state
    return [], "", 0.0


def constrained_row(robot, model, pm, states, limit: np.ndarray) -> tuple[str, dict] | None:
    """q̈ and the constraint forces of ``constrained_dynamics`` against Pinocchio's
    ``constraintDynamics`` (``ProximalSettings(1e-12, damping, 1 or 100)``), with the
    constraints of ``_constraints_of``; None where the robot has none (a fixed base without
    equalities). Returns the check's label and row. With damping (a set that may be
    redundant, such as a planar loop closed by a point) the forces are compared as the
    joint torques ``Jᵀλ`` they exert: the split of λ along a row no joint moves is
    Pinocchio's rounding of that row divided by the damping, where cgadyn's row is 0."""
    import pinocchio as pin

    import cgadyn

    constraints, what, damping = _constraints_of(robot, model)
    if not constraints:
        return None
    label = f"constrained, {what} (q̈, {'Jᵀλ' if damping else 'λ'})"
    models, datas = oracle.pin_constraints(model, pm, constraints)
    data = pm.createData()
    pin.initConstraintDynamics(pm, data, models, datas)
    prox = pin.ProximalSettings(1e-12, damping, 100 if damping else 1)
    qp = oracle.pin_configuration(model, states.q)
    J = cgadyn.constraint_jacobian(model, states.q, constraints)

    def force(i, lam):  # λ, or Jᵀλ where the set may be redundant (the docstring)
        return J[i].T @ lam if damping else lam

    ref = []
    for i in range(states.q.shape[0]):
        a = pin.constraintDynamics(pm, data, qp[i], states.v[i], states.tau[i], models, datas,
                                   prox)
        ref.append(np.concatenate([a, force(i, data.lambda_c)]))
    ref = np.array(ref)
    try:
        qdd, forces = cgadyn.constrained_dynamics(model, states.q, states.v, states.tau,
                                                  constraints, damping=damping)
        mine = [np.concatenate([a, force(i, f)]) for i, (a, f) in enumerate(zip(qdd, forces,
                                                                               strict=True))]
        return label, _row(np.array(mine), ref, limit)
    except ValueError as exc:
        return label, _failed(exc, undefined=not np.all(np.isfinite(ref)))


def _one_by_one(mine, model, states, leaves) -> np.ndarray:
    """``mine`` (a check's cgadyn side) on each sample as a batch of one, stacked: a batch of
    one runs through the algorithm's one-sample entry, so that a cold ``validate`` compiles
    each core with its small C entry and not with a parallel batch entry as well (nor the
    lane groups of the derivatives and M⁻¹: ``validation/results/startup.md``). The
    numbers are the cores' own, which the batches repeat to rounding
    (``tests/test_dynamics.py``, ``tests/test_derivatives.py``)."""
    return np.concatenate([
        mine(model, oracle.States(*(x[i:i + 1] for x in (states.q, states.v, states.a,
                                                           states.tau))), leaves)
        for i in range(states.q.shape[0])])


def _row(mine: np.ndarray, reference: np.ndarray, limit: np.ndarray) -> dict:
    samples = reference.shape[0]
    diff = np.abs(np.asarray(mine) - reference).reshape(samples, -1)
    rel = oracle.relative_error(mine, reference)
    worst = int(np.argmax(np.where(np.isnan(rel), np.inf, rel / limit)))
    ok = bool(np.all(np.isfinite(rel)) and np.all(rel <= limit))
    return {"mean_norm": float(np.linalg.norm(diff, axis=1).mean()),
            "max_abs": float(diff.max()), "max_rel": float(rel.max()),
            "tolerance": float(limit.max()), "worst_sample": worst, "pass": ok}


def _failed(exc: Exception, undefined: bool) -> dict:
    """cgadyn refused (a singular mass matrix, an overflow): a failure, unless the quantity
    is undefined, Pinocchio's result being NaN or infinite too; then "not applicable"."""
    row = {"mean_norm": math.nan, "max_abs": math.nan, "max_rel": math.nan,
           "tolerance": math.nan, "worst_sample": -1, "pass": undefined, "error": str(exc)}
    if undefined:
        row["not_applicable"] = "undefined: Pinocchio's result is not finite either"
    return row


def validate_robot(robot, samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED,
                   tolerance: float = DEFAULT_TOLERANCE, floating_base=None) -> dict:
    """Compare every check with Pinocchio on ``samples`` random states of a robot.

    ``robot``: a name from ``cgadyn.robots()``, a URDF path or URDF text. Returns a
    JSON-ready dict: ``robot, dof, nq, nv, base, samples, seed, tolerance, versions,
    relative_error, scaled, jacobian_links, checks`` (per key of ``oracle.CHECKS``, and
    for an MJCF model with MuJoCo installed of ``mujoco_oracle.CHECKS`` too:
    ``mean_norm, max_abs, max_rel, tolerance, worst_sample, pass``; ``error``, why cgadyn
    refused, and ``not_applicable`` where the quantity is undefined, Pinocchio's result
    being NaN or infinite too, as for forward dynamics with a massless movable subtree),
    ``conditioning`` (the largest cond(M)), ``pass`` and ``seconds``.
    """
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise ValueError(f"tolerance must be a positive finite number, got {tolerance}")
    start = time.perf_counter()
    model, pm = oracle.models(robot, floating_base)
    if model.nv == 0:
        raise ValueError(f"{model.name!r} has no degree of freedom: nothing to validate")
    states = oracle.sample(model, samples, seed)
    leaves = leaf_links(model)
    frames = oracle._frames(pm, leaves)
    data = pm.createData()
    qp = oracle.pin_configuration(model, states.q)
    cond = np.concatenate([oracle.conditioning(model, states.q[i:i + 1])
                           for i in range(samples)])
    rows = {}
    for check in oracle.CHECKS:
        limit = tolerance * (cond if check.scaled else np.ones(samples))
        if check.theirs is None:
            ref = np.stack([oracle.fk_reference(pm, data, qp[i], model.link_names)
                            for i in range(samples)])
        else:
            ref = np.stack([check.theirs(pm, data, qp[i], states, i, frames)
                            for i in range(samples)])
        try:
            rows[check.key] = _row(_one_by_one(check.mine, model, states, leaves), ref, limit)
        except ValueError as exc:  # reported in the table with its reason, not hidden
            rows[check.key] = _failed(exc, undefined=not np.all(np.isfinite(ref)))
    constrained = constrained_row(robot, model, pm, states, tolerance * cond)
    labels = {}
    if constrained is not None:
        labels[CONSTRAINED], rows[CONSTRAINED] = constrained
    if mujoco_oracle.applies(robot):  # an MJCF model: MuJoCo, the second engine, too
        mj = mujoco_oracle.compiled(robot)
        refs = mujoco_oracle.references(model, mj, states)
        for key, mine in mujoco_oracle.mine(model, mj, states).items():
            limit = tolerance * (cond if key in mujoco_oracle.SCALED else np.ones(samples))
            rows[key] = _row(mine, refs[key], limit)
    return {"robot": model.name, "dof": model.nv, "nq": model.nq, "nv": model.nv,
            "base": "free flyer" if model.floating_base else "fixed",
            "samples": samples, "seed": seed, "tolerance": tolerance, "versions": versions(),
            "relative_error": oracle.RELATIVE, "scaled": oracle.SCALED,
            "jacobian_links": leaves, "conditioning": float(cond.max()), "checks": rows,
            "labels": labels,
            "pass": all(row["pass"] for row in rows.values()),
            "seconds": round(time.perf_counter() - start, 3)}
