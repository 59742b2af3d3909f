"""The derivatives of the motor exponential and logarithm, on physical twists ``ξ = (v, ω)``.

A motor ``M = exp(V / 2)`` of the twist V (eq. 6) moved by a body velocity ``δ`` (applied in
its own frame, ``M exp(δ / 2)``) changes its logarithm by ``δξ = J_r(ξ)⁻¹ δ``: ``J_r`` is
the right Jacobian of the exponential, ``J_r(ξ) = J_l(-ξ)`` with (Barfoot, "State Estimation
for Robotics", eqs. 7.85-7.86 and 7.95, ordering ``(v, ω)``)

    J_l(ξ) = [[J(ω), Q(v, ω)], [0, J(ω)]],
    J(ω) = 1 + (1 - cos θ)/θ² ω^ + (θ - sin θ)/θ³ ω^²,           θ = |ω|
    Q(v, ω) = ½ v^ + a (ω^v^ + v^ω^ + ω^v^ω^) + b (ω^²v^ + v^ω^² - 3 ω^v^ω^)
              + c (ω^v^ω^² + ω^²v^ω^),
    a = (θ - sin θ)/θ³, b = (θ² + 2 cos θ - 2)/(2θ⁴), c = (2θ - 3 sin θ + θ cos θ)/(2θ⁵),

and ``J_r⁻¹ = [[A, -A Q_r A], [0, A]]``, ``A = J_r(ω)⁻¹ = 1 + ½ ω^ + d ω^²``,
``d = 1/θ² - (1 + cos θ)/(2θ sin θ)``: Pinocchio's ``Jlog6`` (and ``Jlog3`` its block A).
Every coefficient switches to its Taylor series at small θ. All matrices are written into
caller-given scratch ``t`` (6, 3, 3): nothing is allocated.
"""

from __future__ import annotations

import math

from .._jit import inline, serial

SMALL = 1e-2
"""Below this rotation angle the coefficients take their series (truncation < 1e-16)."""


@inline
def _coefficients(theta):
    """``(1 - cos θ)/θ², a, b, c, d`` of the module docstring."""
    t2 = theta * theta
    if theta < SMALL:
        return (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0, 1.0 / 24.0 - t2 / 720.0,
                1.0 / 120.0 - t2 / 2520.0, 1.0 / 12.0 + t2 / 720.0)
    s, c = math.sin(theta), math.cos(theta)
    return ((1.0 - c) / t2, (theta - s) / (t2 * theta), (t2 + 2.0 * c - 2.0) / (2.0 * t2 * t2),
            (2.0 * theta - 3.0 * s + theta * c) / (2.0 * t2 * t2 * theta),
            1.0 / t2 - (1.0 + c) / (2.0 * theta * s))


@inline
def _hat(x0, x1, x2, out):
    """``out = x^``, the matrix of ``y ↦ x × y``."""
    out[0, 0], out[0, 1], out[0, 2] = 0.0, -x2, x1
    out[1, 0], out[1, 1], out[1, 2] = x2, 0.0, -x0
    out[2, 0], out[2, 1], out[2, 2] = -x1, x0, 0.0


