"""Laws of the reference algebra (the oracle of the kernels): CGA G(4,1) and PGA G(3,0,1)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cgadyn.algebra import Algebra, Multivector
from cgadyn.cga.basis import CGA

PGA = Algebra.pga(3)
ALGEBRAS = {"cga": CGA, "pga3": PGA}
seeds = st.integers(0, 2**32 - 1)


def rand(alg: Algebra, rng, grades=None) -> Multivector:
    mv = Multivector(alg, rng.normal(size=alg.size))
    return mv if grades is None else mv.grade(*grades)


@pytest.mark.parametrize("name", ALGEBRAS)
@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_geometric_product_is_associative(name, seed):
    alg, rng = ALGEBRAS[name], np.random.default_rng(seed)
    a, b, c = (rand(alg, rng) for _ in range(3))
    assert ((a * b) * c).allclose(a * (b * c), atol=1e-9)


@pytest.mark.parametrize("name", ALGEBRAS)
@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_reverse_of_product(name, seed):
    alg, rng = ALGEBRAS[name], np.random.default_rng(seed)
    a, b = rand(alg, rng), rand(alg, rng)
    assert (~(a * b)).allclose(~b * ~a, atol=1e-10)


@pytest.mark.parametrize("name", ALGEBRAS)
@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_outer_product_of_vectors_is_antisymmetric(name, seed):
    alg, rng = ALGEBRAS[name], np.random.default_rng(seed)
    a, b = rand(alg, rng, [1]), rand(alg, rng, [1])
    assert (a ^ b).allclose(-(b ^ a), atol=1e-12)
    assert (a ^ a).allclose(0.0, atol=1e-12)
    # for vectors the geometric product is inner plus outer product
    assert (a * b).allclose((a | b) + (a ^ b), atol=1e-12)


def pga_point(x) -> Multivector:
    """PGA point as the trivector dual of e0 + x (x e0 order as in the forque paper)."""
    e = {n: Multivector.blade(PGA, "e" + n) for n in ("0", "1", "2", "3")}
    return (e["0"] + x[0] * e["1"] + x[1] * e["2"] + x[2] * e["3"]).dual()


def test_regressive_join_of_two_pga_points_is_a_line():
    rng = np.random.default_rng(1)
    p, q = rng.normal(size=3), rng.normal(size=3)
    P, Q = pga_point(p), pga_point(q)
    L = P & Q
    assert np.allclose(L.coeffs, L.grade(2).coeffs) and np.abs(L.coeffs).max() > 1e-6
    # both points and every affine combination lie on it (P ∨ L = 0 for incident P)
    for t in (0.0, 1.0, 0.3, -2.0):
        X = pga_point((1 - t) * p + t * q)
        assert (X & L).allclose(0.0, atol=1e-10)
    assert not (pga_point(p + rng.normal(size=3)) & L).allclose(0.0, atol=1e-6)
    assert (L & P).allclose(0.0, atol=1e-10)


@pytest.mark.parametrize("name", ALGEBRAS)
def test_dual_undual_round_trip(name):
    alg = ALGEBRAS[name]
    a = rand(alg, np.random.default_rng(2))
    assert a.dual().undual().allclose(a)
    assert a.undual().dual().allclose(a)
    # e_k ∧ dual(e_k) is the pseudoscalar for every blade
    for k in range(alg.size):
        e = Multivector(alg, np.eye(alg.size)[k])
        assert (e ^ e.dual()).allclose(Multivector(alg, np.eye(alg.size)[-1]))


@pytest.mark.parametrize("name", ALGEBRAS)
@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_jacobi_identity_of_the_commutator_on_bivectors(name, seed):
    alg, rng = ALGEBRAS[name], np.random.default_rng(seed)
    a, b, c = (rand(alg, rng, [2]) for _ in range(3))
    jac = a.commutator(b.commutator(c)) + b.commutator(c.commutator(a))
    jac = jac + c.commutator(a.commutator(b))
    assert jac.allclose(0.0, atol=1e-9)
    # bivectors are closed under the commutator
    ab = a.commutator(b)
    assert ab.allclose(ab.grade(2), atol=1e-10)


@settings(max_examples=20, deadline=None)
@given(theta=st.floats(-6.0, 6.0), seed=seeds)
def test_exp_of_euclidean_bivector_is_cos_plus_sin(theta, seed):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    B = Multivector.from_blades(CGA, ["e23", "e13", "e12"], u)  # B² = -1
    assert (B * B).allclose(-1.0, atol=1e-12)
    closed = Multivector.scalar(CGA, np.cos(theta)) + B * np.sin(theta)
    assert (B * theta).exp().allclose(closed, atol=1e-10)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_exp_of_null_bivector_is_one_plus_b(seed):
    """PGA translations: B² = 0, so exp(B) = 1 + B."""
    rng = np.random.default_rng(seed)
    B = Multivector.from_blades(PGA, ["e01", "e02", "e03"], rng.normal(size=3) * 3)
    assert (B * B).allclose(0.0, atol=1e-12)
    assert B.exp().allclose(B + 1.0, atol=1e-10)


def test_versor_inverse_and_bad_input():
    rng = np.random.default_rng(3)
    v = rand(CGA, rng, [1])
    assert (v * v.inverse()).allclose(1.0, atol=1e-10)
    with pytest.raises(ValueError, match="zero norm"):
        Multivector.blade(PGA, "e0").inverse()
    with pytest.raises(ValueError, match="last axis"):
        Multivector(CGA, np.zeros(16))
    with pytest.raises(ValueError, match="unknown blade"):
        CGA.blade("e7")
