"""A floating robot's mass matrix and centroidal momentum matrix do not depend on where its
base is (the base twist is in the base frame): far from the origin they keep every digit."""

import numpy as np
import pytest

import cgadyn

DISTANCES = (1.0, 1e3, 1e6)


def _at(q, offset):
    q = q.copy()
    q[:3] += offset
    return q


@pytest.mark.parametrize("robot", ["iris", "solo12"])
@pytest.mark.parametrize("distance", DISTANCES)
def test_mass_matrix_far_from_origin(robot, distance):
    model = cgadyn.load(robot)
    rng = np.random.default_rng(3)
    q = cgadyn.random_configuration(model, 3)
    q[:3] = 0.0
    offset = distance * rng.normal(size=3) / np.sqrt(3)
    M0, M = cgadyn.crba(model, q), cgadyn.crba(model, _at(q, offset))
    assert np.max(np.abs(M - M0)) <= 1e-13 * np.max(np.abs(M0))
    batch = cgadyn.crba(model, np.stack([q, _at(q, offset)]))
    assert np.max(np.abs(batch[1] - M0)) <= 1e-13 * np.max(np.abs(M0))


@pytest.mark.parametrize("robot", ["iris", "solo12"])
@pytest.mark.parametrize("distance", DISTANCES)
def test_centroidal_far_from_origin(robot, distance):
    model = cgadyn.load(robot)
    q = cgadyn.random_configuration(model, 4)
    q[:3] = 0.0
    offset = np.array([distance, -0.5 * distance, 0.25 * distance])
    A0, A = (cgadyn.centroidal_momentum_matrix(model, x) for x in (q, _at(q, offset)))
    assert np.max(np.abs(A - A0)) <= 1e-13 * np.max(np.abs(A0))
    c0, c = (cgadyn.center_of_mass(model, x) for x in (q, _at(q, offset)))
    assert np.allclose(c - offset, c0, rtol=0, atol=1e-14 * distance + 1e-15)
