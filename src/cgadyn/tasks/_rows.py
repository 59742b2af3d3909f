"""Residual rows and their Jacobian rows of one geometric task, in compiled code.

A task compares an object carried by a link with a target object in the world. The link
frame's motor ``M^w_L`` (eq. 5) times a constant tool motor P gives the tool frame
``F = M^w_L P`` (rotation R, origin p); the carried object X, given in the tool frame, is in
the world ``F X ~F`` (eq. 4). A velocity coordinate k moves it by the commutator with its
world twist, ``∂(F X ~F)/∂q_k = S^w_k × (F X ~F)`` (since ``∂F/∂q_k = ½ S^w_k F``); on the
Euclidean coordinates that is ``ẋ = v_k + ω_k × (x - p)`` for a point, with ``(v_k, ω_k)``
the column k of the tool frame's Jacobian at p, world axes (``tool_jacobian``).

A task is a row of ``TASK_SIZE`` floats::

    [kind, link, weight, 0 | P (8) | carried object (8) | target (16)]

(a cooperative task of two links, ``_cooperative``, puts the second link in the fourth
float and its tool motor in the carried object's place)

and each kind's residual and its geometric meaning:

=============  ===  ==========================================================================
kind           dim  residual (x = the carried point c in the world, n, u unit)
=============  ===  ==========================================================================
POINT          3    ``x - t``: the point onto the target point t
PLANE          1    ``n·x - d``: the signed distance of the point to the plane ``n·y = d``
LINE           3    ``u × (x - a)``: the moment of the point about the line (a, u); its norm
                    is the distance to the line
SPHERE         1    ``|x - c| - ρ``: the signed distance to the sphere (c, ρ)
CIRCLE         2    ``(n·(x - c), |(x - c)_⊥n| - ρ)``: off the circle's plane, off its radius
LINE_LINE      6    ``(w' - u, b' × w' - a × u)``: the carried line (b, w) onto the target
                    line (a, u), direction and moment (Plücker coordinates)
PLANE_PLANE    4    ``(n' - n, d' - d)``: the carried plane onto the target plane
ORIENTATION    3    ``log(R_tᵀ R)``: the rotation from the target's to the tool's
POSE           6    ``log6(~M_t F)``: the motor logarithm of the error, Pinocchio's
                    ``log6(oMdes⁻¹ oMf)`` as ``(v, ω)``
=============  ===  ==========================================================================

The Jacobian of POSE is ``Jlog6 · J_local`` and of ORIENTATION ``Jlog3 · Rᵀ J_ω`` (``_lie``);
every row is multiplied by the task's weight.
"""

from __future__ import annotations

import math

from .._jit import inline
from ..algorithms.kinematics import link_motor
from ..kernels import motor_log, motor_mul, motor_reverse, twist_sandwich
from ..kernels.layout import physical
from ..kernels.rigid import point_velocity, rigid_frame, rigid_rotate
from ._lie import jlog3, jlog6

(POINT, PLANE, LINE, SPHERE, CIRCLE, LINE_LINE, PLANE_PLANE, ORIENTATION, POSE, RELATIVE,
 ABSOLUTE) = range(11)
KIND_NAMES = ("point", "plane", "line", "sphere", "circle", "line_line", "plane_plane",
              "orientation", "pose", "relative", "absolute")
DIMS = (3, 1, 3, 1, 2, 6, 4, 3, 6, 6, 6)
"""Residual rows of each kind; the last two are the cooperative tasks of two links
(``_cooperative``)."""

TASK_SIZE = 36
KIND, LINK, WEIGHT, SECOND = 0, 1, 2, 3
TOOL, CARRIED, TARGET = 4, 12, 20
"""The offsets of the tool motor P, the carried object and the target in a task row."""


@inline
def task_dim(kind):
    """Residual rows of a task kind."""
    if kind == POINT or kind == LINE or kind == ORIENTATION:
        return 3
    if kind == PLANE or kind == SPHERE:
        return 1
    if kind == CIRCLE:
        return 2
    if kind == PLANE_PLANE:
        return 4
    return 6


@inline
def tool_jacobian(m, Mw, link, p0, p1, p2, tw, Jf):
    """``Jf`` (6, nv): column k the velocity ``(v, ω)`` of the point p of the link's body and
    the angular velocity, world axes, from the world twist ``S^w_k = M^w_j S_k ~M^w_j``
    (eq. 4) of every coordinate on the path from the root; zero elsewhere."""
    for i in range(6):
        for k in range(m.nv):
            Jf[i, k] = 0.0
    j = m.link_joint[link]
    while j >= 0:
        for k in range(m.iv[j], m.iv[j + 1]):
            twist_sandwich(Mw[j], m.S[k], tw)
            w0, w1, w2, v0, v1, v2 = physical(tw)  # v at the world origin
            Jf[0, k], Jf[1, k], Jf[2, k] = point_velocity(v0, v1, v2, w0, w1, w2, p0, p1, p2)
            Jf[3, k], Jf[4, k], Jf[5, k] = w0, w1, w2
        j = m.parents[j]


