"""Where each physical component sits among the CGA coefficients: the two facts, written once.

A twist ``(-ω1, ω2, -ω3, -v1, -v2, -v3)`` on ``(e23, e13, e12, e1∞, e2∞, e3∞)`` (eq. 7) and
a wrench ``(-n1, n2, -n3, -f1, -f2, -f3)`` on ``(e23, e13, e12, e01, e02, e03)`` (eq. 8):
coefficient k is ``BIVECTOR_SIGN[k]`` times the physical component k, in the physical order
(angular part first). A rotor ``(1, e12, e13, e23)`` of the rotation with unit quaternion
``(w, x, y, z)`` is ``(w, -z, y, -x)``: ``R = w - (x e23 + y e31 + z e12)``.
``cgadyn.cga.conventions`` explains the choice; numpy code reads the constants, compiled
code the inline helpers below (numba folds the constants into the arithmetic).
"""

from __future__ import annotations

from .._jit import inline

BIVECTOR_SIGN = (-1.0, 1.0, -1.0, -1.0, -1.0, -1.0)
"""Coefficient k of a twist or wrench = ``BIVECTOR_SIGN[k]`` × physical component k (ω or n,
then v or f)."""

QUATERNION_OF_ROTOR = ((0, 1.0), (3, -1.0), (2, 1.0), (1, -1.0))
"""``(index, sign)`` of the rotor coefficient that gives w, x, y, z of the unit quaternion;
the map is its own inverse: rotor coefficient ``index`` = sign × quaternion component."""

S0, S1, S2, S3, S4, S5 = BIVECTOR_SIGN
(QW, SW), (QX, SX), (QY, SY), (QZ, SZ) = QUATERNION_OF_ROTOR


@inline
def physical(x):
    """The physical components ``(a1, a2, a3, b1, b2, b3)`` of twist or wrench coefficients:
    ``(ω, v)`` of a twist, ``(n, f)`` of a wrench."""
    return S0 * x[0], S1 * x[1], S2 * x[2], S3 * x[3], S4 * x[4], S5 * x[5]


@inline
def coefficients(x):
    """The six coefficients of a twist or wrench, as a tuple: values that a compiled loop
    keeps in registers while it stores into other arrays (read from ``x`` in the loop, they
    would be loaded again after every store, which might have changed them)."""
    return x[0], x[1], x[2], x[3], x[4], x[5]


@inline
def scaled(s, y):
    """The six coefficients of ``y s`` (``s`` a twist or wrench, ``y`` a number), as a
    tuple kept in registers (``coefficients``)."""
    return s[0] * y, s[1] * y, s[2] * y, s[3] * y, s[4] * y, s[5] * y


@inline
def added(x, s, y):
    """The six coefficients of ``x + y s`` (``x`` a tuple of ``coefficients``), as a tuple:
    a sum over a joint's coordinates accumulated in registers."""
    return (x[0] + s[0] * y, x[1] + s[1] * y, x[2] + s[2] * y, x[3] + s[3] * y,
            x[4] + s[4] * y, x[5] + s[5] * y)


@inline
def bivector(a1, a2, a3, b1, b2, b3):
    """The twist or wrench coefficients of physical ``(ω, v)`` or ``(n, f)``, as a tuple."""
    return S0 * a1, S1 * a2, S2 * a3, S3 * b1, S4 * b2, S5 * b3


@inline
def store_bivector(a1, a2, a3, b1, b2, b3, out):
    """Write the twist or wrench coefficients of physical ``(ω, v)`` or ``(n, f)`` into ``out``."""
    out[0], out[1], out[2] = S0 * a1, S1 * a2, S2 * a3
    out[3], out[4], out[5] = S3 * b1, S4 * b2, S5 * b3


@inline
def quaternion(m):
    """The quaternion ``(w, x, y, z)`` of a motor's (or rotor's) rotor part, unnormalised."""
    return SW * m[QW], SX * m[QX], SY * m[QY], SZ * m[QZ]


@inline
def rotor(q):
    """Rotor coefficients ``(1, e12, e13, e23)`` of a quaternion ``q = (w, x, y, z)`` (an
    array or a tuple), as a tuple: the same map as ``quaternion``, which is its own inverse."""
    return SW * q[QW], SX * q[QX], SY * q[QY], SZ * q[QZ]
