"""The frictional contact solvers (``cgadyn.solve_contacts``, ADMM and PGS; docs/contact.md,
K11-K20) against Pinocchio 4.1's ``ADMMConstraintSolver`` and ``PGSConstraintSolver`` run to
1e-12 on the same ``G``, ``g``, ``μ``, and against the Coulomb law in closed form.

solo12 on its four feet has a regular ``G``: the forces are unique and agree to 1e-6
relative. talos_reduced on its soles' eight corners beside a box on its four corners has a
singular ``G`` (rank 18 of 36): the forces are not unique, so the test compares what is: the
velocities ``σ`` of the sticking soles (zero) and the robot's generalized impulse ``Jᵀλ``;
for the sliding box, whose normal forces are indeterminate and whose friction torque, hence
``σ_T``, depends on them (Pinocchio's own ADMM and PGS differ there), its normal velocities
(zero) and the parts of ``Jᵀλ`` they fix (vertical, roll, pitch). Run with ``-s`` to see
iterations and residuals."""

from __future__ import annotations

import numpy as np
import pytest
from contact_solver_cases import pinocchio_solve, solo12, talos_and_box

import cgadyn

TOL = 1e-12
"""Both libraries' absolute tolerance on each residual."""


def residuals(lam, sigma, mu) -> tuple[float, float, float]:
    """The NCP's residuals (K19) from numpy: distance of λ to the cones, of σ̃ = σ + Γ(σ) to
    the dual cones, max |λ_i · σ̃_i|."""
    primal = dual = comp = 0.0
    for i, m in enumerate(mu):
        lt, ln = lam[3 * i:3 * i + 2], lam[3 * i + 2]
        st = sigma[3 * i:3 * i + 2]
        sn = sigma[3 * i + 2] + m * np.linalg.norm(st)
        primal = max(primal, np.linalg.norm(lt) - m * ln, -ln)
        dual = max(dual, m * np.linalg.norm(st) - sn, -sn)
        comp = max(comp, abs(lt @ st + ln * sn))
    return primal, dual, comp


def solve(G, g, mu, solver, **kw):
    return cgadyn.solve_contacts(G, g, mu, solver=solver, tolerance=TOL,
                                 max_iterations=100000, **kw)


def relative(a, b) -> float:
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_solo12_four_feet_agrees_with_pinocchio(solver):
    _, _, _, _, G, g, mu = solo12()
    assert np.linalg.matrix_rank(G) == 12
    lam, info = solve(G, g, mu, solver)
    ref, ref_sigma, r = pinocchio_solve(G, g, mu, solver)
    sigma = G @ lam + g
    err = relative(lam, ref)
    print(f"\nsolo12 {solver}: {info}; Pinocchio {r.iterations} iterations, primal "
          f"{r.primal_feasibility:.2g}, dual {r.dual_feasibility:.2g}, complementarity "
          f"{r.complementarity:.2g}; λ relative difference {err:.2g}")
    assert info.converged and r.converged
    assert err < 1e-6
    assert np.abs(sigma - ref_sigma).max() < 1e-8
    assert max(residuals(lam, sigma, mu)) < 1e-8
    # the three regimes: sticking (σ = 0), lifting off (λ = 0), sliding (on the cone)
    assert np.abs(sigma[0:3]).max() < 1e-9 and lam[2] > 0
    assert np.abs(lam[3:6]).max() == 0.0 and sigma[5] > 0
    assert abs(np.linalg.norm(lam[6:8]) - mu[2] * lam[8]) < 1e-9 and \
        np.linalg.norm(sigma[6:8]) > 1e-3


