"""The reference algebra's log inverts exp for bivectors, in CGA and PGA, and agrees with
the closed-form motor_log kernel."""

from __future__ import annotations

import numpy as np
import pytest

from cgadyn import kernels as K
from cgadyn.algebra import Algebra, Multivector
from cgadyn.cga.basis import motor_of, twist_mv


@pytest.mark.parametrize("seed", range(4))
def test_cga_log_inverts_exp_and_matches_kernel(seed):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=6)
    v[:3] *= 2.5 / max(np.linalg.norm(v[:3]), 1e-9) * rng.uniform(0.1, 1.0)  # |θ| < π
    half = twist_mv(v) * 0.5
    log = half.exp().log()
    np.testing.assert_allclose(log.grade(2).coeffs, half.coeffs, atol=1e-12)
    out = np.empty(6)
    K.motor_log(motor_of(half.exp()), out)
    np.testing.assert_allclose(out, v, atol=1e-12)


@pytest.mark.parametrize("d", [2, 3, 4])
def test_pga_log_inverts_exp(d):
    alg = Algebra.pga(d)
    rng = np.random.default_rng(d)
    b = Multivector(alg, np.where(alg.grades == 2, rng.normal(size=alg.size), 0.0)) * 0.4
    m = b.exp()
    np.testing.assert_allclose(m.log().grade(2).coeffs, b.coeffs, atol=1e-12)
    np.testing.assert_allclose(m.log().exp().coeffs, m.coeffs, atol=1e-12)


def test_general_inverse_and_sqrt():
    alg = Algebra.cga()
    rng = np.random.default_rng(1)
    a = Multivector(alg, rng.normal(size=alg.size))
    np.testing.assert_allclose((a * a.general_inverse()).coeffs, np.eye(alg.size)[0], atol=1e-10)
    r = (Multivector(alg, np.where(alg.grades == 2, rng.normal(size=alg.size), 0.0)) * 0.3).exp()
    s = r.sqrt()
    np.testing.assert_allclose((s * s).coeffs, r.coeffs, atol=1e-12)
