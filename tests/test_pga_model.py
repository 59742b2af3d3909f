"""PGA model G(d,0,1): fast products against the reference algebra, points, rates, motors."""

import numpy as np
import pytest

from cgadyn.algebra import Multivector
from cgadyn.pga import normalize_motor, pga
from cgadyn.pga.integrators import _normalize_motor_series
from cgadyn.pga.model import PGA

DIMS = [1, 2, 3, 4]


@pytest.mark.parametrize("d", DIMS)
def test_products_match_reference_multivector(d):
    m = pga(d)
    rng = np.random.default_rng(d)
    a, b = rng.normal(size=(2, m.n))
    A, B = Multivector(m.algebra, a), Multivector(m.algebra, b)
    np.testing.assert_allclose(m.gp(a, b), (A * B).coeffs, atol=1e-12)
    np.testing.assert_allclose(m.op(a, b), (A ^ B).coeffs, atol=1e-12)
    np.testing.assert_allclose(m.lc(a, b), (A | B).coeffs, atol=1e-12)
    np.testing.assert_allclose(m.vee(a, b), (A & B).coeffs, atol=1e-12)
    np.testing.assert_allclose(m.commutator(a, b), A.commutator(B).coeffs, atol=1e-12)
    np.testing.assert_allclose(m.dual(a), A.dual().coeffs)
    np.testing.assert_allclose(m.undual(m.dual(a)), a)
    np.testing.assert_allclose(m.exp(0.3 * a), (A * 0.3).exp().coeffs, atol=1e-10)


@pytest.mark.parametrize("d", DIMS)
def test_points_rates_and_motors(d):
    m = pga(d)
    rng = np.random.default_rng(10 + d)
    x, v = rng.normal(size=(2, d))
    np.testing.assert_allclose(m.coords(m.point(x)), x)
    # exp(-B t/2) with B = translation_rate(v) moves points by v t (section 2.1.5).
    t = 0.7
    moved = m.sandwich(m.exp(-0.5 * t * m.translation_rate(v)), m.point(x))
    np.testing.assert_allclose(m.coords(moved), x + v * t, atol=1e-12)
    # rotation_rate turns e_i towards e_j in each plane (i, j).
    for k, (i, j) in enumerate(m.euclidean_planes):
        w = np.zeros(len(m.eij))
        w[k] = np.pi / 2
        p = m.coords(m.sandwich(m.exp(-0.5 * m.rotation_rate(w)), m.point(np.eye(d)[i - 1])))
        np.testing.assert_allclose(p, np.eye(d)[j - 1], atol=1e-12)
    vv, ww = m.split_rate(m.translation_rate(v) + m.rotation_rate(np.arange(len(m.eij))))
    np.testing.assert_allclose(vv, v)
    np.testing.assert_allclose(ww, np.arange(len(m.eij)))


@pytest.mark.parametrize("d", DIMS)
def test_motor_renormalisation(d):
    m = pga(d)
    rng = np.random.default_rng(20 + d)
    motor = m.exp(-0.5 * m.grade(rng.normal(size=m.n), 2))
    even = [k for k in range(0, d + 2, 2)]
    noise = sum(m.grade(rng.normal(size=m.n), k) for k in even) * 1e-4
    fixed = normalize_motor(m, motor + noise)
    np.testing.assert_allclose(m.gp(fixed, m.reverse(fixed)), m.scalar(), atol=1e-14)
    assert np.abs(fixed - motor).max() < 1e-3
    np.testing.assert_allclose(normalize_motor(m, motor), motor, atol=1e-14)


def test_3d_closed_form_renormalisation_equals_general_series():
    m = pga(3)
    rng = np.random.default_rng(5)
    motor = m.exp(-0.5 * m.grade(rng.normal(size=m.n), 2))
    bad = motor + 1e-3 * (m.grade(rng.normal(size=m.n), 0) + m.grade(rng.normal(size=m.n), 2)
                          + m.grade(rng.normal(size=m.n), 4))
    np.testing.assert_allclose(normalize_motor(m, bad), _normalize_motor_series(m, bad),
                               atol=1e-15)


@pytest.mark.parametrize("bad", [0, 5, -1, 2.5, True, "3", None])
def test_dimension_outside_1_to_4_is_rejected(bad):
    with pytest.raises(ValueError, match="dimension must be an integer in 1..4"):
        pga(bad)
    with pytest.raises(ValueError, match="1..4"):
        PGA(bad)


def test_bad_coordinates_are_rejected():
    m = pga(3)
    with pytest.raises(ValueError, match="last axis 3"):
        m.point([1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        m.point([1.0, np.nan, 0.0])
