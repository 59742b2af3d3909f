"""``M * I`` for a rigid-body inertia in closed form: the cheap special case of eq. (16).

A rigid body's inertia is fixed by ten numbers: its mass m, the first moment h = m c and
the rotational inertia Ī about the frame origin (eqs. 18-19: ``I = M^CoM * I_com``). Moving
it by a motor ``M = T R`` moves the centre of mass like a point and turns the rotational
inertia with the rotor, so eq. (16) reduces to (Featherstone's rigid transform)::

    m' = m,   h' = R h + m p,   Ī' = R Ī Rᵀ - [R h]× [p]× - [p]× [h']×

with p the translation of M. That is about 100 multiplications where the general
congruence of eq. (16) takes 270; the composite inertias of the mass matrix (CRBA) are
rigid, articulated ones (ABA) are not. Coefficients are read from and written to the
element matrix of ``cgadyn.cga.conventions``: ``I = D P D`` with P the physical 6x6
inertia in (ω, v) order and ``D = diag(-1, 1, -1, -1, -1, -1)``.
"""

from __future__ import annotations

from numba import njit

from ._generated import motor_translation


@njit(cache=True, nogil=True, inline="always")
def rigid_inertia_transform(m, inertia, out):
    """``out = M * I`` for a rigid inertia ``I`` (any inertia built from mass, com and a
    3x3 rotational inertia, or a sum of them). ``out`` may alias ``inertia``."""
    # rotation matrix of the rotor, quaternion (w, x, y, z) = (m0, -m3, m2, -m1)
    w, x, y, z = m[0], -m[3], m[2], -m[1]
    r00 = 1.0 - 2.0 * (y * y + z * z)
    r01 = 2.0 * (x * y - z * w)
    r02 = 2.0 * (x * z + y * w)
    r10 = 2.0 * (x * y + z * w)
    r11 = 1.0 - 2.0 * (x * x + z * z)
    r12 = 2.0 * (y * z - x * w)
    r20 = 2.0 * (x * z - y * w)
    r21 = 2.0 * (y * z + x * w)
    r22 = 1.0 - 2.0 * (x * x + y * y)
    p0, p1, p2 = motor_translation(m)
    # physical parameters: P = D I D, Ī = P[:3, :3], [h]x = P[:3, 3:], m = P[3, 3]
    a00, a11, a22 = inertia[0, 0], inertia[1, 1], inertia[2, 2]
    a01, a02, a12 = -inertia[0, 1], inertia[0, 2], -inertia[1, 2]
    h0, h1, h2 = inertia[2, 4], inertia[0, 5], -inertia[1, 3]
    mass = inertia[3, 3]
    # h_r = R h, h' = h_r + m p
    g0 = r00 * h0 + r01 * h1 + r02 * h2
    g1 = r10 * h0 + r11 * h1 + r12 * h2
    g2 = r20 * h0 + r21 * h1 + r22 * h2
    k0, k1, k2 = g0 + mass * p0, g1 + mass * p1, g2 + mass * p2
    # T = R Ī, then Ī_r = T Rᵀ (symmetric)
    t00 = r00 * a00 + r01 * a01 + r02 * a02
    t01 = r00 * a01 + r01 * a11 + r02 * a12
    t02 = r00 * a02 + r01 * a12 + r02 * a22
    t10 = r10 * a00 + r11 * a01 + r12 * a02
    t11 = r10 * a01 + r11 * a11 + r12 * a12
    t12 = r10 * a02 + r11 * a12 + r12 * a22
    t20 = r20 * a00 + r21 * a01 + r22 * a02
    t21 = r20 * a01 + r21 * a11 + r22 * a12
    t22 = r20 * a02 + r21 * a12 + r22 * a22
    b00 = t00 * r00 + t01 * r01 + t02 * r02
    b01 = t00 * r10 + t01 * r11 + t02 * r12
    b02 = t00 * r20 + t01 * r21 + t02 * r22
    b11 = t10 * r10 + t11 * r11 + t12 * r12
    b12 = t10 * r20 + t11 * r21 + t12 * r22
    b22 = t20 * r20 + t21 * r21 + t22 * r22
    # - [g]x [p]x - [p]x [k]x  =  (g·p + p·k) 1 - (p gᵀ + k pᵀ)   (for [a]x[b]x = b aᵀ - (a·b) 1)
    s = g0 * p0 + g1 * p1 + g2 * p2 + p0 * k0 + p1 * k1 + p2 * k2
    b00 += s - (p0 * g0 + k0 * p0)
    b11 += s - (p1 * g1 + k1 * p1)
    b22 += s - (p2 * g2 + k2 * p2)
    b01 -= p0 * g1 + k0 * p1
    b02 -= p0 * g2 + k0 * p2
    b12 -= p1 * g2 + k1 * p2
    # back to the element matrix I' = D P' D
    out[0, 0], out[1, 1], out[2, 2] = b00, b11, b22
    out[0, 1] = out[1, 0] = -b01
    out[0, 2] = out[2, 0] = b02
    out[1, 2] = out[2, 1] = -b12
    # [k]x = [[0, -k2, k1], [k2, 0, -k0], [-k1, k0, 0]], row i signed by D_i D_3 = -D_i
    out[0, 3], out[0, 4], out[0, 5] = 0.0, -k2, k1
    out[1, 3], out[1, 4], out[1, 5] = -k2, 0.0, k0
    out[2, 3], out[2, 4], out[2, 5] = -k1, k0, 0.0
    for i in range(3):
        for j in range(3):
            out[3 + j, i] = out[i, 3 + j]
            out[3 + i, 3 + j] = mass if i == j else 0.0
