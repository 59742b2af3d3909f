"""``cgadyn.constraints`` against Pinocchio 4.1 (docs/constraints.md): q̈ and forces
(``constraintDynamics``, ``ProximalSettings(1e-12, 1e-12, 0, 1)``), J
(``getConstraintsJacobian``), G (``computeDelassusMatrix`` for constraints in the local frame
anchored to the world, where it computes J M⁻¹ Jᵀ; J M⁻¹ Jᵀ from Pinocchio's J and
``computeMinverse`` for all), post-impact velocities and impulses
(``impulseDynamics``), each to 1e-9 relative (``oracle.relative_error``), on solo12 with its
four feet, talos_reduced with both soles and random trees with random point and frame
constraints in both frames, with and without a free flyer. Run with ``-s`` to see the
largest errors."""

from __future__ import annotations

import numpy as np
import pytest
from constraint_cases import FEET, SOLES, pinocchio_results, random_case

import cgadyn
from cgadyn import oracle

TOL = 1e-9


def errors(model, pm, q, v, tau, cs, restitution=0.0, impulses=True) -> dict:
    """The largest relative error of each quantity over the states (q, v, tau: (B, ...))."""
    out: dict = {}
    for x, y, t in zip(q, v, tau, strict=True):
        ref = pinocchio_results(model, pm, x, y, t, cs, restitution)
        qdd, forces = cgadyn.constrained_dynamics(model, x, y, t, cs)
        v_after, imp = cgadyn.impulse_dynamics(model, x, y, cs, restitution)
        mine = {"qdd": qdd, "forces": forces, "J": cgadyn.constraint_jacobian(model, x, cs),
                "JMinvJt": cgadyn.delassus(model, x, cs), "v_after": v_after,
                "impulses": imp}
        if all(c.frame == "local" and c.other is None for c in cs):
            mine["G"] = mine["JMinvJt"]
        if not impulses:
            del mine["v_after"], mine["impulses"]
        for key, value in mine.items():
            e = float(oracle.relative_error(value[None], ref[key][None])[0])
            out[key] = max(out.get(key, 0.0), e)
    return out


def states(model, seed: int, samples: int = 3):
    rng = np.random.default_rng(seed)
    q = np.array([cgadyn.random_configuration(model, rng) for _ in range(samples)])
    return q, rng.normal(size=(samples, model.nv)), rng.normal(size=(samples, model.nv))


@pytest.mark.parametrize("frame", ["local", "local_world_aligned"])
def test_solo12_four_feet(frame):
    model, pm = oracle.models("solo12")
    q, v, tau = states(model, 1)
    cs = [cgadyn.Constraint(model, "point", foot, frame=frame, corrector=(10.0, 2.0),
                            q=q[0]) for foot in FEET]
    err = errors(model, pm, q, v, tau, cs, restitution=0.3)
    print(f"\nsolo12, four point feet, {frame}: {err}")
    assert max(err.values()) < TOL, err


@pytest.mark.parametrize("frame", ["local", "local_world_aligned"])
def test_talos_reduced_two_soles(frame):
    model, pm = oracle.models("talos_reduced")
    q, v, tau = states(model, 2, samples=2)
    cs = [cgadyn.Constraint(model, "frame", sole, frame=frame, corrector=(5.0, 1.0),
                            q=q[0]) for sole in SOLES]
    err = errors(model, pm, q, v, tau, cs)
    print(f"\ntalos_reduced, two frame soles, {frame}: {err}")
    assert max(err.values()) < TOL, err


@pytest.mark.parametrize("floating", [False, True])
@pytest.mark.parametrize("seed", range(6))
def test_random_trees(seed, floating):
    """Random trees of 8 joints with random point and frame constraints (world anchors and
    loops, both frames, random correctors). Pinocchio's ``impulseDynamics`` takes the
    pre-impact velocity of the first end alone, and its ``computeDelassusMatrix`` differs
    from J M⁻¹ Jᵀ of its own J for a constraint between two links: both are compared where
    every constraint is anchored to the world; loops are checked by J M⁻¹ Jᵀ and by the
    impact law itself (test_constraints.py)."""
    model, pm, q, v, tau, cs = random_case(seed, floating)
    world = all(c.other is None for c in cs)
    err = errors(model, pm, q[None], v[None], tau[None], cs, 0.4, impulses=world)
    print(f"\nrandom tree {seed}, floating {floating}, {[c.name for c in cs]}: {err}")
    assert max(err.values()) < TOL, err


