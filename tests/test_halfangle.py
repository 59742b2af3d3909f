"""The joint motors' scalars (eq. 6) from the vectorised half-angle sine and cosine."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cgadyn.kernels.halfangle import LIBM_BEYOND, PIO2_1, PIO2_2, PIO2_3
from cgadyn.multibody.joints import joint_scalars

PI_50 = Fraction("3.14159265358979323846264338327950288419716939937510")

ULPS = 2.5
"""Ours are within 1.7 ulp of the exact values, libm's within 0.5."""


def scalars(q):
    q = np.asarray(q, dtype=np.float64)
    c, s = np.empty(len(q)), np.empty(len(q))
    joint_scalars(q, c, s)  # cos and sin of every half coordinate
    return c, s


def assert_close_to_libm(q, c, s):
    ref_c = np.cos(0.5 * q)
    ref_s = np.sin(0.5 * q)
    np.testing.assert_array_less(np.abs(c - ref_c), ULPS * np.spacing(np.abs(ref_c)) + 1e-300)
    np.testing.assert_array_less(np.abs(s - ref_s), ULPS * np.spacing(np.abs(ref_s)) + 1e-300)


def test_pi_over_two_split_is_exact_enough():
    """The first two parts carry 33 significant bits (so k·P is exact for |k| < 2^20) and
    the three parts sum to π/2 far below double precision."""
    for part in (PIO2_1, PIO2_2):
        mantissa, _ = math.frexp(part)
        assert (Fraction(mantissa) * 2**33).denominator == 1
    error = Fraction(PIO2_1) + Fraction(PIO2_2) + Fraction(PIO2_3) - PI_50 / 2
    assert abs(error) < Fraction(1, 10**35)


def test_joint_range_and_quadrant_boundaries():
    rng = np.random.default_rng(0)
    k = np.arange(-64, 65)
    q = np.concatenate([
        rng.uniform(-2 * math.pi, 2 * math.pi, 5000),
        k * math.pi / 2, k * math.pi, k * math.pi / 2 + 1e-9, k * math.pi / 2 - 1e-9,
        [0.0, -0.0, 5e-324, 1e-300, 1e-8, -1e-8],
    ])
    assert_close_to_libm(q, *scalars(q))


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-4 * LIBM_BEYOND, 4 * LIBM_BEYOND), min_size=1, max_size=24))
def test_any_finite_angle(q):
    """Through the reduction's whole range, and beyond it (libm)."""
    q = np.array(q)
    assert_close_to_libm(q, *scalars(q))


def test_far_angles_take_libm_exactly():
    q = np.array([0.3, 2.5 * LIBM_BEYOND, -1e12, 1e300])
    c, s = scalars(q)
    np.testing.assert_array_equal(c[1:], np.cos(0.5 * q[1:]))
    np.testing.assert_array_equal(s[1:], np.sin(0.5 * q[1:]))


def test_scalars_are_on_the_unit_circle():
    q = np.random.default_rng(1).uniform(-50, 50, 1000)
    c, s = scalars(q)
    np.testing.assert_allclose(c * c + s * s, 1.0, atol=4e-16)
