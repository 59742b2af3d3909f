"""Every compiled kernel (single and batch) against the dense reference algebra."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cgadyn import kernels as K
from cgadyn.cga import conventions as C
from cgadyn.cga.basis import (
    NULL,
    WRENCH_BLADES,
    motor_mv,
    motor_of,
    twist_mv,
    twist_of,
    wrench_mv,
    wrench_of,
)
from cgadyn.kernels import batch as KB

B = 7
seeds = st.integers(0, 2**32 - 1)


def rigid_motor(rng) -> np.ndarray:
    """A normalised motor (M ~M = 1) of a random pose."""
    q = rng.normal(size=4)
    return C.motor_from_quaternion(q / np.linalg.norm(q), rng.normal(size=3))


def spd_inertia(rng) -> np.ndarray:
    A = rng.normal(size=(3, 3))
    return C.inertia_from_parameters(rng.uniform(0.1, 3), rng.normal(size=3), A @ A.T + np.eye(3))


def ref_inertia_apply(I, v):
    """Eq. (15) literally: W = -Σ_k (I^{e_k} · V) e_k."""
    V = twist_mv(v)
    W = 0.0
    for k, blade in enumerate(WRENCH_BLADES):
        ik = float(wrench_mv(I[k]).scalar_product(V))
        W = W - ik * NULL.multivector(np.array([1.0]), [blade])
    return wrench_of(W)


def ref_inertia_transform(m, I):
    """Eq. (16) literally with reference products and blade extraction."""
    M = motor_mv(m)
    moved = [wrench_of(M * wrench_mv(I[k]) * ~M) for k in range(6)]
    out = np.empty((6, 6))
    for j in range(6):
        inner = sum(moved[k][j] * wrench_mv(np.eye(6)[k]) for k in range(6))
        out[j] = wrench_of(M * inner * ~M)
    return out


# name: (single kernel, batch kernel, input makers, reference, output shape)
def cases(rng):
    m8, n8 = rng.normal(size=8), rng.normal(size=8)
    r = rigid_motor(rng)
    v, u, w = rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
    I = spd_inertia(rng)
    return {
        "motor_mul": ((m8, n8), motor_of(motor_mv(m8) * motor_mv(n8))),
        "motor_mul_rotor": (  # b's e∞ coefficients are garbage: never read
            (m8, n8), motor_of(motor_mv(m8) * motor_mv(np.r_[n8[:4], 0, 0, 0, 0]))),
        "motor_mul_translator": (  # only b4..b6 are read
            (m8, n8), motor_of(motor_mv(m8) * motor_mv(np.r_[1, 0, 0, 0, n8[4:7], 0]))),
        "motor_reverse": ((m8,), motor_of(~motor_mv(m8))),
        "twist_sandwich": ((m8, v), twist_of(motor_mv(m8) * twist_mv(v) * ~motor_mv(m8))),
        "twist_sandwich_rev": ((m8, v), twist_of(~motor_mv(m8) * twist_mv(v) * motor_mv(m8))),
        "wrench_sandwich": ((m8, w), wrench_of(motor_mv(m8) * wrench_mv(w) * ~motor_mv(m8))),
        "wrench_sandwich_rev": (
            (m8, w), wrench_of(~motor_mv(m8) * wrench_mv(w) * motor_mv(m8))),
        "twist_cross": ((v, u), twist_of(twist_mv(v).commutator(twist_mv(u)))),
        "twist_cross_wrench": ((v, w), wrench_of(twist_mv(v).commutator(wrench_mv(w)))),
        "inertia_apply": ((I, v), ref_inertia_apply(I, v)),
        "inertia_transform": ((r, I), ref_inertia_transform(r, I)),
        "wrench_adjoint": (
            (m8,), np.array([wrench_of(motor_mv(m8) * wrench_mv(e) * ~motor_mv(m8))
                             for e in np.eye(6)]).T),
    }


def _call_single(name, args, ref):
    out = np.empty(np.shape(ref))
    getattr(K, name)(*args, out)
    return out


@pytest.mark.parametrize("seed", range(3))
def test_kernels_equal_the_reference(seed):
    for name, (args, ref) in cases(np.random.default_rng(seed)).items():
        assert np.allclose(_call_single(name, args, ref), ref, atol=1e-10), name


@pytest.mark.parametrize("seed", range(2))
def test_batch_kernels_equal_the_single_ones(seed):
    rng = np.random.default_rng(seed)
    rows = [cases(rng) for _ in range(B)]
    for name in rows[0]:
        args = [np.stack([r[name][0][i] for r in rows]) for i in range(len(rows[0][name][0]))]
        refs = np.stack([r[name][1] for r in rows])
        out = np.empty_like(refs)
        batch = getattr(KB, name + "_batch", None)
        if batch is None:  # only the kernels numpy-level code calls have a batch form
            continue
        assert batch(*args, out) is out
        assert np.allclose(out, refs, atol=1e-10), name


@settings(max_examples=25, deadline=None)
@given(seed=seeds)
def test_dot_is_the_scalar_product(seed):
    rng = np.random.default_rng(seed)
    v, w = rng.normal(size=(B, 6)), rng.normal(size=(B, 6))
    ref = twist_mv(v).scalar_product(wrench_mv(w))
    assert np.allclose([K.dot(v[n], w[n]) for n in range(B)], ref)
    assert np.allclose(KB.dot_batch(v, w, np.empty(B)), ref)


def test_translator_rotor_and_translation():
    rng = np.random.default_rng(4)
    p, r = rng.normal(size=(B, 3)), rng.normal(size=(B, 4))
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    out = np.empty((B, 8))
    for b in range(B):
        K.translator_rotor(*p[b], *r[b], out[b])
    T = motor_mv(np.concatenate([np.ones((B, 1)), np.zeros((B, 3)), -0.5 * p, np.zeros((B, 1))],
                                axis=1))
    R = motor_mv(np.concatenate([r, np.zeros((B, 4))], axis=1))
    assert np.allclose(out, motor_of(T * R))
    assert np.allclose(KB.motor_translation_batch(out, np.empty((B, 3))), p)
    assert np.allclose(K.motor_translation(out[0]), p[0])


@settings(max_examples=25, deadline=None)
@given(seed=seeds, eps=st.floats(1e-6, 0.3))
def test_normalize_restores_unit_norm(seed, eps):
    rng = np.random.default_rng(seed)
    m = rigid_motor(rng) + eps * rng.normal(size=8)
    out = np.empty(8)
    K.motor_normalize(m, out)
    Mn = motor_mv(out)
    assert (Mn * ~Mn).allclose(1.0, atol=1e-10)
    assert np.allclose(KB.motor_normalize_batch(m[None], np.empty((1, 8)))[0], out)


def exp_ref(v):
    return motor_of((twist_mv(v) * 0.5).exp())


@settings(max_examples=25, deadline=None)
@given(seed=seeds, scale=st.sampled_from([1e-9, 1e-5, 1e-3, 0.5, 2.0]))
def test_exp_equals_reference_exp_and_log_inverts_it(seed, scale):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=6)
    v[:3] *= scale / np.linalg.norm(v[:3]) * rng.uniform(0.1, 1.0)  # |θ| < π
    m = np.empty(8)
    K.twist_exp(v, m)
    assert np.allclose(m, exp_ref(v), atol=1e-10)
    back = np.empty(6)
    K.motor_log(m, back)
    assert np.allclose(back, v, atol=1e-9)


@pytest.mark.parametrize("theta", [0.0, 1e-9, 1e-6, 1e-4, 1.0, 3.0, np.pi])
def test_exp_of_log_of_motor(theta):
    rng = np.random.default_rng(5)
    for _ in range(5):
        axis = rng.normal(size=3)
        m = C.motor_from_axis_angle(axis, theta, rng.normal(size=3))
        v = np.empty(6)
        K.motor_log(m, v)
        back = np.empty(8)
        K.twist_exp(v, back)
        assert np.allclose(back, m, atol=1e-9) or np.allclose(back, -m, atol=1e-9)
        assert np.allclose(C.matrix_from_motor(back), C.matrix_from_motor(m), atol=1e-9)


def test_pure_translation_log_and_exp():
    t = np.array([0.3, -1.0, 2.0])
    m = C.motor_from_rt(np.eye(3), t)
    v = np.empty(6)
    K.motor_log(m, v)
    assert np.allclose(v[:3], 0) and np.allclose(C.motion_from_twist(v)[:3], t)
    batch = KB.twist_exp_batch(v[None], np.empty((1, 8)))
    assert np.allclose(batch[0], m)
    assert np.allclose(KB.motor_log_batch(m[None], np.empty((1, 6)))[0], v)


@settings(max_examples=25, deadline=None)
@given(seed=seeds)
def test_equivariance_eq17(seed):
    """M I[V] ~M = (M * I)[M V ~M]."""
    rng = np.random.default_rng(seed)
    m, I, v = rigid_motor(rng), spd_inertia(rng), rng.normal(size=6)
    w, lhs, mv_, mI, rhs = (np.empty(6), np.empty(6), np.empty(6), np.empty((6, 6)),
                            np.empty(6))
    K.inertia_apply(I, v, w)
    K.wrench_sandwich(m, w, lhs)
    K.twist_sandwich(m, v, mv_)
    K.inertia_transform(m, I, mI)
    K.inertia_apply(mI, mv_, rhs)
    assert np.allclose(lhs, rhs, atol=1e-9)


def test_adjoint_kernels_equal_the_sandwiches():
    rng = np.random.default_rng(7)
    for _ in range(B):
        m, I = rigid_motor(rng), spd_inertia(rng)
        v, w = rng.normal(size=6), rng.normal(size=6)
        X = np.empty((6, 6))
        K.wrench_adjoint(m, X)
        got, want = np.empty(6), np.empty(6)
        K.adjoint_apply(X, w, got)
        K.wrench_sandwich(m, w, want)
        assert np.allclose(got, want, atol=1e-10)
        K.adjoint_apply_transpose(X, v, got)
        K.twist_sandwich_rev(m, v, want)
        assert np.allclose(got, want, atol=1e-10)
        gotI, wantI = np.empty((6, 6)), np.empty((6, 6))
        K.inertia_congruence(X, I, gotI)
        K.inertia_transform(m, I, wantI)
        assert np.allclose(gotI, wantI, atol=1e-10)
        acc = I.copy()
        K.inertia_congruence_add(X, I, acc)
        assert np.allclose(acc, I + wantI, atol=1e-10)
