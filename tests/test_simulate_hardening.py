"""``simulate`` on the physics a user relies on: controllers never push on a free base,
long runs keep only the states asked for and refuse what cannot fit, and divergence is
called divergence (with the step, the quantity and the likely cause), not a model fault."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn.sim import PD, GravityCompensation, SimulationDiverged, simulate

G = 9.81


@pytest.fixture(scope="module")
def solo():
    return cgadyn.load("solo12")


@pytest.fixture(scope="module")
def panda():
    return cgadyn.load("panda")


def _lifted(model, height=1.0):
    q = cgadyn.neutral(model)
    q[2] = height
    return q


@pytest.mark.parametrize("controller", [PD(kp=5.0, kd=0.2), GravityCompensation(),
                                        PD(kp=1.0, kd=0.05, gravity_compensation=False)])
def test_controllers_never_hold_a_free_base_in_the_air(solo, controller):
    """Whatever the joints do, no external force acts: the centre of mass falls freely,
    ½ g t², and the base with it."""
    q0 = _lifted(solo)
    traj = simulate(solo, q0, np.zeros(solo.nv), 1e-3, 300, controller=controller)
    c0, c1 = (cgadyn.center_of_mass(solo, q) for q in (traj.q[0], traj.q[-1]))
    fall = 0.5 * G * 0.3 ** 2
    assert abs((c0[2] - c1[2]) - fall) < 1e-7  # RK4's error, not a force
    assert np.allclose(c1[:2], c0[:2], atol=1e-7)
    assert traj.q[0, 2] - traj.q[-1, 2] > 0.4  # the base falls too


def test_gravity_compensation_acts_on_the_joints_only(solo):
    """Gravity compensation adds g(q) on the joints: the base's entries are left alone, so
    the joints' accelerations are those of ABA with the joint part of g(q) as torque."""
    q0 = _lifted(solo)
    v0 = np.zeros(solo.nv)
    traj = simulate(solo, q0, v0, 1e-3, 1, controller=GravityCompensation())
    tau = cgadyn.gravity_torques(solo, q0)
    tau[:6] = 0.0
    np.testing.assert_allclose(traj.a[0], cgadyn.aba(solo, q0, v0, tau), atol=1e-12)
    assert solo.actuated.tolist() == [False] * 6 + [True] * 12


@pytest.mark.parametrize("kp", [5.0, np.full(12, 5.0), np.r_[np.zeros(6), np.full(12, 5.0)]])
def test_pd_gains_per_actuated_coordinate(solo, kp):
    q0 = _lifted(solo)
    ref = simulate(solo, q0, np.zeros(solo.nv), 1e-3, 20, controller=PD(kp=5.0, kd=0.2))
    traj = simulate(solo, q0, np.zeros(solo.nv), 1e-3, 20, controller=PD(kp=kp, kd=0.2))
    np.testing.assert_array_equal(traj.q, ref.q)


@pytest.mark.parametrize("kp, match", [
    (np.full(18, 5.0), "acts on the free flyer's coordinates"),
    (np.ones(5), r"one per actuated coordinate \(12,\) or one per velocity coordinate"),
])
def test_pd_gains_refused(solo, kp, match):
    with pytest.raises(ValueError, match=match):
        simulate(solo, _lifted(solo), np.zeros(solo.nv), 1e-3, 2, controller=PD(kp, 1.0))


def test_record_every_keeps_every_kth_state(panda):
    q0 = cgadyn.random_configuration(panda, 1)
    full = simulate(panda, q0, np.zeros(9), 1e-3, 25)
    some = simulate(panda, q0, np.zeros(9), 1e-3, 25, record_every=10)
    rows = [0, 10, 20, 25]
    np.testing.assert_array_equal(some.q, full.q[rows])
    np.testing.assert_array_equal(some.v, full.v[rows])
    np.testing.assert_array_equal(some.a, full.a[rows])
    np.testing.assert_allclose(some.t, full.t[rows], rtol=1e-15)
    np.testing.assert_allclose(some.energy, full.energy[rows], rtol=1e-14)
    last = simulate(panda, np.stack([q0, q0]), np.zeros(9), 1e-3, 25, final_only=True)
    assert last.q.shape == (2, 1, 9) and last.t.tolist() == [0.025]
    np.testing.assert_array_equal(last.q[1, 0], full.q[-1])


