"""Closed forms on motors: exp of a twist, log of a motor, normalisation.

Hand-written on top of the generated products of ``_generated.py``: these are not
polynomials, so they are closed forms with explicit small-angle series, not expansions.

A twist ``V`` (eq. 7) with angular velocity ω and linear velocity v has coefficients
``(-ω1, ω2, -ω3, -v1, -v2, -v3)`` on ``(e23, e13, e12, e1∞, e2∞, e3∞)``; see
``cgadyn.cga.conventions``. Moving with ``V`` for unit time is the motor ``exp(V / 2)``
(eq. 6 with the paper's ½ made explicit): a rotor ``R = exp(V_rot / 2)`` followed by the
translator ``T = 1 - ½ p e∞`` of the screw displacement ``p``.
"""

from __future__ import annotations

import math

from .._jit import serial
from ._generated import (
    motor_mul,
    motor_translation,
    translator_rotor,
)
from .layout import physical, store_bivector


@serial
def _rotation_coefficients(theta):
    """(sin θ/θ, (1 - cos θ)/θ², (θ - sin θ)/θ³), with series below 1e-4."""
    if theta < 1e-4:
        t2 = theta * theta
        return 1.0 - t2 / 6.0, 0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0
    s = math.sin(theta)
    c = math.cos(theta)
    return s / theta, (1.0 - c) / (theta * theta), (theta - s) / (theta * theta * theta)


@serial
def twist_exp(v, out):
    """Motor of the screw motion ``out = exp(V / 2)`` of a twist (eq. 6)."""
    w1, w2, w3, u1, u2, u3 = physical(v)  # ω and v
    theta = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    half = 0.5 * theta
    if theta < 1e-4:
        k = 0.5 - theta * theta / 48.0
    else:
        k = math.sin(half) / theta
    # rotor R = cos(θ/2) + (sin(θ/2)/θ) V_rot on (1, e12, e13, e23)
    r0, r1, r2, r3 = math.cos(half), k * v[2], k * v[1], k * v[0]
    # translation p = J(ω) v, J = 1 + b ω^ + c ω^2 (left Jacobian of the rotation)
    _, b, c = _rotation_coefficients(theta)
    cx1 = w2 * u3 - w3 * u2
    cx2 = w3 * u1 - w1 * u3
    cx3 = w1 * u2 - w2 * u1
    cc1 = w2 * cx3 - w3 * cx2
    cc2 = w3 * cx1 - w1 * cx3
    cc3 = w1 * cx2 - w2 * cx1
    p1 = u1 + b * cx1 + c * cc1
    p2 = u2 + b * cx2 + c * cc2
    p3 = u3 + b * cx3 + c * cc3
    translator_rotor(p1, p2, p3, r0, r1, r2, r3, out)


@serial
def motor_log(m, out):
    """Twist ``V`` with ``exp(V / 2) = M`` for a normalised motor, rotation angle in [0, 2π).

    Handles pure translations, the small-angle limit and θ = π.
    """
    r0, r1, r2, r3 = m[0], m[1], m[2], m[3]
    s = math.sqrt(r1 * r1 + r2 * r2 + r3 * r3)
    theta = 2.0 * math.atan2(s, r0)
    if theta < 1e-4:
        k = 0.5 - theta * theta / 48.0
    else:
        k = s / theta
    out[0] = r3 / k
    out[1] = r2 / k
    out[2] = r1 / k
    p1, p2, p3 = motor_translation(m)
    w1, w2, w3, _, _, _ = physical(out)  # ω
    # v = J(ω)^-1 p, J^-1 = 1 - ½ ω^ + d ω^2
    if theta < 1e-4:
        d = 1.0 / 12.0 + theta * theta / 720.0
    else:
        d = (1.0 - theta * math.sin(theta) / (2.0 * (1.0 - math.cos(theta)))) / (theta * theta)
    cx1 = w2 * p3 - w3 * p2
    cx2 = w3 * p1 - w1 * p3
    cx3 = w1 * p2 - w2 * p1
    cc1 = w2 * cx3 - w3 * cx2
    cc2 = w3 * cx1 - w1 * cx3
    cc3 = w1 * cx2 - w2 * cx1
    store_bivector(w1, w2, w3, p1 - 0.5 * cx1 + d * cc1, p2 - 0.5 * cx2 + d * cc2,
                   p3 - 0.5 * cx3 + d * cc3, out)


@serial
def motor_normalize(m, out):
    """Project a motor back onto the manifold ``M ~M = 1``.

    The rotor part is scaled to unit norm, then the translation it carries is kept:
    ``M = T R`` with ``T = (M ~R)`` reduced to its e∞ part.
    """
    n = math.sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2] + m[3] * m[3])
    p1, p2, p3 = motor_translation(m)
    s = 1.0 / (n * n)
    translator_rotor(p1 * s, p2 * s, p3 * s, m[0] / n, m[1] / n, m[2] / n, m[3] / n, out)


__all__ = ["motor_log", "motor_mul", "motor_normalize", "twist_exp"]
