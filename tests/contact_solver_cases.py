"""The contact problems of ``tests/test_contact_solver.py``: solo12 on its four feet, and
talos_reduced on the eight corners of its soles beside a free box on its four lower corners;
and Pinocchio 4.1's ADMM and PGS solvers on the same ``G``, ``g``, ``μ``."""

from __future__ import annotations

import numpy as np

import cgadyn
from cgadyn import oracle

FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
SOLES = ("left_sole_link", "right_sole_link")
SOLE = (0.1, 0.05)
"""Half the sides of talos's soles (m): their corners at (±x, ±y, 0) in the sole frame."""
BOX = (0.2, 0.15, 0.1)
"""Half the sides of the box (m)."""
DT = 1e-2


def box_urdf(mass: float = 2.0) -> str:
    """One link with the inertia of a solid box of sides ``2 BOX`` and ``mass``."""
    a, b, c = (2 * x for x in BOX)
    ix, iy, iz = (mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12,
                  mass * (a * a + b * b) / 12)
    return (f'<robot name="box"><link name="box"><inertial><mass value="{mass}"/>'
            f'<inertia ixx="{ix}" ixy="0" ixz="0" iyy="{iy}" iyz="0" izz="{iz}"/>'
            f'</inertial></link></robot>')


def at(x: float, y: float, z: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = x, y, z
    return T


def contacts(model, q, links, corners) -> list:
    """Point contacts in ``local_world_aligned`` frame at ``corners`` of each link, held to
    the world where they stand at ``q``."""
    return [cgadyn.Constraint(model, "point", link, at(*c), q=q) for link in links
            for c in corners]


def state(model, seed: int, speed: float, base):
    """The neutral configuration, a random velocity of size ``speed`` whose base moves at
    ``base`` (its linear velocity, pressing down and sliding), zero torques."""
    rng = np.random.default_rng(seed)
    v = speed * rng.normal(size=model.nv)
    v[:3] = base
    return cgadyn.neutral(model), v, np.zeros(model.nv)


def solo12(seed: int = 0):
    """``(model, pm, constraints, J, G, g, mu)`` of solo12 on its four feet, sliding forwards
    and pressing down: at seed 0 the front left foot sticks, the front right lifts off, the
    hind left slides, the hind right sticks."""
    model, pm = oracle.models("solo12")
    q, v, tau = state(model, seed, 1.0, (0.3, -0.2, -0.05))
    cs = contacts(model, q, FEET, [(0.0, 0.0, 0.0)])
    G, g = cgadyn.contact_problem(model, q, v, tau, DT, cs)
    J = cgadyn.constraint_jacobian(model, q, cs)
    return model, pm, cs, J, G, g, np.array([0.9, 0.2, 0.1, 0.7])


def talos_and_box(seed: int = 1):
    """``(parts, G, g, mu)``: talos_reduced on its soles' eight corners and a box on its four
    lower corners as one problem (G block diagonal); ``parts`` the two robots'
    ``(model, pm, constraints, J, rows)``."""
    parts, Gs, gs = [], [], []
    sole = [(sx * SOLE[0], sy * SOLE[1], 0.0) for sx in (1, -1) for sy in (1, -1)]
    lower = [(sx * BOX[0], sy * BOX[1], -BOX[2]) for sx in (1, -1) for sy in (1, -1)]
    start = 0
    for robot, links, corners, speed, base in (
            ("talos_reduced", SOLES, sole, 0.05, (0.02, 0.01, -0.05)),
            (box_urdf(), ("box",), lower, 0.2, (0.3, 0.2, -0.1))):
        model, pm = oracle.models(robot, floating_base=True)
        q, v, tau = state(model, seed, speed, base)
        cs = contacts(model, q, links, corners)
        G, g = cgadyn.contact_problem(model, q, v, tau, DT, cs)
        J = cgadyn.constraint_jacobian(model, q, cs)
        parts.append((model, pm, cs, J, slice(start, start + G.shape[0])))
        Gs.append(G)
        gs.append(g)
        start += G.shape[0]
    G = np.zeros((start, start))
    for (_, _, _, _, rows), Gi in zip(parts, Gs, strict=True):
        G[rows, rows] = Gi
    mu = np.array([0.8] * 8 + [0.25] * 4)
    return parts, G, np.concatenate(gs), mu


def pinocchio_solve(G, g, mu, solver: str = "admm", compliance=None, tol: float = 1e-12,
                    iterations: int = 100000):
    """Pinocchio 4.1's ``ADMMConstraintSolver`` or ``PGSConstraintSolver`` on a dense
    Delassus operator: ``(λ, σ, result)``. The solvers read from the constraint models only
    their sets (``CoulombFrictionCone`` of each ``PointContactConstraintModel``'s friction),
    so the models are points on the world joint of an empty model; the compliance ``R`` is
    the Delassus operator's (``updateCompliance``: it then solves with ``G + R``)."""
    import pinocchio as pin

    m = pin.Model()
    nc = len(mu)
    models, datas = pin.StdVec_ConstraintModel(), pin.StdVec_ConstraintData()
    for i in range(nc):
        cm = pin.PointContactConstraintModel(m, 0)
        cm.setFriction(float(mu[i]))
        models.append(pin.ConstraintModel(cm))
    for cm in models:
        datas.append(cm.createData())
    D = pin.DelassusOperatorDense(np.array(G))
    if compliance is not None:
        D.updateCompliance(np.asarray(compliance, dtype=float))  # G + R
    if solver == "admm":
        s, r, sol = pin.ADMMSolverSettings(), pin.ADMMSolverResult(), \
            pin.ADMMConstraintSolver(3 * nc)
        s.admm_update_rule = pin.ADMMUpdateRule.SPECTRAL
    else:
        s, r, sol = pin.PGSSolverSettings(), pin.PGSSolverResult(), \
            pin.PGSConstraintSolver(3 * nc)
    s.max_iterations = iterations
    for name in ("absolute_complementarity_tol", "absolute_feasibility_tol",
                 "relative_complementarity_tol", "relative_feasibility_tol"):
        setattr(s, name, tol)
    sol.solve(D, np.array(g), models, datas, s, r)
    lam = np.array(r.retrieveConstraintImpulses())
    R = np.zeros(3 * nc) if compliance is None else np.asarray(compliance, dtype=float)
    return lam, G @ lam + R * lam + g, r
