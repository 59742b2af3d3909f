"""Cross-validation of cgadyn against Pinocchio, in the style of Table 1 of the CGA paper.

For ``samples`` random states (``q`` uniform within the joint limits, in ``[-π, π]`` for
continuous joints and infinite limits; ``v``, ``a``, ``tau`` standard normal) every
algorithm runs once in cgadyn, as one batch call, and per sample in Pinocchio; the result
reports per algorithm the mean norm of the difference (the paper's measure), the largest
absolute difference and the largest relative difference, with ``REL_DEFINITION``.

    >>> from cgadyn.validate import validate_robot
    >>> result = validate_robot("panda", samples=100)
    >>> result["pass"], result["algorithms"]["aba"]["mean_norm"]

The paper (section 5.3) averaged over 1000 samples; the default here is 100.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DEFAULT_SAMPLES = 100
PAPER_SAMPLES = 1000
DEFAULT_SEED = 0
DEFAULT_TOLERANCE = 1e-10

#: The paper's Table 1, gafro (CGA) against Pinocchio on the Franka Emika Panda.
PAPER_PANDA = {"rnea": 1.28015e-14, "aba": 6.73759e-14}

REL_DEFINITION = "rel = max|cgadyn - pinocchio| / max(1, max|pinocchio|), per sample"

#: Algorithm keys, in table order, with their labels.
ALGORITHMS = {
    "rnea": "inverse dynamics (rnea)",
    "aba": "forward dynamics (aba)",
    "crba": "mass matrix (crba)",
    "gravity": "gravity torques g(q)",
    "jacobian_world": "Jacobians, world frame",
    "jacobian_local": "Jacobians, local frame",
    "fk": "forward kinematics (all links)",
}

__all__ = [
    "ALGORITHMS",
    "DEFAULT_SAMPLES",
    "DEFAULT_SEED",
    "DEFAULT_TOLERANCE",
    "PAPER_PANDA",
    "PAPER_SAMPLES",
    "REL_DEFINITION",
    "compare",
    "leaf_links",
    "sample_states",
    "validate_robot",
    "versions",
]


@dataclass(frozen=True)
class States:
    """A batch of random states, ``(B, n)`` each."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray


def versions() -> dict[str, str]:
    """Versions of cgadyn, Pinocchio, numpy and numba."""
    import numba
    import pinocchio

    import cgadyn

    return {"cgadyn": cgadyn.__version__, "pinocchio": pinocchio.__version__,
            "numpy": np.__version__, "numba": numba.__version__}


def sample_states(model, samples: int, seed: int) -> States:
    """Random states: ``q`` uniform in the limits (``[-π, π]`` where unbounded or
    continuous), ``v``, ``a``, ``tau`` standard normal."""
    rng = np.random.default_rng(seed)
    lower, upper = np.array(model.lower), np.array(model.upper)
    free = ~(np.isfinite(lower) & np.isfinite(upper))
    free |= np.array([k == "continuous" for k in model.joint_kinds], dtype=bool)
    lower[free], upper[free] = -math.pi, math.pi
    shape = (samples, model.nv)
    q = rng.uniform(lower, upper, size=shape)
    return States(q, rng.standard_normal(shape), rng.standard_normal(shape),
                  rng.standard_normal(shape))


def leaf_links(model) -> list[str]:
    """One link per leaf joint (a joint without children): the last link, in URDF order,
    rigidly attached to its body. Falls back to the model's last link."""
    link_joint = np.asarray(model.link_joint)
    leaves = []
    for j in range(model.nv):
        attached = np.flatnonzero(link_joint == j)
        if not model.children(j) and attached.size:
            leaves.append(model.link_names[attached[-1]])
    return leaves or [model.link_names[-1]]


def compare(mine: np.ndarray, reference: np.ndarray) -> dict:
    """Errors of a batch ``(B, ...)`` against the reference: mean over samples of the norm
    of the difference, max absolute difference, max relative difference (REL_DEFINITION)."""
    samples = reference.shape[0]
    diff = np.abs(np.asarray(mine) - reference).reshape(samples, -1)
    scale = np.maximum(1.0, np.abs(reference).reshape(samples, -1).max(axis=1))
    rel = diff.max(axis=1) / scale
    worst = int(np.argmax(np.where(np.isnan(rel), np.inf, rel)))
    return {"mean_norm": float(np.linalg.norm(diff, axis=1).mean()),
            "max_abs": float(diff.max()), "max_rel": float(rel.max()), "worst_sample": worst}


def _models(robot: str):
    """The cgadyn model and the Pinocchio model of a robot name or URDF path."""
    import pinocchio as pin

    import cgadyn
    from cgadyn.multibody import robot_path

    if robot in cgadyn.robots() or not Path(robot).is_file():
        path = robot_path(robot)  # raises ValueError for an unknown name
        model = cgadyn.load(robot)
    else:
        path = Path(robot)
        model = cgadyn.load(str(path))
    pm = pin.buildModelFromUrdf(str(path))
    if tuple(pm.names[1:]) != tuple(model.joint_names):
        raise RuntimeError(f"joint order differs from Pinocchio's: {list(pm.names[1:])} vs "
                           f"{list(model.joint_names)}")
    return model, pm


