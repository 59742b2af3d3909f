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

The ten parameters are also a compact storage of a rigid inertia (``rigid_parameters``):
``(m, h1, h2, h3, Ī11, Ī22, Ī33, Ī12, Ī13, Ī23)``. Sums of rigid inertias are rigid, so the
composite inertias of CRBA are summed and applied (``rigid_apply``, eq. 15: 24
multiplications where the 6x6 element matrix takes 36) in this form.
"""

from __future__ import annotations

from .._jit import inline
from ._generated import motor_translation
from .layout import bivector, physical, quaternion, store_bivector


@inline
def _rotation(m):
    """Rotation matrix (row by row) of the rotor of a normalised motor."""
    w, x, y, z = quaternion(m)
    return (1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w),
            2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w),
            2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y))


@inline
def rigid_parameters(inertia):
    """The ten parameters ``(m, h, Ī11, Ī22, Ī33, Ī12, Ī13, Ī23)`` of a rigid inertia given
    as an element matrix: ``P = D I D``, ``Ī = P[:3, :3]``, ``[h]× = P[:3, 3:]``, m = P[3, 3]."""
    return (inertia[3, 3],  # m
            inertia[2, 4], inertia[0, 5], -inertia[1, 3],  # h, read from [h]×
            inertia[0, 0], inertia[1, 1], inertia[2, 2],  # diagonal of Ī
            -inertia[0, 1], inertia[0, 2], -inertia[1, 2])  # Ī12, Ī13, Ī23


@inline
def rigid_matrix(par, out):
    """The element matrix ``I = D P D`` of a rigid inertia given by its ten parameters."""
    mass, k0, k1, k2 = par[0], par[1], par[2], par[3]
    out[0, 0], out[1, 1], out[2, 2] = par[4], par[5], par[6]  # Ī11, Ī22, Ī33
    out[0, 1] = out[1, 0] = -par[7]  # D1 D2 Ī12
    out[0, 2] = out[2, 0] = par[8]  # D1 D3 Ī13
    out[1, 2] = out[2, 1] = -par[9]  # D2 D3 Ī23
    # [k]x = [[0, -k2, k1], [k2, 0, -k0], [-k1, k0, 0]], row i signed by D_i D_3 = -D_i
    out[0, 3], out[0, 4], out[0, 5] = 0.0, -k2, k1
    out[1, 3], out[1, 4], out[1, 5] = -k2, 0.0, k0
    out[2, 3], out[2, 4], out[2, 5] = -k1, k0, 0.0
    for i in range(3):
        for j in range(3):
            out[3 + j, i] = out[i, 3 + j]  # the transposed block [h]×ᵀ
            out[3 + i, 3 + j] = mass if i == j else 0.0  # m 1


@inline
def _store(par, out):
    """Write ten parameters (a tuple) into ``out``."""
    out[0], out[1], out[2], out[3], out[4] = par[0], par[1], par[2], par[3], par[4]
    out[5], out[6], out[7], out[8], out[9] = par[5], par[6], par[7], par[8], par[9]


@inline
def _transform(r, p0, p1, p2, par):
    """Ten parameters of ``M * I`` from those of I (an array or a tuple), M's rotation
    matrix r (row by row) and its translation p."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    mass, h0, h1, h2 = par[0], par[1], par[2], par[3]
    a00, a11, a22, a01, a02, a12 = par[4], par[5], par[6], par[7], par[8], par[9]
    # g = R h, k = h' = g + m p
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
    return (mass,  # m' = m
            k0, k1, k2,  # h' = R h + m p
            b00 + s - (p0 * g0 + k0 * p0),  # Ī'11
            b11 + s - (p1 * g1 + k1 * p1),  # Ī'22
            b22 + s - (p2 * g2 + k2 * p2),  # Ī'33
            b01 - (p0 * g1 + k0 * p1),  # Ī'12
            b02 - (p0 * g2 + k0 * p2),  # Ī'13
            b12 - (p1 * g2 + k1 * p2))  # Ī'23


@inline
def rigid_inertia_transform(m, inertia, out):
    """``out = M * I`` for a rigid inertia ``I`` (any inertia built from mass, com and a
    3x3 rotational inertia, or a sum of them), as element matrices. ``out`` may alias
    ``inertia``."""
    p0, p1, p2 = motor_translation(m)  # translation p of M
    rigid_matrix(_transform(_rotation(m), p0, p1, p2, rigid_parameters(inertia)), out)


@inline
def rigid_frame(m):
    """The rotation matrix R (row by row) and the translation p of a normalised motor M,
    built once for the moves below."""
    return _rotation(m), motor_translation(m)


@inline
def rigid_rotate(r, x, y, z):
    """``R (x, y, z)``, R row by row as ``rigid_frame`` gives it."""
    return (r[0] * x + r[1] * y + r[2] * z, r[3] * x + r[4] * y + r[5] * z,
            r[6] * x + r[7] * y + r[8] * z)


@inline
def rigid_motion(r, p, w0, w1, w2, v0, v1, v2):
    """The physical components ``(ω', v')`` of ``M X ~M`` (eq. 4) for the twist X of
    physical components ``(ω, v)``, from M's R and p (``rigid_frame``): the motion
    transform ``ω' = R ω``, ``v' = R v + p × ω'``, 24 multiplications where the general
    sandwich takes 72."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    p0, p1, p2 = p
    u0 = r00 * w0 + r01 * w1 + r02 * w2  # ω' = R ω
    u1 = r10 * w0 + r11 * w1 + r12 * w2
    u2 = r20 * w0 + r21 * w1 + r22 * w2
    return (u0, u1, u2,  # v' = R v + p × ω'
            r00 * v0 + r01 * v1 + r02 * v2 + p1 * u2 - p2 * u1,
            r10 * v0 + r11 * v1 + r12 * v2 + p2 * u0 - p0 * u2,
            r20 * v0 + r21 * v1 + r22 * v2 + p0 * u1 - p1 * u0)


@inline
def point_velocity(v0, v1, v2, w0, w1, w2, p0, p1, p2):
    """``v + ω × p``: the velocity of the point p under the twist whose angular velocity is
    ω and whose linear part v is the velocity of the point at the origin (world axes); with
    a coordinate's world twist, that coordinate's column of the point's Jacobian (C1)."""
    return (v0 + (w1 * p2 - w2 * p1), v1 + (w2 * p0 - w0 * p2), v2 + (w0 * p1 - w1 * p0))


