"""Identities that hold on floating-base robots without any oracle: what issue 11 asks to show.

- ``aba(rnea(a)) == a`` and ``M(q) q̈ = τ - h(q, v)``;
- the power balance ``d(T + U)/dt = v · τ`` along a short trajectory integrated on the
  configuration manifold (the work done by τ equals the change of the total energy);
- ``difference(q, integrate(q, v)) == v``;
- central differences of the link placements through ``integrate`` against the local
  Jacobians, the six base columns included.
"""

from __future__ import annotations

import numpy as np
import pytest

import cgadyn

ROBOTS = ["solo12", "anymal"]


@pytest.fixture(scope="module", params=ROBOTS)
def model(request):
    m = cgadyn.load(request.param)
    assert m.floating_base
    return m


def state(model, seed):
    rng = np.random.default_rng(seed)
    q = cgadyn.random_configuration(model, rng)
    return q, rng.normal(size=model.nv), rng.normal(size=model.nv)


def rel(x, y) -> float:
    return float(np.abs(np.asarray(x) - y).max() / max(np.abs(y).max(), 1e-300))


def test_inverse_and_forward_dynamics_invert_each_other(model):
    for seed in range(3):
        q, v, a = state(model, seed)
        tau = cgadyn.rnea(model, q, v, a)
        assert rel(cgadyn.aba(model, q, v, tau), a) < 1e-10
        qdd = cgadyn.aba(model, q, v, tau)
        M, h = cgadyn.crba(model, q), cgadyn.nonlinear_effects(model, q, v)
        assert rel(M @ qdd, tau - h) < 1e-10


def test_difference_inverts_integrate(model):
    for seed in range(3):
        q, v, _ = state(model, seed)
        assert rel(cgadyn.difference(model, q, cgadyn.integrate(model, q, v)), v) < 1e-12


def energy_and_work(model, q, v, tau, dt, seconds):
    """RK4 on the manifold for ``seconds`` with constant generalised forces ``tau``: the change
    of T + U, and the work ∫ v · τ dt by Simpson's rule over the steps."""

    def f(q, v):
        return cgadyn.aba(model, q, v, tau)

    energy, power = [cgadyn.energy(model, q, v).sum()], [v @ tau]
    for _ in range(round(seconds / dt)):
        k1v, k1a = v, f(q, v)
        q2, v2 = cgadyn.integrate(model, q, 0.5 * dt * k1v), v + 0.5 * dt * k1a
        k2v, k2a = v2, f(q2, v2)
        q3, v3 = cgadyn.integrate(model, q, 0.5 * dt * k2v), v + 0.5 * dt * k2a
        k3v, k3a = v3, f(q3, v3)
        q4, v4 = cgadyn.integrate(model, q, dt * k3v), v + dt * k3a
        k4v, k4a = v4, f(q4, v4)
        q = cgadyn.integrate(model, q, dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v))
        v = v + dt / 6 * (k1a + 2 * k2a + 2 * k3a + k4a)
        energy.append(cgadyn.energy(model, q, v).sum())
        power.append(v @ tau)
    p = np.array(power)
    work = dt / 3 * (p[0] + p[-1] + 4 * p[1:-1:2].sum() + 2 * p[2:-1:2].sum())
    return energy[-1] - energy[0], work


def test_power_balance_along_a_trajectory(model):
    """d(T + U)/dt = v · τ: over 0.1 s the change of energy equals the work of τ (base wrench
    included), up to the integrator's error, which falls as the step shrinks. (RK4 that sums
    body-frame rates taken at different points of the group is of second order on a floating
    base, hence the factor of at least 3 per halving rather than 15.)"""
    q, v, _ = state(model, 7)
    tau = 0.1 * np.random.default_rng(8).normal(size=model.nv)
    change, work = energy_and_work(model, q, 0.5 * v, tau, 1e-3, 0.1)
    change2, work2 = energy_and_work(model, q, 0.5 * v, tau, 5e-4, 0.1)
    assert abs(work) > 1e-2  # the torques do work: the identity is not 0 = 0
    assert abs(change - work) < 1e-5 * abs(work)
    assert abs(change2 - work2) < abs(change - work) / 3


def test_placement_differences_match_local_jacobians(model):
    """(T(q ⊕ εe_i) - T(q ⊖ εe_i)) / 2ε = T(q) [J_i]^ with J_i the i-th column of the LOCAL
    Jacobian: the linear part in the translation column, the angular part skew."""
    q, _, _ = state(model, 11)
    eps = 1e-6
    T0 = cgadyn.link_placements(model, q)
    names = model.link_names
    for link in (names[0], names[len(names) // 2], names[-1]):
        i = model.link_index(link)
        J = cgadyn.jacobian(model, q, link, frame="local")
        fd = np.empty((6, model.nv))
        for k in range(model.nv):
            e = np.zeros(model.nv)
            e[k] = eps
            dT = (cgadyn.link_placements(model, cgadyn.integrate(model, q, e))[i]
                  - cgadyn.link_placements(model, cgadyn.integrate(model, q, -e))[i]) / (2 * eps)
            hat = np.linalg.solve(T0[i], dT)
            fd[:3, k] = hat[:3, 3]
            fd[3:, k] = hat[2, 1], hat[0, 2], hat[1, 0]
        assert rel(J, fd) < 1e-7, link
        assert np.abs(J[:, :6]).max() > 0.1  # the base columns are there