@pytest.mark.parametrize("floating", [False, True])
@pytest.mark.parametrize("seed", range(3))
def test_random_trees_with_frames(seed, floating):
    """Trees of 14 joints with frame constraints (welds to the world and between links) in
    both frames, and a few points."""
    model, pm, q, v, tau, cs = random_case(100 + seed, floating, joints=14, frames=0.8)
    assert any(c.kind == "frame" for c in cs)
    world = all(c.other is None for c in cs)
    err = errors(model, pm, q[None], v[None], tau[None], cs, 0.4, impulses=world)
    print(f"\nrandom tree {100 + seed}, floating {floating}, "
          f"{[(c.name, c.frame) for c in cs]}: {err}")
    assert max(err.values()) < TOL, err


def test_anymal_four_feet():
    model, pm = oracle.models("anymal")
    q, v, tau = states(model, 4, samples=2)
    cs = [cgadyn.Constraint(model, "point", foot, frame=frame, corrector=(3.0, 1.0), q=q[0])
          for foot, frame in zip(("LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT"),
                                 ("local", "local_world_aligned") * 2, strict=True)]
    err = errors(model, pm, q, v, tau, cs, restitution=0.2)
    print(f"\nanymal, four point feet: {err}")
    assert max(err.values()) < TOL, err


@pytest.mark.parametrize("frame", ["local", "local_world_aligned"])
def test_talos_hands_welded_to_each_other(frame):
    """A humanoid standing on both soles with its hands welded to each other (a loop through
    both arms and the torso)."""
    model, pm = oracle.models("talos_reduced")
    q, v, tau = states(model, 5, samples=2)
    cs = [cgadyn.Constraint(model, "frame", sole, frame=frame, q=q[0]) for sole in SOLES]
    grip = np.eye(4)
    grip[:3, 3] = [0.0, 0.0, -0.1]
    cs.append(cgadyn.Constraint(model, "frame", "gripper_left_base_link", grip,
                                "gripper_right_base_link", grip, frame, corrector=(4.0, 2.0)))
    err = errors(model, pm, q, v, tau, cs, impulses=False)
    print(f"\ntalos_reduced, soles and hands welded, {frame}: {err}")
    assert max(err.values()) < TOL, err


def test_pinocchio_delassus_is_in_the_local_frame():
    """Pinocchio 4.1's ``computeDelassusMatrix`` gives ``J M⁻¹ Jᵀ`` with the rows of the
    constraint's local frame whatever its ``reference_frame``: for a world-aligned constraint
    it equals cgadyn's ``delassus`` of the same constraint in ``"local"`` and not the one
    in ``"local_world_aligned"`` (rows rotated by the frame's rotation)."""
    model, pm = oracle.models("solo12")
    q = cgadyn.random_configuration(model, np.random.default_rng(3))
    aligned = [cgadyn.Constraint(model, "point", "FL_FOOT", q=q)]
    local = [cgadyn.Constraint(model, "point", "FL_FOOT", frame="local", q=q)]
    ref = pinocchio_results(model, pm, q, np.zeros(model.nv), np.zeros(model.nv), aligned)
    np.testing.assert_allclose(cgadyn.delassus(model, q, local), ref["G"], rtol=0,
                               atol=1e-12 * np.abs(ref["G"]).max())
    assert np.abs(cgadyn.delassus(model, q, aligned) - ref["G"]).max() > 1e-3
    np.testing.assert_allclose(cgadyn.delassus(model, q, aligned), ref["JMinvJt"], rtol=0,
                               atol=1e-12 * np.abs(ref["G"]).max())