@inline
def rigid_move_twist(r, p, x, out):
    """``out = M X ~M`` (eq. 4) for a twist X, from M's R and p (``rigid_frame``):
    ``rigid_motion`` on X's physical components."""
    w0, w1, w2, v0, v1, v2 = physical(x)  # ω and v of X
    u0, u1, u2, y0, y1, y2 = rigid_motion(r, p, w0, w1, w2, v0, v1, v2)
    store_bivector(u0, u1, u2, y0, y1, y2, out)


@inline
def rigid_move_inertia(r, p, inertia, out):
    """The ten parameters ``out`` of ``M * I`` (eq. 16) of a rigid inertia given as an
    element matrix, from M's R and p (``rigid_frame``)."""
    _store(_transform(r, p[0], p[1], p[2], rigid_parameters(inertia)), out)


@inline
def rigid_axis_transform(m, axis, inertia, s, out):
    """One motor, two moves: the twist ``s = M B ~M`` (eq. 4) of a joint axis B and the ten
    parameters ``out`` of ``M * I`` (eq. 16) of a rigid inertia, R and p built once."""
    r, p = rigid_frame(m)
    rigid_move_twist(r, p, axis, s)
    rigid_move_inertia(r, p, inertia, out)


@inline
def rigid_rate(par, v, out):
    """The ten parameters ``out`` of ``İ = V ×* I - I V×``, the rate of change of a rigid
    inertia (ten parameters ``par``) carried by the twist ``V``: with ``V = (ω, v)``,

        ṁ = 0,   ḣ = m v + ω × h,   İ = [ω]× Ī - Ī [ω]× + 2 (h·v) 1 - (v hᵀ + h vᵀ).

    A rigid inertia moved by motors stays one, so its rate has ten parameters too, and
    ``rigid_apply`` applies it: ``İ[U] = V × I[U] - I[V × U]``."""
    mass, h0, h1, h2 = par[0], par[1], par[2], par[3]
    a00, a11, a22, a01, a02, a12 = par[4], par[5], par[6], par[7], par[8], par[9]
    w0, w1, w2, v0, v1, v2 = physical(v)
    # X = [ω]× Ī, rows of [[0, -w2, w1], [w2, 0, -w0], [-w1, w0, 0]] times Ī
    x00 = -w2 * a01 + w1 * a02
    x01 = -w2 * a11 + w1 * a12
    x02 = -w2 * a12 + w1 * a22
    x10 = w2 * a00 - w0 * a02
    x11 = w2 * a01 - w0 * a12
    x12 = w2 * a02 - w0 * a22
    x20 = -w1 * a00 + w0 * a01
    x21 = -w1 * a01 + w0 * a11
    x22 = -w1 * a02 + w0 * a12
    hv = 2.0 * (h0 * v0 + h1 * v1 + h2 * v2)
    out[0] = 0.0
    out[1] = mass * v0 + w1 * h2 - w2 * h1  # ḣ = m v + ω × h
    out[2] = mass * v1 + w2 * h0 - w0 * h2
    out[3] = mass * v2 + w0 * h1 - w1 * h0
    out[4] = 2.0 * x00 + hv - 2.0 * v0 * h0  # İ = X + Xᵀ + 2 (h·v) 1 - (v hᵀ + h vᵀ)
    out[5] = 2.0 * x11 + hv - 2.0 * v1 * h1
    out[6] = 2.0 * x22 + hv - 2.0 * v2 * h2
    out[7] = x01 + x10 - (v0 * h1 + h0 * v1)
    out[8] = x02 + x20 - (v0 * h2 + h0 * v2)
    out[9] = x12 + x21 - (v1 * h2 + h1 * v2)


@inline
def motor_matrix(m, out):
    """The 4x4 homogeneous matrix of a normalised motor into ``out``."""
    r, p = rigid_frame(m)
    for i in range(3):
        for j in range(3):
            out[i, j] = r[3 * i + j]
        out[i, 3] = p[i]
        out[3, i] = 0.0
    out[3, 3] = 1.0


@inline
def rigid_apply(par, v):
    """``I[V]`` (eq. 15) for a rigid inertia given by its ten parameters: the physical
    ``n = Ī ω + h × v``, ``f = m v + ω × h``, on twist and wrench coefficients. Returns the
    wrench's six coefficients as a tuple (kept in registers by the caller)."""
    mass, h0, h1, h2 = par[0], par[1], par[2], par[3]
    w0, w1, w2, u0, u1, u2 = physical(v)  # ω and v
    return bivector(par[4] * w0 + par[7] * w1 + par[8] * w2 + h1 * u2 - h2 * u1,  # n
                    par[7] * w0 + par[5] * w1 + par[9] * w2 + h2 * u0 - h0 * u2,
                    par[8] * w0 + par[9] * w1 + par[6] * w2 + h0 * u1 - h1 * u0,
                    mass * u0 + w1 * h2 - w2 * h1,  # f
                    mass * u1 + w2 * h0 - w0 * h2,
                    mass * u2 + w0 * h1 - w1 * h0)
