"""PGS's polish on the active set (``contact/polish.py``, docs/contact.md K18a): on problems
whose solution is built to be known (contacts that stick, slide and separate, a joint
limit's row that holds and one that does not, a friction loss at its bound), the guess read
off the solution is the one built, Newton's steps on it converge quadratically to the
solution from other forces of that guess, and ``pgs_solve`` returns that solution, the
sliding contact's friction direction included, with K19's residuals below its
tolerance."""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn
from cgadyn.contact import polish

MU = np.array([0.6, 0.5, 0.7])
BOUNDS = np.array([[0.0, np.inf], [0.0, np.inf], [-0.3, 0.3]])
"""Two joint limits' rows (``λ >= 0``) and a friction loss's (``|λ| <= 0.3``)."""


def built(seed: int):
    """``(G, g, λ*, σ*)``: ``G`` symmetric positive definite and diagonally dominant,
    ``λ*`` and ``σ* = G λ* + g`` meeting K13 and K26 block by block: contact 0 sticks
    (``σ = 0``, ``λ`` inside its cone), contact 1 slides (``σ_N = 0``, ``λ_T = -μ λ_N σ_T /
    ‖σ_T‖``), contact 2 is apart (``λ = 0``, ``σ_N > 0``); the first limit holds (``λ > 0``,
    ``σ = 0``), the second does not (``λ = 0``, ``σ > 0``); the friction loss sits at its
    upper bound (``σ < 0``)."""
    rng = np.random.default_rng(seed)
    m = 12
    A = rng.normal(size=(m, m))
    G = 0.2 * (A @ A.T) / m + np.diag(rng.uniform(1.0, 2.0, m))
    lam = np.zeros(m)
    sigma = np.zeros(m)
    lam[0:3] = [0.1, -0.2, 1.0]  # ‖λ_T‖ = 0.22 < 0.6
    slide = np.array([0.8, -0.6])  # the sliding velocity σ_T, unit direction
    lam[5] = 1.5
    lam[3:5] = -MU[1] * lam[5] * slide
    sigma[3:5] = 0.4 * slide
    sigma[6:9] = [0.3, -0.1, 0.5]  # apart: any tangential velocity, opening
    lam[9], sigma[10] = 0.7, 0.2  # the limit that holds, the one that does not
    lam[11], sigma[11] = 0.3, -0.25  # the friction loss at its upper bound
    return G, sigma - G @ lam, lam, sigma


@pytest.mark.parametrize("seed", range(5))
def test_the_guess_read_off_the_solution_is_the_one_built(seed):
    G, g, lam, sigma = built(seed)
    rows, slides = np.zeros(12), np.zeros(12)
    k, sliding = polish.active_set(MU, BOUNDS, lam, rows, slides)
    # contact 0's three rows, contact 1's (sliding), the holding limit's row
    assert sliding == 1
    np.testing.assert_array_equal(rows[:k], [0, 1, 2, 3, 4, 5, 9])
    np.testing.assert_array_equal(slides[:k], [0, 0, 0, 1, 1, 1, 0])


@pytest.mark.parametrize("seed", range(5))
def test_newton_on_the_guess_lands_on_the_solution(seed):
    """From other forces of the same guess (the friction turned by 0.05 rad), Newton's
    steps converge to the solution, quadratically: each step's residual at most a constant
    times the square of the one before, down to rounding."""
    G, g, lam, sigma = built(seed)
    R = np.zeros(12)
    rows, slides = np.zeros(12), np.zeros(12)
    k, _ = polish.active_set(MU, BOUNDS, lam, rows, slides)
    rng = np.random.default_rng(100 + seed)
    x = lam.copy()
    x[[0, 1, 2, 5, 9]] += rng.uniform(-0.05, 0.05, 5)
    c, s_ = np.cos(0.05), np.sin(0.05)
    x[3:5] = [[c, -s_], [s_, c]] @ x[3:5]
    errors = []
    for _ in range(6):
        sig = G @ x + g
        errors.append(polish.unsettled(MU, x, sig, rows, slides, k))
        assert polish.newton_step(G, R, MU, x, sig, rows, slides, k, np.empty((12, 12)),
                                  np.empty(12)) >= 0.0
    np.testing.assert_allclose(x, lam, atol=1e-12)
    e = [v for v in errors if v > 1e-13]
    assert len(e) >= 3 and all(b <= 100.0 * a * a for a, b in zip(e, e[1:], strict=False))


@pytest.mark.parametrize("seed", range(5))
def test_pgs_returns_the_built_solution(seed):
    G, g, lam, sigma = built(seed)
    out, info = cgadyn.solve_contacts(G, g, MU, solver="pgs", bounds=BOUNDS, tolerance=1e-12)
    assert info.converged
    assert max(info.primal, info.dual, info.complementarity) <= 1e-12
    np.testing.assert_allclose(out, lam, atol=1e-10)


def test_a_singular_guess_is_refused_and_leaves_the_forces():
    """Two contacts on one point (``G`` of rank 3 in 6 rows): both stick, the guess's system
    is singular, and the step says so without touching ``λ``."""
    rng = np.random.default_rng(7)
    A = rng.normal(size=(3, 3))
    block = A @ A.T + np.eye(3)
    G = np.block([[block, block], [block, block]])
    lam = np.array([0.1, 0.0, 1.0, -0.1, 0.0, 1.0])
    mu = np.array([0.5, 0.5])
    rows, slides = np.zeros(6), np.zeros(6)
    k, sliding = polish.active_set(mu, np.zeros((0, 2)), lam, rows, slides)
    assert (k, sliding) == (6, 0)
    before = lam.copy()
    assert polish.newton_step(G, np.zeros(6), mu, lam, G @ lam + np.ones(6), rows, slides, k,
                              np.empty((6, 6)), np.empty(6)) == -1.0
    np.testing.assert_array_equal(lam, before)
