"""examples/lqr_cart_pole.py: the LQR gain from aba_derivatives balances the cart-pole, and
the linearisation agrees with finite differences of aba."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy")

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "lqr_cart_pole.py"


@pytest.fixture(scope="module")
def example():
    spec = importlib.util.spec_from_file_location("lqr_cart_pole", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def balanced(example):
    return example.run(seconds=6.0, dt=2e-3, perturbation=0.3)


def test_lqr_brings_the_pole_upright(balanced):
    r = balanced
    assert r["open_loop_eigenvalues"].real.max() > 1.0  # upright is unstable
    assert r["closed_loop_eigenvalues"].real.max() < 0.0
    assert r["initial_error"] == pytest.approx(0.3)
    assert r["final_error"] < 1e-2 * r["initial_error"]
    assert np.abs(r["x"][-100:]).max() < 1e-2  # settled, not passing through zero
    assert r["max_abs_u"] <= r["effort_limit"].min()


def test_without_or_with_a_wrong_gain_the_pole_falls(example, balanced):
    """The convergence test above can fail: the same loop with no gain, or with the LQR
    gain's opposite, leaves upright."""
    fallen = example.run(seconds=1.0, dt=2e-3, perturbation=0.3, gain=np.zeros((1, 4)))
    assert np.abs(fallen["x"][:, 1]).max() > 1.0  # the pole tilts past 57°
    wrong = example.run(seconds=2.0, dt=2e-3, perturbation=0.3, gain=-balanced["K"])
    assert wrong["closed_loop_eigenvalues"].real.max() > 0.0
    assert wrong["final_error"] > 10 * wrong["initial_error"]


def test_only_the_cart_is_actuated(example, balanced):
    model = balanced["model"]
    assert list(example.actuated_coordinates(model)) == [model.idx_v[model.joint_index(
        "cart_slide")]]
    assert balanced["B"].shape == (2 * model.nv, 1)


def test_linearisation_matches_finite_differences(example, balanced):
    model, nv, A = balanced["model"], balanced["model"].nv, balanced["A"]
    np.testing.assert_array_equal(A[:nv, :nv], 0.0)
    np.testing.assert_array_equal(A[:nv, nv:], np.eye(nv))
    fq, fv = example.finite_difference_jacobians(model, np.zeros(nv), np.zeros(nv),
                                                 np.zeros(nv))
    np.testing.assert_allclose(A[nv:, :nv], fq, atol=1e-6)
    np.testing.assert_allclose(A[nv:, nv:], fv, atol=1e-6)
    assert balanced["fd_error_equilibrium"] < 1e-6
    assert balanced["fd_error_start"] < 1e-6
    rng = np.random.default_rng(12)
    for _ in range(3):  # away from upright and moving, where dq̈/dv is not zero
        q, v, tau = rng.uniform(-2, 2, nv), rng.normal(size=nv), rng.normal(size=nv)
        assert example.linearisation_error(model, q, v, tau) < 1e-6
