"""``cgadyn.constraints`` checked by physics (docs/constraints.md): the constraint holds
(J q̈ + γ = 0, C6), the equations of motion hold (M q̈ + h = τ + Jᵀ λ), an impact obeys
its law (J v⁺ = -e J v⁻, C9) and never adds kinetic energy at e = 0, point rows are the
motion of a conformal point, redundant sets are solved by proximal iterations (C8) and
conflicting ones named, a closed four-bar linkage keeps its loop for 10 s, and bad inputs
are named."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest
from constraint_cases import FEET, four_bar, loop_error, random_case, random_constraints
from hypothesis import given, settings
from hypothesis import strategies as st
from joint_cases import random_model

import cgadyn
from cgadyn.algebra.multivector import Multivector
from cgadyn.cga.basis import NULL
from cgadyn.cga.objects import Point


def solo(q_seed: int = 0):
    model = cgadyn.load("solo12")
    rng = np.random.default_rng(q_seed)
    q = cgadyn.random_configuration(model, rng)
    return model, q, rng.normal(size=model.nv), rng.normal(size=model.nv)


CASES = [(seed, floating) for seed in range(4) for floating in (False, True)]


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31), st.booleans())
def test_constrained_dynamics_identities(seed, floating):
    """Random trees with random point and frame constraints, loops included."""
    model, _, q, v, tau, cs = random_case(seed, floating)
    qdd, lam = cgadyn.constrained_dynamics(model, q, v, tau, cs)
    J = cgadyn.constraint_jacobian(model, q, cs)
    gamma = cgadyn.constraint_drift(model, q, v, cs)
    scale = max(1.0, np.abs(J @ qdd).max(), np.abs(gamma).max())
    assert np.abs(J @ qdd + gamma).max() <= 1e-9 * scale  # C6
    M, h = cgadyn.crba(model, q), cgadyn.nonlinear_effects(model, q, v)
    lhs, rhs = M @ qdd + h, tau + J.T @ lam
    assert np.abs(lhs - rhs).max() <= 1e-9 * max(1.0, np.abs(rhs).max())


def _recursion_case(name: str, rng):
    """Models on which C12 takes each of its paths: a free root with rotor inertia (its six
    S_k, not C12'), a fixed base, joints of several coordinates, solo12 (C12')."""
    if name == "spherical":
        return cgadyn.from_pinocchio(random_model("tree", [
            (0, pin.JointModelSpherical()), (1, pin.JointModelSpherical()),
            (2, pin.JointModelRY()), (1, pin.JointModelPZ()), (4, pin.JointModelSpherical()),
            (5, pin.JointModelRUBZ())], 2))
    if name == "solo12":
        return cgadyn.load("solo12")
    model = random_case(int(rng.integers(2**31)), name != "fixed")[0]
    if name == "floating, armature":
        model = dataclasses.replace(model, armature=rng.uniform(0.05, 1.0, model.nv))
    return model


@pytest.mark.parametrize("name", ["floating, armature", "fixed", "spherical", "solo12"])
def test_delassus_recursion_is_j_minv_jt(name):
    """C12 (C12' at a free root without rotor inertia) equals J M⁻¹ Jᵀ formed from
    cgadyn's own J and M⁻¹, loops between links included; constrained dynamics through
    C13 satisfies M q̈ + h = τ + Jᵀ λ on the same models."""
    rng = np.random.default_rng(7)
    model = _recursion_case(name, rng)
    solved = 0
    for _ in range(6):
        q = cgadyn.random_configuration(model, rng)
        cs = random_constraints(model, rng, model.nv - 1)
        J = cgadyn.constraint_jacobian(model, q, cs)
        expected = J @ cgadyn.minverse(model, q) @ J.T
        G = cgadyn.delassus(model, q, cs)
        assert np.abs(G - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())
        assert np.array_equal(G, G.T)
        if np.linalg.cond(G) > 1e6:  # a redundant draw: G is checked, the dynamics not
            continue
        v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
        qdd, lam = cgadyn.constrained_dynamics(model, q, v, tau, cs)
        lhs = cgadyn.crba(model, q) @ qdd + cgadyn.nonlinear_effects(model, q, v)
        rhs = tau + J.T @ lam
        assert np.abs(lhs - rhs).max() <= 1e-8 * max(1.0, np.abs(rhs).max())
        solved += 1
    assert solved > 0


@pytest.mark.parametrize("seed, floating", CASES)
@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_impulse_law_and_energy(seed, floating, e):
    """Loops included: J v⁺ = -e J v⁻ (C9); at e = 0 the kinetic energy never grows."""
    model, _, q, v, _, cs = random_case(seed, floating)
    v_after, impulses = cgadyn.impulse_dynamics(model, q, v, cs, restitution=e)
    J = cgadyn.constraint_jacobian(model, q, cs)
    assert np.abs(J @ v_after + e * (J @ v)).max() <= 1e-9 * max(1.0, np.abs(J @ v).max())
    M = cgadyn.crba(model, q)
    np.testing.assert_allclose(M @ (v_after - v), J.T @ impulses, rtol=0,
                               atol=1e-9 * max(1.0, np.abs(impulses).max()))
    if e == 0.0:
        assert v_after @ M @ v_after <= v @ M @ v * (1 + 1e-12)


def test_point_rows_are_the_motion_of_a_conformal_point():
    """C1: the rows of a world-aligned point held to the world are the Euclidean part of
    ``∂X/∂q = S^w_k × X`` of the conformal point the link carries
    (``tasks.object_jacobian``)."""
    model, q, _, _ = solo()
    x = np.array([0.01, -0.02, 0.03])
    P = np.eye(4)
    P[:3, 3] = x
    J = cgadyn.constraint_jacobian(model, q, [cgadyn.Constraint(model, "point", "FL_FOOT", P)])
    X, dX = cgadyn.object_jacobian(model, q, "FL_FOOT", Point(x))
    rows = NULL.coeffs(Multivector(X.mv.algebra, dX.T), ["e1", "e2", "e3"]).T
    np.testing.assert_allclose(J, rows, rtol=0, atol=1e-12)


def test_solo12_feet_forces_carry_its_weight():
    """Held by its four feet: the feet's forces are Newton's law of the whole robot,
    ``Σ f = m (c̈ - g)``, with no torque at the joints (it sags); with the torques of contact
    inverse dynamics for q̈ = 0 (C10) it stands still and the vertical forces sum to its
    weight."""
    model = cgadyn.load("solo12")
    q = cgadyn.neutral(model)
    q[2] = 0.3
    q[7:] = np.tile([0.0, 0.8, -1.6], 4)
    cs = [cgadyn.Constraint(model, "point", foot, q=q) for foot in FEET]
    zero = np.zeros(model.nv)
    mass, g = cgadyn.total_mass(model), np.array([0.0, 0.0, -9.81])
    qdd, forces = cgadyn.constrained_dynamics(model, q, zero, zero, cs)
    com_acceleration = cgadyn.center_of_mass(model, q, zero, qdd)[2]
    np.testing.assert_allclose(forces.reshape(4, 3).sum(axis=0), mass * (com_acceleration - g),
                               rtol=1e-12, atol=1e-12)
    tau, _ = cgadyn.contact_inverse_dynamics(model, q, zero, zero, cs)
    qdd, forces = cgadyn.constrained_dynamics(model, q, zero, tau, cs)
    np.testing.assert_allclose(qdd, 0.0, atol=1e-10)
    assert forces.reshape(4, 3)[:, 2].sum() == pytest.approx(9.81 * mass, rel=1e-12)
    np.testing.assert_allclose(forces.reshape(4, 3)[:, :2].sum(axis=0), 0.0, atol=1e-10)


def test_redundant_set_takes_proximal_iterations():
    """The four feet held twice: without damping the singular Delassus matrix is an error
    naming the first repeated constraint; with damping the proximal iterations converge to
    forces shared equally between the copies (the least-norm ones), with J q̈ + γ = 0."""
    model, q, v, tau = solo()
    cs = [cgadyn.Constraint(model, "point", f, q=q) for f in FEET] * 2
    with pytest.raises(ValueError, match=r"constraint 4 \(point FL_FOOT on the world\).*"
                                         r"damping > 0"):
        cgadyn.constrained_dynamics(model, q, v, tau, cs)
    qdd, lam, info = cgadyn.constrained_dynamics(model, q, v, tau, cs, damping=1e-6,
                                                 return_info=True)
    assert info.converged and 1 < info.iterations < 100 and info.residual <= 1e-10
    single, lam1 = cgadyn.constrained_dynamics(model, q, v, tau, cs[:4])
    np.testing.assert_allclose(qdd, single, rtol=0, atol=1e-8 * np.abs(single).max())
    np.testing.assert_allclose(lam[:12], lam[12:], rtol=0, atol=1e-8 * np.abs(lam).max())
    np.testing.assert_allclose(lam[:12] + lam[12:], lam1, rtol=0,
                               atol=1e-8 * np.abs(lam1).max())


def test_conflicting_set_is_named():
    """One foot held at two different places, with a corrector pulling to both: no q̈
    satisfies both, and the error names a constraint rather than returning NaN."""
    model, q, v, tau = solo()
    here = cgadyn.Constraint(model, "point", "FL_FOOT", q=q, corrector=(10.0, 0.0))
    there = np.eye(4)
    there[:3, 3] = here.other_placement[:3, 3] + [0.0, 0.0, 0.1]
    away = cgadyn.Constraint(model, "point", "FL_FOOT", other_placement=there,
                             corrector=(10.0, 0.0))
    with pytest.raises(ValueError, match=r"no solution.*constraint \d \(point FL_FOOT"):
        cgadyn.constrained_dynamics(model, q, v, tau, [here, away], damping=1e-6)
    with pytest.raises(ValueError, match=r"constraint 1 \(point FL_FOOT on the world\)"):
        cgadyn.constrained_dynamics(model, q, v, tau, [here, away])


def test_a_link_fixed_to_the_world_is_named():
    model = cgadyn.load("panda")
    c = cgadyn.Constraint(model, "point", "panda_link0")
    with pytest.raises(ValueError, match=r"constraint 0 \(point panda_link0 on the world\) "
                                         r"moves with no joint"):
        cgadyn.constrained_dynamics(model, np.zeros(9), np.zeros(9), np.zeros(9), [c])


def test_batches_match_single_calls():
    """A batch runs the compiled calls once for all samples (their batch entries, rounded
    alike to 1e-12) and gives each sample's results."""
    model, q, v, tau = solo()
    rng = np.random.default_rng(5)
    Q = np.array([cgadyn.random_configuration(model, rng) for _ in range(3)])
    V, T = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    cs = [cgadyn.Constraint(model, "point", f, frame="local", q=q) for f in FEET]
    batch = {"dynamics": cgadyn.constrained_dynamics(model, Q, V, T, cs),
             "G": cgadyn.delassus(model, Q, cs, damping=0.1),
             "J": cgadyn.constraint_jacobian(model, Q, cs),
             "gamma": cgadyn.constraint_drift(model, Q, V, cs),
             "impulse": cgadyn.impulse_dynamics(model, Q, V, cs),
             "inverse": cgadyn.contact_inverse_dynamics(model, Q, V, T, cs)}
    assert batch["dynamics"][0].shape == (3, model.nv) and batch["G"].shape == (3, 12, 12)
    qdd, lam, infos = cgadyn.constrained_dynamics(model, Q, V, T, cs, return_info=True)
    assert len(infos) == 3 and all(i.converged for i in infos)
    for i in range(3):
        single = {"dynamics": cgadyn.constrained_dynamics(model, Q[i], V[i], T[i], cs),
                  "G": cgadyn.delassus(model, Q[i], cs, damping=0.1),
                  "J": cgadyn.constraint_jacobian(model, Q[i], cs),
                  "gamma": cgadyn.constraint_drift(model, Q[i], V[i], cs),
                  "impulse": cgadyn.impulse_dynamics(model, Q[i], V[i], cs),
                  "inverse": cgadyn.contact_inverse_dynamics(model, Q[i], V[i], T[i], cs)}
        for key, one in single.items():
            pairs = zip(batch[key], one, strict=True) if isinstance(one, tuple) else \
                [(batch[key], one)]
            for mine, s in pairs:
                np.testing.assert_allclose(mine[i], s, rtol=0,
                                           atol=1e-12 * max(1, np.abs(s).max()), err_msg=key)
    np.testing.assert_allclose(batch["G"][0] - 0.1 * np.eye(12),
                               cgadyn.delassus(model, Q[0], cs), rtol=0,
                               atol=1e-12 * np.abs(batch["G"][0]).max())


def test_contact_inverse_dynamics_by_substitution():
    """C10: the torques of a constrained motion give it back in forward dynamics, with no
    force on the free flyer and forces that balance it."""
    model, q, v, tau = solo()
    tau[:6] = 0.0
    cs = [cgadyn.Constraint(model, "point", f, q=q) for f in FEET]
    qdd, _ = cgadyn.constrained_dynamics(model, q, v, tau, cs)
    tau2, lam2 = cgadyn.contact_inverse_dynamics(model, q, v, qdd, cs)
    assert np.all(tau2[:6] == 0.0)
    again, lam3 = cgadyn.constrained_dynamics(model, q, v, tau2, cs)
    np.testing.assert_allclose(again, qdd, rtol=0, atol=1e-9 * np.abs(qdd).max())
    np.testing.assert_allclose(lam3, lam2, rtol=0, atol=1e-9 * np.abs(lam2).max())
    one = [cgadyn.Constraint(model, "point", "FL_FOOT", q=q)]  # 3 rows cannot hold 6
    with pytest.raises(ValueError, match="cannot balance the unactuated"):
        cgadyn.contact_inverse_dynamics(model, q, v, qdd, one)


def test_four_bar_keeps_its_loop_for_ten_seconds():
    """A closed four-bar linkage (planar: the loop's out-of-plane row is zero, so the set is
    redundant and solved by proximal iterations) integrated for 10 s by RK4 with dt = 5 ms
    over ``constrained_dynamics`` with a Baumgarte corrector: the loop stays closed to 1e-8
    and the energy (gravity, no torque) is kept; both are printed."""
    model, loop, q, v = four_bar()
    dt, steps = 5e-3, 2000

    def acceleration(x, y):
        return cgadyn.constrained_dynamics(model, x, y, np.zeros(3), [loop], damping=1e-10)[0]

    e0 = cgadyn.energy(model, q, v).sum()
    worst_loop = worst_energy = 0.0
    for _ in range(steps):
        k1 = (v, acceleration(q, v))
        k2 = (v + dt / 2 * k1[1], acceleration(q + dt / 2 * k1[0], v + dt / 2 * k1[1]))
        k3 = (v + dt / 2 * k2[1], acceleration(q + dt / 2 * k2[0], v + dt / 2 * k2[1]))
        k4 = (v + dt * k3[1], acceleration(q + dt * k3[0], v + dt * k3[1]))
        q = q + dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v = v + dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        worst_loop = max(worst_loop, np.abs(loop_error(model, loop, q)).max())
        worst_energy = max(worst_energy, abs(cgadyn.energy(model, q, v).sum() - e0))
    print(f"\nfour-bar, 10 s, RK4 dt 5 ms, corrector {loop.corrector}: loop error "
          f"{worst_loop:.3g} m, energy drift max |E - E0| / |E0| = {worst_energy / abs(e0):.3g}")
    assert worst_loop < 1e-8
    assert worst_energy < 1e-6 * abs(e0)


@pytest.mark.parametrize("kwargs, message", [
    ({"kind": "line"}, r"kind must be 'point' \(3 rows.*got 'line'"),
    ({"link": "no_such_link"}, r"no link 'no_such_link' in 'solo12'; links: base_link"),
    ({"placement": np.eye(3)}, r"placement must be a 4x4 homogeneous matrix or a Motor, got "
                               r"an array of shape \(3, 3\)"),
    ({"placement": 2 * np.eye(4)}, r"placement must be a rigid 4x4"),
    ({"frame": "world"}, r"frame must be 'local' or 'local_world_aligned'.*got 'world'"),
    ({"corrector": (1.0, -1.0)}, r"corrector Kd must be a finite number >= 0, got -1.0"),
    ({"corrector": 3.0}, r"corrector must be a pair \(Kp, Kd\)"),
    ({"other": "FL_FOOT"}, r"link and other are both 'FL_FOOT'"),
])
def test_bad_constraints_are_named(kwargs, message):
    model = cgadyn.load("solo12")
    args = {"kind": "point", "link": "FL_FOOT"} | kwargs
    with pytest.raises(ValueError, match=message):
        cgadyn.Constraint(model, **args)


def test_bad_calls_are_named():
    model, q, v, tau = solo()
    c = cgadyn.Constraint(model, "point", "FL_FOOT")
    with pytest.raises(ValueError, match=r"constraints\[1\] must be a cgadyn.Constraint"):
        cgadyn.constraint_jacobian(model, q, [c, "FL_FOOT"])
    with pytest.raises(ValueError, match="made for the model 'panda'"):
        cgadyn.constraint_jacobian(model, q, [cgadyn.Constraint(cgadyn.load("panda"), "point",
                                                                "panda_hand")])
    with pytest.raises(ValueError, match=r"q must have shape \(19,\)"):
        cgadyn.delassus(model, q[:5], [c])
    with pytest.raises(ValueError, match="damping must be a finite number >= 0"):
        cgadyn.delassus(model, q, [c], damping=-1.0)
    with pytest.raises(ValueError, match="iterations must be an integer >= 1"):
        cgadyn.constrained_dynamics(model, q, v, tau, [c], damping=1e-8, iterations=0)
    with pytest.raises(ValueError, match=r"restitution must be a number in \[0, 1\]"):
        cgadyn.impulse_dynamics(model, q, v, [c], restitution=1.5)
    with pytest.raises(ValueError, match="batches of the same size"):
        cgadyn.constrained_dynamics(model, np.stack([q, q]), v, tau, [c])
    with pytest.raises(ValueError, match=r"v contains NaN|NaN"):
        cgadyn.constrained_dynamics(model, q, np.full(model.nv, np.nan), tau, [c])