@pytest.mark.slow
@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_talos_soles_and_box_corners_agree_where_unique(solver):
    parts, G, g, mu = talos_and_box()
    assert np.linalg.matrix_rank(G) < G.shape[0]
    lam, info = solve(G, g, mu, solver)
    ref, ref_sigma, r = pinocchio_solve(G, g, mu, solver)
    sigma = G @ lam + g
    assert info.converged and r.converged
    mine, theirs = residuals(lam, sigma, mu), residuals(ref, ref_sigma, mu)
    print(f"\ntalos + box {solver}: {info}; residuals {mine}; Pinocchio {r.iterations} "
          f"iterations, residuals {theirs}")
    assert max(mine) < 1e-8 and max(theirs) < 1e-8
    (_, _, _, Jt, talos), (_, _, _, Jb, box) = parts
    # talos sticks on its eight corners: σ = 0, Jᵀλ unique
    assert np.abs(sigma[talos]).max() < 1e-9 and np.abs(ref_sigma[talos]).max() < 1e-9
    err_talos = relative(Jt.T @ lam[talos], Jt.T @ ref[talos])
    # the box slides: its normal velocities are zero, which fixes its vertical, roll and
    # pitch impulses; its σ_T is not unique
    normal = np.arange(box.start + 2, box.stop, 3)
    assert np.abs(sigma[normal]).max() < 1e-9
    err_box = relative((Jb.T @ lam[box])[2:5], (Jb.T @ ref[box])[2:5])
    spread = np.abs(sigma[box] - ref_sigma[box]).max()
    print(f"  Jᵀλ relative difference: talos {err_talos:.2g}, box (z, roll, pitch) "
          f"{err_box:.2g}; the box's σ_T differs by {spread:.2g} (not unique)")
    assert err_talos < 1e-6 and err_box < 1e-6


def test_pgs_and_admm_agree_where_unique():
    _, _, _, _, G, g, mu = solo12()
    a, ia = solve(G, g, mu, "admm")
    p, ip = solve(G, g, mu, "pgs")
    assert ia.converged and ip.converged
    assert relative(a, p) < 1e-6


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_compliance_agrees_with_pinocchio(solver):
    _, _, _, _, G, g, mu = solo12()
    R = np.linspace(0.01, 0.1, 12)
    lam, info = solve(G, g, mu, solver, compliance=R)
    ref, ref_sigma, r = pinocchio_solve(G, g, mu, solver, compliance=R)
    assert info.converged and relative(lam, ref) < 1e-6
    assert max(residuals(lam, G @ lam + R * lam + g, mu)) < 1e-8


def spd(rng, n=3) -> np.ndarray:
    A = rng.normal(size=(n, n))
    return A @ A.T + 0.5 * np.eye(n)


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_one_contact_sticks_inside_the_cone(solver):
    rng = np.random.default_rng(3)
    G, mu = spd(rng), 0.8
    inside = np.array([0.3, -0.2, 1.0])  # ‖λ_T‖ = 0.36 < μ λ_N
    g = -G @ inside  # pressing in, a tangential part the friction holds
    lam, info = solve(G, g, mu, solver)
    assert info.converged
    np.testing.assert_allclose(lam, inside, atol=1e-9)
    np.testing.assert_allclose(G @ lam + g, 0.0, atol=1e-9)


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_one_contact_slides_on_the_cone_against_its_velocity(solver):
    rng = np.random.default_rng(4)
    G, mu = spd(rng), 0.3
    g = np.array([2.0, -1.5, -1.0])  # pressing in, sliding hard
    lam, info = solve(G, g, mu, solver)
    sigma = G @ lam + g
    assert info.converged
    assert lam[2] > 0 and abs(sigma[2]) < 1e-9  # no penetration
    assert abs(np.linalg.norm(lam[:2]) - mu * lam[2]) < 1e-9  # on the cone's boundary
    direction = -sigma[:2] / np.linalg.norm(sigma[:2])  # maximal dissipation
    np.testing.assert_allclose(lam[:2], mu * lam[2] * direction, atol=1e-9)


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_a_separating_contact_has_no_force(solver):
    rng = np.random.default_rng(5)
    G = spd(rng)
    lam, info = solve(G, np.array([0.4, -0.7, 0.2]), 0.5, solver)
    assert info.converged and info.iterations == 0
    assert np.all(lam == 0.0)


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_batch_equals_single(solver):
    rng = np.random.default_rng(6)
    B, nc = 5, 3
    G = np.array([spd(rng, 3 * nc) for _ in range(B)])
    g = rng.normal(size=(B, 3 * nc)) - np.tile([0, 0, 1.0], nc)
    mu = rng.uniform(0.1, 1.0, size=(B, nc))
    lam, info = cgadyn.solve_contacts(G, g, mu, solver=solver)
    assert lam.shape == (B, 3 * nc) and info.iterations.shape == (B,)
    for b in range(B):
        one, i1 = cgadyn.solve_contacts(G[b], g[b], mu[b], solver=solver)
        np.testing.assert_array_equal(lam[b], one)
        assert info.iterations[b] == i1.iterations and info.converged[b] == i1.converged


