"""Rotor inertia (``Model.armature``) in every algorithm of the dynamics, against Pinocchio's
``model.armature`` (added to M's diagonal by its crba, rnea, aba, computeMinverse and both
derivatives): single calls and batches (the batches of more than eight samples take the
lane paths of minverse and the derivatives), a fixed arm and a floating quadruped, with
armature on every coordinate, the free flyer's included."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import cgadyn
from cgadyn import oracle
from cgadyn.multibody.registry import example_robot_data_dir

ERD = example_robot_data_dir()
ROBOTS = {"panda": ("panda_description/urdf/panda.urdf", False),
          "anymal": ("anymal_b_simple_description/robots/anymal.urdf", True)}
SAMPLES = 11  # one group of eight lanes and three samples one at a time


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def robot(request):
    path, floating = ROBOTS[request.param]
    path = str(ERD / path)
    pm = (pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating
          else pin.buildModelFromUrdf(path))
    rng = np.random.default_rng(7)
    pm.armature = rng.uniform(0.05, 2.0, pm.nv)  # as large as the links' own inertias
    model = cgadyn.from_pinocchio(pm)
    states = oracle.sample(model, SAMPLES, 3)
    return model, pm, pm.createData(), states


def _pin(pm, d, model, states, f):
    return np.stack([f(pm, d, oracle.pin_configuration(model, states.q[i]), i)
                     for i in range(SAMPLES)])


def test_armature_is_read_from_pinocchio(robot):
    model, pm, _, _ = robot
    assert np.array_equal(model.armature, pm.armature)
    assert np.any(model.armature > 0.5)


@pytest.mark.parametrize("batch", [False, True])
def test_armature_in_every_algorithm(robot, batch):
    model, pm, d, s = robot

    def mine(f):
        return f(s) if batch else np.stack([f(oracle.States(s.q[i], s.v[i], s.a[i], s.tau[i]))
                                            for i in range(SAMPLES)])

    sym = oracle.symmetric
    cond = np.linalg.cond(cgadyn.crba(model, s.q))
    checks = {
        "rnea": (mine(lambda x: cgadyn.rnea(model, x.q, x.v, x.a)),
                 _pin(pm, d, model, s, lambda pm, d, qp, i: pin.rnea(pm, d, qp, s.v[i],
                                                                     s.a[i]).copy()), 1.0),
        "crba": (mine(lambda x: cgadyn.crba(model, x.q)),
                 _pin(pm, d, model, s, lambda pm, d, qp, i: sym(pin.crba(pm, d, qp))), 1.0),
        "aba": (mine(lambda x: cgadyn.aba(model, x.q, x.v, x.tau)),
                _pin(pm, d, model, s, lambda pm, d, qp, i: pin.aba(pm, d, qp, s.v[i],
                                                                   s.tau[i]).copy()), cond),
        "minverse": (mine(lambda x: cgadyn.minverse(model, x.q)),
                     _pin(pm, d, model, s, lambda pm, d, qp, i: sym(
                         pin.computeMinverse(pm, d, qp))), cond),
        "rnea_derivatives": (
            mine(lambda x: np.stack(cgadyn.rnea_derivatives(model, x.q, x.v, x.a), -3)),
            _pin(pm, d, model, s, lambda pm, d, qp, i: np.stack([
                sym(y) if k == 2 else y.copy() for k, y in enumerate(
                    pin.computeRNEADerivatives(pm, d, qp, s.v[i], s.a[i]))])), 1.0),
        "aba_derivatives": (
            mine(lambda x: np.stack(cgadyn.aba_derivatives(model, x.q, x.v, x.tau), -3)),
            _pin(pm, d, model, s, lambda pm, d, qp, i: np.stack([
                sym(y) if k == 2 else y.copy() for k, y in enumerate(
                    pin.computeABADerivatives(pm, d, qp, s.v[i], s.tau[i]))])), cond),
    }
    for key, (got, ref, scale) in checks.items():
        rel = oracle.relative_error(got, ref)
        assert np.all(rel <= 1e-10 * scale), (key, float((rel / scale).max()))


def test_armature_adds_to_the_mass_matrix_diagonal_only(robot):
    import dataclasses

    model, _, _, s = robot
    bare = dataclasses.replace(model, armature=np.zeros(model.nv))
    diff = cgadyn.crba(model, s.q[0]) - cgadyn.crba(bare, s.q[0])
    assert np.allclose(diff, np.diag(model.armature), rtol=0.0, atol=1e-12)
    tau = cgadyn.rnea(model, s.q[0], s.v[0], s.a[0]) - cgadyn.rnea(bare, s.q[0], s.v[0], s.a[0])
    assert np.allclose(tau, model.armature * s.a[0], rtol=0.0, atol=1e-10)