def _pin_configuration(pm, q: np.ndarray) -> np.ndarray:
    """Pinocchio's configuration for a batch of cgadyn angles: (cos, sin) where nq = 2."""
    columns = []
    for j in range(q.shape[1]):
        if pm.joints[j + 1].nq == 2:
            columns += [np.cos(q[:, j]), np.sin(q[:, j])]
        else:
            columns.append(q[:, j])
    return np.stack(columns, axis=1)


def _pin_sample(pm, data, qp, v, a, tau, leaf_ids, link_ids) -> dict[str, np.ndarray]:
    """Every algorithm of the table in Pinocchio for one state."""
    import pinocchio as pin

    out = {"rnea": pin.rnea(pm, data, qp, v, a).copy(),
           "aba": pin.aba(pm, data, qp, v, tau).copy()}
    M = pin.crba(pm, data, qp)
    out["crba"] = np.triu(M) + np.triu(M, 1).T
    out["gravity"] = pin.computeGeneralizedGravity(pm, data, qp).copy()
    pin.computeJointJacobians(pm, data, qp)
    pin.updateFramePlacements(pm, data)
    for key, frame in (("jacobian_world", pin.WORLD), ("jacobian_local", pin.LOCAL)):
        out[key] = np.stack([pin.getFrameJacobian(pm, data, f, frame) for f in leaf_ids])
    out["fk"] = np.stack([data.oMf[f].homogeneous for f in link_ids])
    return out


def _pinocchio(pm, states: States, leaves: list[str], links: list[str]) -> dict:
    """Pinocchio's results for the whole batch, stacked as ``(B, ...)``."""
    import pinocchio as pin

    data = pm.createData()
    qp = _pin_configuration(pm, states.q)
    leaf_ids = [pm.getFrameId(name, pin.BODY) for name in leaves]
    link_ids = [pm.getFrameId(name, pin.BODY) for name in links]
    rows = [_pin_sample(pm, data, qp[i], states.v[i], states.a[i], states.tau[i], leaf_ids,
                        link_ids) for i in range(len(qp))]
    return {key: np.stack([row[key] for row in rows]) for key in ALGORITHMS}


def _cgadyn_calls(model, s: States, leaves: list[str]) -> dict:
    """One batch call per algorithm, as zero-argument functions."""
    import cgadyn as cg

    def jac(frame: str):
        return lambda: np.stack([cg.jacobian(model, s.q, link, frame) for link in leaves], 1)

    return {"rnea": lambda: cg.rnea(model, s.q, s.v, s.a),
            "aba": lambda: cg.aba(model, s.q, s.v, s.tau),
            "crba": lambda: cg.crba(model, s.q),
            "gravity": lambda: cg.gravity_torques(model, s.q),
            "jacobian_world": jac("world"),
            "jacobian_local": jac("local"),
            "fk": lambda: cg.link_placements(model, s.q)}


def _check(call, reference: np.ndarray, tolerance: float) -> dict:
    """Run one cgadyn call and compare it; an exception is a failure with its message."""
    try:
        row = compare(call(), reference)
    except Exception as exc:  # reported in the table, not hidden
        return {"mean_norm": math.nan, "max_abs": math.nan, "max_rel": math.nan,
                "worst_sample": -1, "pass": False, "error": f"{type(exc).__name__}: {exc}"}
    row["pass"] = bool(math.isfinite(row["max_rel"]) and row["max_rel"] <= tolerance)
    return row


def validate_robot(name: str, samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED,
                   tolerance: float = DEFAULT_TOLERANCE) -> dict:
    """Compare every algorithm with Pinocchio on ``samples`` random states of a robot.

    ``name``: a name from ``cgadyn.robots()`` or a URDF path. Returns a JSON-ready dict:
    ``robot, dof, samples, seed, tolerance, versions, relative_error, jacobian_links,
    algorithms`` (per key of ``ALGORITHMS``: ``mean_norm, max_abs, max_rel, worst_sample,
    pass`` and ``error`` if cgadyn raised), ``pass`` and ``seconds``.
    Raises ``ValueError`` for an unknown robot.
    """
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    start = time.perf_counter()
    model, pm = _models(name)
    states = sample_states(model, samples, seed)
    leaves = leaf_links(model)
    reference = _pinocchio(pm, states, leaves, list(model.link_names))
    calls = _cgadyn_calls(model, states, leaves)
    rows = {key: _check(calls[key], reference[key], tolerance) for key in ALGORITHMS}
    return {"robot": model.name, "dof": model.nv, "samples": samples, "seed": seed,
            "tolerance": tolerance, "versions": versions(), "relative_error": REL_DEFINITION,
            "jacobian_links": leaves, "algorithms": rows,
            "pass": all(row["pass"] for row in rows.values()),
            "seconds": round(time.perf_counter() - start, 3)}