def test_a_warm_start_at_the_solution_stops_at_once():
    _, _, _, _, G, g, mu = solo12()
    lam, _ = solve(G, g, mu, "admm")
    again, info = cgadyn.solve_contacts(G, g, mu, tolerance=1e-8, warm_start=lam)
    assert info.iterations <= 1 and relative(again, lam) < 1e-8


def test_contact_problem_gives_the_velocity_after_the_step():
    model, _, cs, J, G, g, mu = solo12()
    lam, _ = solve(G, g, mu, "admm")
    q = cgadyn.neutral(model)
    rng = np.random.default_rng(0)
    v = rng.normal(size=model.nv)
    tau = rng.normal(size=model.nv)
    G, g = cgadyn.contact_problem(model, q, v, tau, 0.01, cs)
    M = cgadyn.crba(model, q)
    v_free = v + 0.01 * np.linalg.solve(M, tau - cgadyn.rnea(model, q, v, np.zeros(model.nv)))
    v_after = v_free + np.linalg.solve(M, J.T @ lam)  # K20
    np.testing.assert_allclose(J @ v_after, G @ lam + g, atol=1e-10)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"G": np.eye(4)}, "m = 3"),
    ({"G": np.eye(6) + np.triu(np.ones((6, 6)), 1)}, "symmetric"),
    ({"g": np.zeros(5)}, "g must be"),
    ({"mu": -0.1}, "mu must be >= 0"),
    ({"mu": np.ones(3)}, "mu must be"),
    ({"compliance": -1.0}, "compliance must be >= 0"),
    ({"solver": "newton"}, "solver must be"),
    ({"g": [0, 0, np.nan, 0, 0, 0]}, "NaN"),
    ({"warm_start": np.zeros(4)}, "warm_start must be"),
    ({"max_iterations": 1.5}, "max_iterations"),
    ({"G": -np.eye(6)}, "not positive semi-definite"),
])
def test_bad_input_is_named(kwargs, message):
    args = {"G": np.eye(6), "g": np.zeros(6), "mu": 0.5} | kwargs
    with pytest.raises(ValueError, match=message):
        cgadyn.solve_contacts(**args)


def test_contact_problem_refuses_frame_constraints():
    model, _, cs, *_ = solo12()
    weld = cgadyn.Constraint(model, "frame", "FL_FOOT")
    with pytest.raises(ValueError, match="point constraint in 'local_world_aligned'"):
        cgadyn.contact_problem(model, cgadyn.neutral(model), np.zeros(model.nv),
                               np.zeros(model.nv), 0.01, [weld])
    with pytest.raises(ValueError, match="dt must be"):
        cgadyn.contact_problem(model, cgadyn.neutral(model), np.zeros(model.nv),
                               np.zeros(model.nv), 0.0, cs)


def test_pgs_reads_no_row_past_a_small_problem():
    """PGS's scratch rows hold ``max(m, 6)`` floats: on one contact (m = 3) it must keep
    ``σ`` over the problem's rows alone. Run as plain Python (``NUMBA_DISABLE_JIT``, bounds
    checked, in a child process): reading past ``G``'s rows raises ``IndexError`` there."""
    import os
    import subprocess
    import sys

    code = ("import numpy as np, cgadyn\n"
            "G = np.array([[2.0, 0.1, 0.2], [0.1, 1.5, 0.1], [0.2, 0.1, 3.0]])\n"
            "lam, info = cgadyn.solve_contacts(G, -G @ np.array([0.3, -0.2, 1.0]), "
            "np.array([0.8]), solver='pgs')\n"
            "assert info.converged and np.allclose(lam, [0.3, -0.2, 1.0], atol=1e-9), lam\n")
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