@inline
def _mul(a, b, out):
    """``out = a b`` (3x3)."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]


@serial
def _q_left(v0, v1, v2, w0, w1, w2, a, b, c, t):
    """``t[5] = Q(v, ω)``, from the vectors instead of the eight matrix products of the
    module docstring: with ``k = ω·v`` and ``z = ω × v`` the identities
    ``ω^v^ = v ωᵀ - k 1``, ``v^ω^ = ω vᵀ - k 1``, ``ω^v^ω^ = -k ω^``,
    ``ω^²v^ = z ωᵀ - k ω^``, ``v^ω^² = -ω zᵀ - k ω^`` and ``ω^v^ω^² = ω^²v^ω^ = -k ω^²``
    give ``Q = ½ v^ + a (v ωᵀ + ω vᵀ - 2k 1) + (b - a) k ω^ + b (z ωᵀ - ω zᵀ)
    - 2 c k (ω ωᵀ - θ² 1)``."""
    Q = t[5]
    k = w0 * v0 + w1 * v1 + w2 * v2
    z0, z1, z2 = w1 * v2 - w2 * v1, w2 * v0 - w0 * v2, w0 * v1 - w1 * v0
    t2 = w0 * w0 + w1 * w1 + w2 * w2
    e = (b - a) * k  # the factor of ω^
    f = -2.0 * c * k  # the factor of ω^²
    d = -2.0 * a * k + f * (-t2)  # the diagonal: -2ak 1 - 2ck (-θ² 1)
    w = (w0, w1, w2)
    v = (v0, v1, v2)
    zz = (z0, z1, z2)
    for i in range(3):
        for j in range(3):
            Q[i, j] = (a * (v[i] * w[j] + w[i] * v[j]) + b * (zz[i] * w[j] - w[i] * zz[j])
                       + f * w[i] * w[j])
        Q[i, i] += d
    # ½ v^ + e ω^, the skew part
    s0, s1, s2 = 0.5 * v0 + e * w0, 0.5 * v1 + e * w1, 0.5 * v2 + e * w2
    Q[0, 1] -= s2
    Q[1, 0] += s2
    Q[0, 2] += s1
    Q[2, 0] -= s1
    Q[1, 2] -= s0
    Q[2, 1] += s0


@serial
def jlog3(w0, w1, w2, out):
    """``out = J_r(ω)⁻¹ = 1 + ½ ω^ + d ω^²`` (3x3): ``δω = out δ`` for a rotation moved by
    the body angular velocity δ (Pinocchio's ``Jlog3``)."""
    theta = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    d = _coefficients(theta)[4]
    ww = (w0 * w0, w0 * w1, w0 * w2, w1 * w1, w1 * w2, w2 * w2)
    t2 = theta * theta
    out[0, 0] = 1.0 + d * (ww[0] - t2)
    out[1, 1] = 1.0 + d * (ww[3] - t2)
    out[2, 2] = 1.0 + d * (ww[5] - t2)
    out[0, 1], out[1, 0] = -0.5 * w2 + d * ww[1], 0.5 * w2 + d * ww[1]
    out[0, 2], out[2, 0] = 0.5 * w1 + d * ww[2], -0.5 * w1 + d * ww[2]
    out[1, 2], out[2, 1] = -0.5 * w0 + d * ww[4], 0.5 * w0 + d * ww[4]


@serial
def jlog6(xi, out, t):
    """``out = J_r(ξ)⁻¹`` (6x6) for the physical twist ``xi = (v, ω)``: Pinocchio's
    ``Jlog6`` of ``exp6(ξ)``. ``t``: (6, 3, 3) scratch."""
    v0, v1, v2, w0, w1, w2 = xi[0], xi[1], xi[2], xi[3], xi[4], xi[5]
    theta = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    _, a, b, c, _ = _coefficients(theta)
    _q_left(-v0, -v1, -v2, -w0, -w1, -w2, a, b, c, t)  # t[5] = Q_r = Q(-v, -ω)
    A = t[4]
    jlog3(w0, w1, w2, A)
    _mul(A, t[5], t[0])
    _mul(t[0], A, t[1])  # A Q_r A
    for i in range(3):
        for j in range(3):
            out[i, j] = A[i, j]
            out[i + 3, j + 3] = A[i, j]
            out[i, j + 3] = -t[1, i, j]
            out[i + 3, j] = 0.0


@serial
def jexp6(xi, out, t):
    """``out = J_r(ξ)`` (6x6): the body velocity of ``exp6(ξ)`` per rate of ξ.
    ``t``: (6, 3, 3) scratch."""
    v0, v1, v2, w0, w1, w2 = xi[0], xi[1], xi[2], xi[3], xi[4], xi[5]
    theta = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    e, a, b, c, _ = _coefficients(theta)
    _q_left(-v0, -v1, -v2, -w0, -w1, -w2, a, b, c, t)  # t[5] = Q_r
    W, W2 = t[0], t[1]
    _hat(-w0, -w1, -w2, W)
    _mul(W, W, W2)
    for i in range(3):
        for j in range(3):
            r = e * W[i, j] + a * W2[i, j] + (1.0 if i == j else 0.0)  # J(-ω)
            out[i, j] = r
            out[i + 3, j + 3] = r
            out[i, j + 3] = t[5, i, j]
            out[i + 3, j] = 0.0