@inline
def _to_local(R, Jf):
    """Every column ``(v, ω)`` of ``Jf`` to ``(Rᵀ v, Rᵀ ω)``: world axes to the frame's."""
    for k in range(Jf.shape[1]):
        for h in (0, 3):
            y0, y1, y2 = Jf[h, k], Jf[h + 1, k], Jf[h + 2, k]
            Jf[h, k] = R[0] * y0 + R[3] * y1 + R[6] * y2
            Jf[h + 1, k] = R[1] * y0 + R[4] * y1 + R[7] * y2
            Jf[h + 2, k] = R[2] * y0 + R[5] * y1 + R[8] * y2


@inline
def local_jacobian(m, Mw, link, F, tw, Jf):
    """``Jf`` (6, nv): the body Jacobian of the frame F carried by the link, rows
    ``[v, ω]`` in F's own axes (Pinocchio's LOCAL frame Jacobian)."""
    R, p = rigid_frame(F)
    tool_jacobian(m, Mw, link, p[0], p[1], p[2], tw, Jf)
    _to_local(R, Jf)


@inline
def _point_rate(Jf, k, c0, c1, c2):
    """``ẋ = v + ω × c`` of the point at ``p + c`` for coordinate k."""
    return point_velocity(Jf[0, k], Jf[1, k], Jf[2, k], Jf[3, k], Jf[4, k], Jf[5, k], c0, c1,
                          c2)


