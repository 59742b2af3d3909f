"""The pivot of a joint of three unit columns (``algorithms.pivots``): Ĩ_j, the Schur
complement of Î_j on the joint's own coefficients, is zero in their rows and columns, and
the block forms (``schur_block``, ``schur_apply``, ``outside_congruence_add``) equal the
full ones (``articulated_inertia``, ``Ĩ @ x``, ``kernels.inertia_congruence_add``)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from cgadyn import kernels as K
from cgadyn.algorithms import pivots as P
from cgadyn.cga import conventions as C


def _articulated(rng) -> np.ndarray:
    """A symmetric positive definite 6 x 6 articulated inertia: a rigid body's plus a
    positive semidefinite rank-3 term (as a child's Ĩ moved in adds)."""
    q = rng.normal(size=4)
    A = rng.normal(size=(3, 3))
    body = C.inertia_from_parameters(rng.uniform(0.5, 2.0), rng.normal(size=3),
                                     A @ A.T + np.eye(3))
    E = rng.normal(size=(6, 3))
    m = C.motor_from_quaternion(q / np.linalg.norm(q), rng.normal(size=3))
    X = np.empty((6, 6))
    K.wrench_adjoint(m, X)
    return body + E @ E.T, X


@pytest.mark.parametrize("own", list(itertools.combinations(range(6), 3)))
def test_the_block_forms_equal_the_full_ones(own):
    rng = np.random.default_rng(sum(own))
    Ih, X = _articulated(rng)
    Ih = 0.5 * (Ih + Ih.T)
    signs = rng.choice([-1.0, 1.0], size=3)
    S = np.zeros((3, 6))
    S[range(3), own] = signs
    unit_axis = np.array(own, dtype=np.int64)
    U = np.array([s * Ih[:, i] for s, i in zip(signs, own, strict=True)])  # U_j = Î_j[S_j]
    D, Dinv, G = np.empty((6, 6)), np.empty((6, 6)), np.empty((3, 6))
    assert P.joint_pivot(np.zeros(3), S, U, 0, 3, D, Dinv)
    D2, Dinv2 = np.empty((6, 6)), np.empty((6, 6))
    assert P.unit_pivot(np.zeros(3), unit_axis, S, U, 0, 3, D2, Dinv2)
    np.testing.assert_allclose(Dinv2[:3, :3], Dinv[:3, :3], rtol=1e-12)
    P.pivot_gain(Dinv, U, 0, 3, G)
    full = np.empty((6, 6))
    P.articulated_inertia(Ih, U, G, 0, 3, full)
    assert np.abs(full[list(own)]).max() < 1e-12 * np.abs(Ih).max()
    assert np.abs(full[:, list(own)]).max() < 1e-12 * np.abs(Ih).max()

    three, o0, o1, o2 = P.outside(unit_axis, np.zeros(3), 0, 3)
    assert three and (o0, o1, o2) == tuple(i for i in range(6) if i not in own)
    block = np.full((6, 6), np.nan)
    P.schur_block(Ih, U, G, 0, 3, o0, o1, o2, block)
    o = [o0, o1, o2]
    np.testing.assert_allclose(block[np.ix_(o, o)], full[np.ix_(o, o)], rtol=0, atol=1e-12)

    c = rng.normal(size=6)
    applied = np.full(6, np.nan)
    P.schur_apply(block, c, o0, o1, o2, applied)
    np.testing.assert_allclose(applied, full @ c, rtol=0, atol=1e-12 * np.abs(Ih).max())

    want, got = Ih.copy(), Ih.copy()
    K.inertia_congruence_add(X, full, want)
    P.outside_congruence_add(X, block, o0, o1, o2, np.empty((6, 6)), got)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-11 * np.abs(want).max())


def test_other_joints_take_the_full_forms():
    """Rotor inertia, a column that is not ±e_i, a count other than three or an axis
    twice: no block."""
    axes = np.array([3, 4, 5, -1, 0, 1], dtype=np.int64)
    assert P.outside(axes, np.zeros(6), 0, 3)[0]
    assert not P.outside(axes, np.array([0.0, 0.1, 0.0, 0, 0, 0]), 0, 3)[0]  # armature
    assert not P.outside(axes, np.zeros(6), 1, 4)[0]  # a general column
    assert not P.outside(axes, np.zeros(6), 4, 6)[0]  # two coordinates
    assert not P.outside(np.array([3, 3, 5]), np.zeros(3), 0, 3)[0]  # an axis twice
