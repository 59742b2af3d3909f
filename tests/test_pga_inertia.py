"""The inertia map as a duality: eq. (2.22) eigenbasis form = eq. (2.13) point-mass sum."""

import numpy as np
import pytest

from cgadyn.pga import Inertia, kinetic_energy, pga

DIMS = [1, 2, 3, 4]


def box_points(d, edges):
    bits = (np.arange(2**d)[:, None] >> np.arange(d)) & 1
    return (bits - 0.5) * edges


@pytest.mark.parametrize("d", DIMS)
def test_eigenbasis_form_equals_point_mass_sum(d):
    """I[B] = sum_k lambda_k [B]_k *e_k (2.22) equals sum_i m_i X_i ∨ (X_i × B) (2.13)."""
    m = pga(d)
    edges = np.arange(1.0, d + 1)
    pts = box_points(d, edges)
    masses = np.linspace(0.5, 1.5, len(pts))
    masses = masses + masses[::-1]  # symmetric: centroid stays at the origin
    s = np.einsum("i,ia,ib->ab", masses, pts, pts)
    moments = [s[i - 1, i - 1] + s[j - 1, j - 1] for i, j in m.euclidean_planes]
    diag = Inertia.principal(m, masses.sum(), moments)
    rng = np.random.default_rng(d)
    b = m.grade(rng.normal(size=m.n), 2)
    x = m.point(pts)
    direct = (masses[:, None] * m.vee(x, m.commutator(x, b))).sum(0)
    np.testing.assert_allclose(diag.apply(b), direct, atol=1e-12)
    np.testing.assert_allclose(diag.inverse(diag.apply(b)), b, atol=1e-12)


@pytest.mark.parametrize("d", DIMS)
def test_general_frame_from_moments_is_additive_point_sum(d):
    """Off-centre, non-principal frame: from_moments equals the point sum (2.13)."""
    m = pga(d)
    rng = np.random.default_rng(30 + d)
    pts = rng.normal(size=(7, d)) + 0.5
    masses = rng.uniform(0.5, 2.0, size=7)
    mass = masses.sum()
    com = masses @ pts / mass
    inertia = Inertia.from_moments(m, mass, com, np.einsum("i,ia,ib->ab", masses, pts, pts))
    b = m.grade(rng.normal(size=m.n), 2)
    x = m.point(pts)
    direct = (masses[:, None] * m.vee(x, m.commutator(x, b))).sum(0)
    np.testing.assert_allclose(inertia.apply(b), direct, atol=1e-11)


@pytest.mark.parametrize("d", DIMS)
def test_kinetic_energy_is_classical(d):
    """T = ½ B ∨ I[B] = ½ m v² + ½ sum i_ij w_ij² at the centroid (sections 2.7.2, A.12)."""
    m = pga(d)
    rng = np.random.default_rng(40 + d)
    mass, moments = 2.5, rng.uniform(0.5, 2, size=len(m.eij))
    inertia = Inertia.principal(m, mass, moments)
    v, w = rng.normal(size=d), rng.normal(size=len(m.eij))
    b = m.translation_rate(v) + m.rotation_rate(w)
    expected = 0.5 * mass * v @ v + 0.5 * moments @ w**2
    assert kinetic_energy(inertia, b) == pytest.approx(expected, rel=1e-12)


def test_hypercube_moments_and_3d_tensor():
    m = pga(3)
    cube = Inertia.hypercube(m, 12.0, [1.0, 2.0, 3.0])
    # planes (12, 13, 23) <-> (I_zz, I_yy, I_xx) of the cuboid of section 2.5.8
    tensor = np.diag([4.0 + 9.0, 1.0 + 9.0, 1.0 + 4.0])
    np.testing.assert_allclose(cube.matrix, Inertia.from_tensor(m, 12.0, np.zeros(3),
                                                                tensor).matrix, atol=1e-12)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda m: Inertia.principal(m, 0.0, [1, 1, 1]), "mass must be finite and positive"),
        (lambda m: Inertia.principal(m, -2.0, [1, 1, 1]), "mass"),
        (lambda m: Inertia.principal(m, 1.0, [1, 0, 1]), "principal moments"),
        (lambda m: Inertia.principal(m, 1.0, [1, -1, 1]), "principal moments"),
        (lambda m: Inertia.principal(m, 1.0, [1, 1]), "3 principal moments expected"),
        (lambda m: Inertia.principal(m, np.nan, [1, 1, 1]), "mass"),
        (lambda m: Inertia.hypercube(m, 1.0, [1, 0, 1]), "edge lengths"),
        (lambda m: Inertia.from_tensor(m, 1.0, np.zeros(3), -np.eye(3)), "principal moments"),
        (lambda m: Inertia.from_tensor(pga(2), 1.0, np.zeros(2), np.eye(3)), "needs d=3"),
        (lambda m: Inertia.from_moments(m, 1.0, np.zeros(3), -np.eye(3)), "positive definite"),
    ],
)
def test_bad_inertia_input(make, match):
    with pytest.raises(ValueError, match=match):
        make(pga(3))
