"""The scalars of every joint motor at once: ``exp(q B / 2) = c + s B`` (eq. 6).

A revolute axis is a line (B² = -1): ``(c, s) = (cos q/2, sin q/2)``; a prismatic axis is
a direction (B² = 0): ``(c, s) = (1, q/2)``. The recursions need one such pair per joint,
and libm's ``sincos`` is a call per angle, one angle at a time, which the compiler does
not vectorise: on a small robot, a sizeable share of the mass matrix.
``multibody.joints.joint_scalars`` computes all pairs in one branch-free loop that LLVM
vectorises, with ``half_angle_sincos``:

- Cody-Waite reduction ``x = k π/2 + r``, ``|r| <= π/4``, with π/2 split in three parts;
  the first two carry 33 significant bits, so ``k P1`` and ``k P2`` are exact for
  ``|k| < 2**20`` and ``r`` is exact to about an ulp.
- Taylor polynomials of sin r to degree 17 and cos r to degree 18 (Horner in r²): the
  truncation error is below 1e-19 on ``|r| <= π/4``.
- The quadrant ``k mod 4`` swaps and signs the pair.

The results are within 1.7 ulp of the exact values (libm's: 0.5 ulp); most of it is the
rounding of ``r``, which an extra-precise remainder would remove at the cost of speed.

Half angles beyond ``LIBM_BEYOND`` (1e5 rad, far outside any joint's range, and inside
the reduction's exact range) are redone with libm.
"""

from __future__ import annotations

import math

from .._jit import inline

PIO2_1 = 1.5707963267341256  # π/2 to 33 significant bits
PIO2_2 = 6.077100506303966e-11  # the next 33 bits
PIO2_3 = 2.0222662487959506e-21  # the rest, rounded: P1 + P2 + P3 = π/2 to 1e-37
TWO_OVER_PI = 0.6366197723675814
LIBM_BEYOND = 1e5
"""Half angles of larger magnitude take libm's sin and cos."""


@inline
def _sin_cos_reduced(r):
    """(sin r, cos r) for ``|r| <= π/4``: Taylor polynomials in z = r²."""
    z = r * r
    sin = r + r * z * (-1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (
        1.0 / 362880 + z * (-1.0 / 39916800 + z * (1.0 / 6227020800 + z * (
            -1.0 / 1307674368000 + z * (1.0 / 355687428096000))))))))
    cos = 1.0 + z * (-0.5 + z * (1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (
        -1.0 / 3628800 + z * (1.0 / 479001600 + z * (-1.0 / 87178291200 + z * (
            1.0 / 20922789888000 + z * (-1.0 / 6402373705728000)))))))))
    return sin, cos


@inline
def half_angle_sincos(x):
    """(cos x/2, sin x/2), branch-free for ``|x/2| <= LIBM_BEYOND``."""
    h = 0.5 * x
    k = math.floor(h * TWO_OVER_PI + 0.5)  # nearest multiple of π/2
    r = ((h - k * PIO2_1) - k * PIO2_2) - k * PIO2_3
    sin, cos = _sin_cos_reduced(r)
    quadrant = int(k) & 3
    odd = quadrant & 1
    c = sin if odd else cos  # x/2 = k π/2 + r: odd quadrants swap sine and cosine
    s = cos if odd else sin
    c_sign = 1.0 - ((quadrant + 1) & 2)  # cos is negative in quadrants 1 and 2
    s_sign = 1.0 - (quadrant & 2)  # sin in quadrants 2 and 3
    return c_sign * c, s_sign * s
