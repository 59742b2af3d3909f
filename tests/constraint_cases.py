"""Robots with constraints for the tests of ``cgadyn.constraints``: solo12 on its four feet,
talos_reduced on both soles, a closed four-bar linkage, random trees with random point and
frame constraints; and the same constraints in Pinocchio."""

from __future__ import annotations

import numpy as np

import cgadyn
from cgadyn import oracle

FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
SOLES = ("left_sole_link", "right_sole_link")
INERTIAL = ('<inertial><origin xyz="{c}"/><mass value="{m}"/><inertia ixx="{i}" ixy="0" '
            'ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial>')


def rigid(rng) -> np.ndarray:
    """A random rigid 4x4 placement (translation within 0.3 m)."""
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    T = np.eye(4)
    T[:3, :3] = Q * np.sign(np.linalg.det(Q))
    T[:3, 3] = rng.uniform(-0.3, 0.3, 3)
    return T


def random_tree_urdf(rng, n: int) -> str:
    """A random tree of n one-dof joints (revolute, continuous, prismatic) and fixed joints
    between them, random axes, placements and inertias."""
    links = []
    for i in range(n + 1):
        c = " ".join(f"{x:.3f}" for x in rng.uniform(-0.2, 0.2, 3))
        links.append(f'<link name="L{i}">'
                     + INERTIAL.format(c=c, m=f"{rng.uniform(0.5, 2):.3f}",
                                       i=f"{rng.uniform(0.02, 0.1):.3f}") + "</link>")
    joints = []
    for i in range(1, n + 1):
        parent = int(rng.integers(max(0, i - 3), i))
        kind = rng.choice(["revolute", "revolute", "continuous", "prismatic"])
        axis = " ".join(f"{x:.3f}" for x in rng.normal(size=3))
        xyz = " ".join(f"{x:.3f}" for x in rng.uniform(-0.4, 0.4, 3))
        rpy = " ".join(f"{x:.3f}" for x in rng.uniform(-3, 3, 3))
        joints.append(f'<joint name="J{i}" type="{kind}"><parent link="L{parent}"/>'
                      f'<child link="L{i}"/><origin xyz="{xyz}" rpy="{rpy}"/>'
                      f'<axis xyz="{axis}"/><limit lower="-2" upper="2" effort="1" '
                      f'velocity="1"/></joint>')
    return f'<robot name="tree">{"".join(links)}{"".join(joints)}</robot>'


def random_constraints(model, rng, rows: int, frames: float = 0.4) -> list:
    """Random point and frame constraints (a share ``frames`` of frames) in both frames, on
    the world or between links, with random placements and correctors, of at most ``rows``
    rows in all."""
    out, used = [], 0
    movable = [i for i in range(model.nlinks) if model.link_joint[i] >= 0]
    while True:
        kind = "frame" if rng.random() < frames else "point"
        size = 6 if kind == "frame" else 3
        if used + size > rows:
            break
        link = int(rng.choice(movable))
        other = None if rng.random() < 0.5 else int(rng.choice(
            [i for i in range(model.nlinks) if i != link]))
        frame = str(rng.choice(["local", "local_world_aligned"]))
        corrector = (float(rng.uniform(0, 5)), float(rng.uniform(0, 3)))
        out.append(cgadyn.Constraint(
            model, kind, link, rigid(rng), other,
            rigid(rng) if other is not None or rng.random() < 0.5 else None, frame, corrector,
            q=cgadyn.random_configuration(model, rng)))
        used += size
    return out


def pinocchio_results(model, pm, q, v, tau, constraints, restitution=0.0) -> dict:
    """Pinocchio 4.1's results for one state: q̈ and λ (``constraintDynamics`` with
    ``ProximalSettings(1e-12, 1e-12, 0, 1)``), J (``getConstraintsJacobian``), G
    (``computeDelassusMatrix``), J M⁻¹ Jᵀ (from ``computeMinverse``), v⁺ and the impulses
    (``impulseDynamics``)."""
    import pinocchio as pin

    d = pm.createData()
    qp = oracle.pin_configuration(model, q)
    models, datas = oracle.pin_constraints(model, pm, constraints)
    pin.initConstraintDynamics(pm, d, models, datas)
    prox = pin.ProximalSettings(1e-12, 1e-12, 0.0, 1)
    a = pin.constraintDynamics(pm, d, qp, v, tau, models, datas, prox).copy()
    lam = d.lambda_c.copy()
    J = np.array(pin.getConstraintsJacobian(pm, d, models, datas)).reshape(-1, pm.nv)
    G = pin.computeDelassusMatrix(pm, d, qp, models, datas, 0.0).copy()
    Minv = oracle.symmetric(pin.computeMinverse(pm, d, qp))
    v_after = pin.impulseDynamics(pm, d, qp, v, models, datas, restitution, prox).copy()
    impulses = d.impulse_c.copy()
    return {"qdd": a, "forces": lam, "J": J, "G": G, "JMinvJt": J @ Minv @ J.T,
            "v_after": v_after, "impulses": impulses}