def test_a_stop_keeps_the_last_state_reached(panda):
    """With every k-th state kept, a rollout that stops keeps the last state it reached."""
    tau = np.zeros((40, 9))
    tau[15:] = 1e9
    with pytest.warns(SimulationDiverged, match="diverged"):
        some = simulate(panda, cgadyn.neutral(panda), np.zeros(9), 1e-3, 40, tau=tau,
                        record_every=10)
    with pytest.warns(SimulationDiverged):
        full = simulate(panda, cgadyn.neutral(panda), np.zeros(9), 1e-3, 40, tau=tau)
    k = some.completed
    assert 15 <= k < 40 and full.completed == k
    np.testing.assert_array_equal(some.q[-1], full.q[-1])
    assert some.t[-1] == pytest.approx(k * 1e-3)


def test_what_cannot_fit_is_refused_before_it_starts():
    talos = cgadyn.load("talos")
    q0 = np.tile(cgadyn.neutral(talos), (6000, 1))
    with pytest.raises(ValueError, match=r"(?s)need .*[KMGTP]iB.*more than the .* available.*"
                                         r"record_every=\d+.*final_only=True"):
        simulate(talos, q0, np.zeros(talos.nv), 1e-3, 10 ** 8)


@pytest.mark.parametrize("kwargs", [
    dict(dt=1.0),
    dict(controller=PD(kp=1e12, kd=0.0, q_ref=np.zeros(9))),
    dict(tau=np.full((200, 9), 1e10)),
    dict(v0=np.full(9, 1e5)),
])
def test_divergence_is_named_as_such(panda, kwargs):
    args = dict(q0=cgadyn.neutral(panda) + 0.3, v0=np.zeros(9), dt=1e-3, steps=200) | kwargs
    with pytest.warns(SimulationDiverged) as record:
        traj = simulate(panda, **args)
    message = str(record[0].message)
    assert traj.diverged and "the state diverged" in message and "dt" in message
    assert "singular" not in message and "step" in message


def test_divergence_in_a_batch_names_the_rollout(solo):
    q0 = np.tile(_lifted(solo), (3, 1))
    v0 = np.zeros((3, solo.nv))
    v0[2, 8] = 1e5
    with pytest.warns(SimulationDiverged, match=r"rollout 2 stopped after 0 of 10 steps"):
        traj = simulate(solo, q0, v0, 1e-3, 10)
    assert traj.diverged.tolist() == [False, False, True]


def test_free_fall_is_not_divergence(solo):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = simulate(solo, _lifted(solo, 1e4), np.zeros(solo.nv), 0.05, 400,
                        integrator="semi_implicit_euler", final_only=True)
    assert not traj.diverged and traj.v[-1, 2] < -150.0
    assert np.isfinite(traj.q).all()


@pytest.mark.parametrize("kwargs, match", [
    (dict(q0=np.zeros((0, 9))), "q0 holds no rollout"),
    (dict(tau=np.zeros((5, 9), dtype=complex)), "tau has complex values"),
    (dict(record_every=0), "record_every must be a positive integer"),
    (dict(record_every=2.5), "record_every must be a positive integer"),
    (dict(final_only="yes"), "final_only must be True or False"),
])
def test_bad_arguments(panda, kwargs, match):
    args = dict(q0=cgadyn.neutral(panda), v0=np.zeros(9), dt=1e-3, steps=5) | kwargs
    with pytest.raises(ValueError, match=match):
        simulate(panda, **args)
