"""The configuration manifold and the centroidal quantities against Pinocchio, on a legged
robot with a free flyer and on fixed-base arms."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import cgadyn
from cgadyn.multibody import load_urdf, robot_path
from cgadyn.multibody.registry import example_robot_data_dir

ERD = example_robot_data_dir()
TOL = 1e-12


def _floating(rel: str, name: str):
    path = str(ERD / rel)
    pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    return load_urdf(path, name=name, floating_base=True), pm


def _fixed(name: str):
    return cgadyn.load(name), pin.buildModelFromUrdf(str(robot_path(name)))


MODELS = {
    "anymal": lambda: _floating("anymal_b_simple_description/robots/anymal.urdf", "anymal"),
    "solo12": lambda: _floating("solo_description/robots/solo12.urdf", "solo12"),
    "panda": lambda: _fixed("panda"),
    "ur5": lambda: _fixed("ur5"),
}


@pytest.fixture(scope="module", params=sorted(MODELS))
def robot(request):
    m, pm = MODELS[request.param]()
    return m, pm, pm.createData()


def test_integrate_difference_interpolate_match_pinocchio(robot):
    m, pm, _ = robot
    rng = np.random.default_rng(1)
    for _ in range(3):
        q0, q1 = cgadyn.random_configuration(m, rng), cgadyn.random_configuration(m, rng)
        v = rng.normal(size=m.nv)
        np.testing.assert_allclose(cgadyn.integrate(m, q0, v), pin.integrate(pm, q0, v),
                                   atol=TOL)
        np.testing.assert_allclose(cgadyn.difference(m, q0, q1), pin.difference(pm, q0, q1),
                                   atol=1e-10)
        np.testing.assert_allclose(cgadyn.interpolate(m, q0, q1, 0.3),
                                   pin.interpolate(pm, q0, q1, 0.3), atol=1e-10)
        np.testing.assert_allclose(cgadyn.difference(m, q0, cgadyn.integrate(m, q0, 0.5 * v)),
                                   0.5 * v, atol=1e-10)


def test_integrate_picks_pinocchio_quaternion_sign(robot):
    """Rotations beyond π: of ±quaternion, the one nearer q's (as Pinocchio picks it), so
    that configurations move between the libraries unchanged."""
    m, pm, _ = robot
    rng = np.random.default_rng(7)
    for _ in range(20):
        q, v = cgadyn.random_configuration(m, rng), 3.0 * rng.normal(size=m.nv)
        np.testing.assert_allclose(cgadyn.integrate(m, q, v), pin.integrate(pm, q, v),
                                   atol=1e-11)


def test_neutral_normalize_and_batches(robot):
    m, pm, _ = robot
    np.testing.assert_array_equal(cgadyn.neutral(m), pin.neutral(pm))
    rng = np.random.default_rng(2)
    q = np.array([cgadyn.random_configuration(m, rng) for _ in range(4)])
    v = rng.normal(size=(4, m.nv))
    rows = np.array([cgadyn.integrate(m, q[b], v[b]) for b in range(4)])
    np.testing.assert_allclose(cgadyn.integrate(m, q, v), rows, atol=1e-14)
    assert np.all(q >= np.where(np.isfinite(m.lower), m.lower, -np.inf))
    if m.floating_base:
        scaled = q.copy()
        scaled[:, 3:7] *= 3.0
        np.testing.assert_allclose(cgadyn.normalize(m, scaled), q, atol=1e-15)
        with pytest.raises(ValueError, match="quaternion.*'root_joint'"):
            cgadyn.integrate(m, scaled[0], v[0])


def test_centroidal_quantities_match_pinocchio(robot):
    m, pm, pd = robot
    rng = np.random.default_rng(3)
    assert cgadyn.total_mass(m) == pytest.approx(pin.computeTotalMass(pm), rel=1e-14)
    for _ in range(3):
        q = cgadyn.random_configuration(m, rng)
        v, a = rng.normal(size=m.nv), rng.normal(size=m.nv)
        c, vc, ac = cgadyn.center_of_mass(m, q, v, a)
        pin.centerOfMass(pm, pd, q, v, a)
        np.testing.assert_allclose(c, pd.com[0], atol=TOL)
        np.testing.assert_allclose(vc, pd.vcom[0], atol=TOL)
        np.testing.assert_allclose(ac, pd.acom[0], atol=1e-11)
        np.testing.assert_allclose(cgadyn.center_of_mass(m, q), pd.com[0], atol=TOL)
        np.testing.assert_allclose(cgadyn.com_jacobian(m, q),
                                   pin.jacobianCenterOfMass(pm, pd, q), atol=TOL)
        Ag = pin.ccrba(pm, pd, q, v)
        np.testing.assert_allclose(cgadyn.centroidal_momentum_matrix(m, q), Ag, atol=1e-11)
        hg = pin.computeCentroidalMomentum(pm, pd, q, v)
        np.testing.assert_allclose(cgadyn.centroidal_momentum(m, q, v), hg.vector, atol=1e-11)


def test_momentum_is_conserved_by_gravity_free_dynamics():
    """Without gravity and external forces a floating robot's momentum about its centre of
    mass is constant: d/dt (A_g v) = 0 with v̇ = aba(q, v, 0)."""
    m, _ = MODELS["solo12"]()
    rng = np.random.default_rng(4)
    q, v = cgadyn.random_configuration(m, rng), rng.normal(size=m.nv)
    a = cgadyn.aba(m, q, v, np.zeros(m.nv), gravity=(0, 0, 0))
    h = 1e-6
    hp = cgadyn.centroidal_momentum(m, cgadyn.integrate(m, q, h * v), v + h * a)
    hm = cgadyn.centroidal_momentum(m, cgadyn.integrate(m, q, -h * v), v - h * a)
    assert np.abs(hp - hm).max() / (2 * h) < 1e-5 * np.abs(hp).max()