def random_case(seed: int, floating: bool, joints: int = 8, frames: float = 0.4):
    """A random tree, constraints on it whose Delassus matrix is well conditioned at a random
    state (cond < 1e6, redrawn until so), and that state: ``(model, pm, q, v, tau, cs)``."""
    rng = np.random.default_rng(seed)
    while True:
        model, pm = oracle.models(random_tree_urdf(rng, joints), floating_base=floating)
        q = cgadyn.random_configuration(model, rng)
        for _ in range(20):
            cs = random_constraints(model, rng, model.nv - 1, frames)
            if cs and np.linalg.cond(cgadyn.delassus(model, q, cs)) < 1e6:
                v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
                return model, pm, q, v, tau, cs


def _rod(name: str, length: float, mass: float = 1.0) -> str:
    i = mass * length * length / 12.0
    return (f'<link name="{name}"><inertial><origin xyz="{length / 2} 0 0"/>'
            f'<mass value="{mass}"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="{i}" iyz="0" '
            f'izz="{i}"/></inertial></link>')


CRANK, COUPLER, ROCKER, GROUND = 0.4, 1.0, 0.8, 1.0
FOUR_BAR = (
    '<robot name="four_bar"><link name="ground"/>' + _rod("crank", CRANK)
    + _rod("coupler", COUPLER) + _rod("rocker", ROCKER)
    + '<joint name="crank_joint" type="continuous"><parent link="ground"/>'
      '<child link="crank"/><axis xyz="0 1 0"/></joint>'
    + f'<joint name="coupler_joint" type="continuous"><parent link="crank"/>'
      f'<child link="coupler"/><origin xyz="{CRANK} 0 0"/><axis xyz="0 1 0"/></joint>'
    + f'<joint name="rocker_joint" type="continuous"><parent link="ground"/>'
      f'<child link="rocker"/><origin xyz="{GROUND} 0 0"/><axis xyz="0 1 0"/></joint>'
      '</robot>')
"""A planar four-bar linkage in the xz plane (joints about y, gravity in the plane) as a tree:
ground-crank-coupler and ground-rocker; the loop is closed by a point constraint."""


def along_x(x: float) -> np.ndarray:
    T = np.eye(4)
    T[0, 3] = x
    return T


def four_bar(corrector=(25.0, 10.0), crank_angle: float = 1.0, crank_speed: float = 2.0):
    """The four-bar's model, its loop constraint (the coupler's end held on the rocker's end),
    and a state on the loop: the crank at ``crank_angle``, turning at ``crank_speed``, the
    other two joints solved for by Gauss-Newton on the loop error."""
    model = cgadyn.load(FOUR_BAR)
    loop = cgadyn.Constraint(model, "point", "coupler", along_x(COUPLER), "rocker",
                             along_x(ROCKER), corrector=corrector)
    q = np.array([crank_angle, -1.0, -2.0])
    for _ in range(30):
        J = cgadyn.constraint_jacobian(model, q, [loop])
        q[1:] -= np.linalg.lstsq(J[:, 1:], loop_error(model, loop, q), rcond=None)[0]
    v = np.array([crank_speed, 0.0, 0.0])
    J = cgadyn.constraint_jacobian(model, q, [loop])
    v[1:] = np.linalg.lstsq(J[:, 1:], -J[:, 0] * crank_speed, rcond=None)[0]
    return model, loop, q, v


def loop_error(model, c, q) -> np.ndarray:
    """The world position of a point constraint's first end minus its second's."""
    T = cgadyn.link_placements(model, q)
    second = c.other_placement if c.other is None else T[c.other] @ c.other_placement
    return (T[c.link] @ c.placement)[:3, 3] - second[:3, 3]