@inline
def task_rows(m, Mw, task, r, J, o, wk):
    """Rows ``o .. o + dim`` of the residual ``r`` and Jacobian ``J`` (·, nv) of one task
    row (module docstring); ``Mw`` the joints' world motors; ``wk`` the stack's workspace
    (``_stack.WORKSPACE``)."""
    kind = int(task[KIND])
    link = int(task[LINK])
    w = task[WEIGHT]
    L, F, E, tw, xi, Jf, J6, t = wk.L, wk.F, wk.E, wk.tw, wk.xi, wk.Jf, wk.J6, wk.t
    link_motor(m, Mw, link, L)
    motor_mul(L, task[TOOL:TOOL + 8], F)  # F = M^w_L P
    R, p = rigid_frame(F)
    p0, p1, p2 = p
    tool_jacobian(m, Mw, link, p0, p1, p2, tw, Jf)
    a = task[CARRIED:CARRIED + 8]
    g = task[TARGET:TARGET + 16]
    nv = m.nv
    if kind <= CIRCLE:
        c0, c1, c2 = rigid_rotate(R, a[0], a[1], a[2])  # x - p
        x0, x1, x2 = p0 + c0, p1 + c1, p2 + c2
        if kind == POINT:
            r[o], r[o + 1], r[o + 2] = w * (x0 - g[0]), w * (x1 - g[1]), w * (x2 - g[2])
            for k in range(nv):
                d0, d1, d2 = _point_rate(Jf, k, c0, c1, c2)
                J[o, k], J[o + 1, k], J[o + 2, k] = w * d0, w * d1, w * d2
        elif kind == PLANE:
            r[o] = w * (g[0] * x0 + g[1] * x1 + g[2] * x2 - g[3])
            for k in range(nv):
                d0, d1, d2 = _point_rate(Jf, k, c0, c1, c2)
                J[o, k] = w * (g[0] * d0 + g[1] * d1 + g[2] * d2)
        elif kind == LINE:
            u0, u1, u2 = g[3], g[4], g[5]
            e0, e1, e2 = x0 - g[0], x1 - g[1], x2 - g[2]
            r[o] = w * (u1 * e2 - u2 * e1)
            r[o + 1] = w * (u2 * e0 - u0 * e2)
            r[o + 2] = w * (u0 * e1 - u1 * e0)
            for k in range(nv):
                d0, d1, d2 = _point_rate(Jf, k, c0, c1, c2)
                J[o, k] = w * (u1 * d2 - u2 * d1)
                J[o + 1, k] = w * (u2 * d0 - u0 * d2)
                J[o + 2, k] = w * (u0 * d1 - u1 * d0)
        elif kind == SPHERE:
            e0, e1, e2 = x0 - g[0], x1 - g[1], x2 - g[2]
            dist = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            r[o] = w * (dist - g[3])
            s = 1.0 / dist if dist > 0.0 else 0.0
            for k in range(nv):
                d0, d1, d2 = _point_rate(Jf, k, c0, c1, c2)
                J[o, k] = w * s * (e0 * d0 + e1 * d1 + e2 * d2)
        else:  # CIRCLE
            n0, n1, n2 = g[3], g[4], g[5]
            e0, e1, e2 = x0 - g[0], x1 - g[1], x2 - g[2]
            h = n0 * e0 + n1 * e1 + n2 * e2
            f0, f1, f2 = e0 - h * n0, e1 - h * n1, e2 - h * n2
            rad = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
            s = 1.0 / rad if rad > 0.0 else 0.0
            r[o], r[o + 1] = w * h, w * (rad - g[6])
            for k in range(nv):
                d0, d1, d2 = _point_rate(Jf, k, c0, c1, c2)
                J[o, k] = w * (n0 * d0 + n1 * d1 + n2 * d2)
                J[o + 1, k] = w * s * (f0 * d0 + f1 * d1 + f2 * d2)
    elif kind == LINE_LINE:
        b0, b1, b2 = rigid_rotate(R, a[0], a[1], a[2])
        b0, b1, b2 = p0 + b0, p1 + b1, p2 + b2
        v0, v1, v2 = rigid_rotate(R, a[3], a[4], a[5])  # w'
        u0, u1, u2 = g[3], g[4], g[5]
        r[o], r[o + 1], r[o + 2] = w * (v0 - u0), w * (v1 - u1), w * (v2 - u2)
        r[o + 3] = w * ((b1 * v2 - b2 * v1) - (g[1] * u2 - g[2] * u1))
        r[o + 4] = w * ((b2 * v0 - b0 * v2) - (g[2] * u0 - g[0] * u2))
        r[o + 5] = w * ((b0 * v1 - b1 * v0) - (g[0] * u1 - g[1] * u0))
        for k in range(nv):
            w0, w1, w2 = Jf[3, k], Jf[4, k], Jf[5, k]
            dv0, dv1, dv2 = w1 * v2 - w2 * v1, w2 * v0 - w0 * v2, w0 * v1 - w1 * v0  # ω × w'
            db0, db1, db2 = _point_rate(Jf, k, b0 - p0, b1 - p1, b2 - p2)
            J[o, k], J[o + 1, k], J[o + 2, k] = w * dv0, w * dv1, w * dv2
            J[o + 3, k] = w * (db1 * v2 - db2 * v1 + b1 * dv2 - b2 * dv1)
            J[o + 4, k] = w * (db2 * v0 - db0 * v2 + b2 * dv0 - b0 * dv2)
            J[o + 5, k] = w * (db0 * v1 - db1 * v0 + b0 * dv1 - b1 * dv0)
    elif kind == PLANE_PLANE:
        n0, n1, n2 = rigid_rotate(R, a[0], a[1], a[2])  # n'
        dd = a[3] + n0 * p0 + n1 * p1 + n2 * p2  # d' = d_l + n'·p
        r[o], r[o + 1], r[o + 2] = w * (n0 - g[0]), w * (n1 - g[1]), w * (n2 - g[2])
        r[o + 3] = w * (dd - g[3])
        for k in range(nv):
            w0, w1, w2 = Jf[3, k], Jf[4, k], Jf[5, k]
            dn0, dn1, dn2 = w1 * n2 - w2 * n1, w2 * n0 - w0 * n2, w0 * n1 - w1 * n0
            J[o, k], J[o + 1, k], J[o + 2, k] = w * dn0, w * dn1, w * dn2
            J[o + 3, k] = w * (dn0 * p0 + dn1 * p1 + dn2 * p2
                               + n0 * Jf[0, k] + n1 * Jf[1, k] + n2 * Jf[2, k])
    else:  # ORIENTATION or POSE: the error motor E = ~M_t F
        motor_reverse(g[0:8], L)
        motor_mul(L, F, E)
        if E[0] < 0.0:  # -E is the same motion: the rotation angle in [0, π]
            for i in range(8):
                E[i] = -E[i]
        motor_log(E, tw)
        w0, w1, w2, v0, v1, v2 = physical(tw)
        xi[0], xi[1], xi[2], xi[3], xi[4], xi[5] = v0, v1, v2, w0, w1, w2
        _to_local(R, Jf)
        if kind == ORIENTATION:
            jlog3(w0, w1, w2, t[0])
            r[o], r[o + 1], r[o + 2] = w * w0, w * w1, w * w2
            for i in range(3):
                for k in range(nv):
                    J[o + i, k] = w * (t[0, i, 0] * Jf[3, k] + t[0, i, 1] * Jf[4, k]
                                       + t[0, i, 2] * Jf[5, k])
        else:
            jlog6(xi, J6, t)
            for i in range(6):
                r[o + i] = w * xi[i]
            for k in range(nv):
                for i in range(3):
                    acc = 0.0
                    for h in range(6):
                        acc += J6[i, h] * Jf[h, k]
                    J[o + i, k] = w * acc
                for i in range(3, 6):  # Jlog6's lower left block is zero
                    acc = 0.0
                    for h in range(3, 6):
                        acc += J6[i, h] * Jf[h, k]
                    J[o + i, k] = w * acc
