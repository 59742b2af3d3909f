"""The compiled core of the constraints: J (C1, C2), γ (C3-C5), the Delassus matrix
``G = J M⁻¹ Jᵀ`` (C7) and the forces of constrained (C6-C8) and impulse (C9) dynamics, one
sample in one call (``docs/constraints.md``).

A list of constraints reaches compiled code as one float array (``pack``): a header
``[nc, nr]`` (constraints, rows), then ``ROW`` floats per constraint: its kind (0 a point,
1 a frame), the joints that carry its two frames (-1 the world, or a link fixed in it), frame
(0 ``"local"``, 1 ``"local_world_aligned"``), the corrector's ``Kp, Kd`` and the motors
``P₁, P₂`` of its two frames in those joints' frames (the link's placement and the
constraint's in it, composed when packed; in the world for -1). Twists here are
Pinocchio's ``[v, ω]`` at the world origin, as in the docs.

``constraint_core`` runs one ``mode``: ``SYSTEM`` (J, and γ with ``v``), ``DELASSUS``
(``G + μ I``), ``FORWARD`` (q̈, λ; C6-C8) or ``IMPULSE`` (v⁺, Λ; C9). ``settings`` holds
``[μ, iterations, accuracy, restitution]``; ``info`` receives ``[iterations, residual,
change, converged, conflicting row or -1]``. The entries below serve one sample (the C
entry of ``cgadyn._native`` and numba's dispatcher) and a batch (parallel over samples).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, prange

from .._jit import core, inline, native, parallel, serial
from .._views import data_pointer
from ..algorithms._checks import check_configuration
from ..algorithms._dense import cholesky, cholesky_substitute
from ..algorithms._pointers import SIGNATURE, packed_array
from ..algorithms._workspace import STACK_FLOATS, chunks, stack_buffer
from ..algorithms.kinematics import world_motors
from ..algorithms.ltdl import ltdl_lower_rows
from ..algorithms.minverse import move_axes_inertias
from ..algorithms.status import DELASSUS_SINGULAR, NONFINITE_RESULT, OK, SINGULAR, at_sample, fault
from ..kernels import motor_mul, motor_reverse
from ..kernels.layout import physical
from ..kernels.motors import motor_log, motor_normalize
from ..kernels.rigid import motor_matrix, point_velocity, rigid_frame, rigid_motion
from ..multibody.packed import unpack
from .articulated import (
    articulated_inertias,
    articulated_sweeps,
    body_motion,
    delassus_rows,
    row_forces,
    row_values,
    row_wrench,
)
from .work.core import workspace, workspace_size

HEAD, ROW = 2, 22
"""The pack's header ``[nc, nr]`` and the floats per constraint."""
KIND, BODY1, BODY2, FRAME, KP, KD, P1, P2 = 0, 1, 2, 3, 4, 5, 6, 14
"""Offsets within a constraint's floats."""
SYSTEM, DRIFT, DELASSUS, FORWARD, IMPULSE = range(5)
"""Modes: J; J and γ; G + μI; constrained dynamics; impulse dynamics."""
MU, ITERATIONS, ACCURACY, RESTITUTION = range(4)
INFO = 5
SINGULAR_PIVOT = 1e-12
"""G is singular where a pivot² of the Cholesky factor of its diagonal-scaled form falls
below this times its row count: the smallest eigenvalue of the rows so far is then below it
too (``solve.SINGULAR``, the threshold of the message)."""
CONFLICT = 1e-6
"""A proximal solve that ends with ``|G λ - b|∞ > CONFLICT · max(1, |b|∞)`` has no solution."""

WORKSPACE = {  # one sample's arrays, in order (tools/generate_workspaces.py); nr: the rows
    "M": ("n", 8),  # the joint motors
    "Mw": ("n", 8),  # the world motors
    "tmp8": (8,),
    "c": ("nq",),  # the joint motors' scalars (eq. 6)
    "s": ("nq",),
    "Sw": ("nv", 6),  # the world Jacobian's columns [v, ω]
    "Vb": ("n", 6),  # the bodies' world twists
    "Ab": ("n", 6),  # and accelerations at q̈ = 0 without gravity
    "E": (3, 8),  # the two ends' motors and the relative one
    "T": (2, 4, 4),  # the two ends' matrices
    "tw": (6,),
    "x": (6, 6),  # small vectors of an end
    "Sa": ("nv", 6),  # S_k in the world, as coefficients (C12)
    "Ih": ("n", 6, 6),  # the articulated inertias Î_j in the world
    "par": (10,),  # ten parameters of an inertia
    "U": ("nv", 6),  # U_j = Î_j[S_j]
    "Gd": ("nv", 6),  # D_j⁻¹ U_j
    "Dinv": ("nv", 6),  # D_j⁻¹, a row per coordinate
    "Dm": (6, 6),  # D_j
    "Dj": (6, 6),  # D_j⁻¹ of a joint of several coordinates
    "It": (6, 6),  # Ĩ_j
    "fr": ("n",),  # 1 for a free root whose Î_j holds its Cholesky factor (C12')
    "Es": ("n", 6),  # one column's wrenches, then accelerations (C13)
    "ys": ("nv",),
    "dq": ("nv",),  # M⁻¹ Jᵀ λ
    "Vw": ("n", 6),  # the bodies' world twists, as coefficients (C13)
    "Cw": ("n", 6),  # their velocity-product accelerations c_j
    "Aw": ("n", 6),  # their accelerations at q̈ = 0 without gravity
    "Eb": ("n", 6),  # ABA's bias wrenches, in the external sign
    "H": ("nv", "nv"),  # M, then its factors Lᵀ D L (before the rows': where nr may change)
    "J": ("nr", "nv"),
    "g": ("nr",),
    "LJt": ("nv", "nr"),  # L⁻ᵀ Jᵀ (L5), for the Delassus operator Wᵀ D⁻¹ W (L7)
    "C": ("nr", "nr"),  # the Cholesky factor
    "b": ("nr",),
    "y": ("nr",),
    "d": ("nr",),
    "af": ("nv",),  # the free acceleration
    "h": ("nv",),  # the bias forces h = C(q, v) v + g(q)
    "e": ("nr",),  # the position error of each row (C5): p₁ - p₂, or -log(~M₁ M₂)
    "W": (2, "nr", 6),  # each row's wrench on the body of each end (C12)
    "rb": (2, "nr"),  # those bodies, -1 the world
    "blocks": (2, "nr"),  # constraint c's rows: blocks[0, c] .. blocks[1, c]
    "act": ("n", "nr"),  # act[j, c]: 1 where constraint c's wrenches pass joint j
    "Ec": ("n", "nr", 6),  # the wrench of row r at joint j
    "Z": ("nv", "nr"),  # Z_j[r] = ⟨S_j, E_j[r]⟩
    "Y": (6, "nr"),  # D_j⁻¹ Z_j
    "Yt": ("nr", 6),  # L⁻¹ E_j at a free root (C12')
    "live": ("nr",),  # the constraints that pass a joint
}


@inline
def _world_columns(m, q, v, drift, k_):
    """``Sw`` the world twists of every coordinate (the world Jacobian's columns), and with
    ``drift`` the bodies' twists ``V_j = V_λ + S_j q̇_j`` and accelerations at q̈ = 0,
    ``A_j = A_λ + V_λ × S_j q̇_j`` (D2; C3)."""
    Sw, Vb, Ab, tw = k_.Sw, k_.Vb, k_.Ab, k_.tw
    world_motors(m, q, k_.c, k_.s, k_.tmp8, k_.M, k_.Mw)
    for j in range(m.n):
        rot, pos = rigid_frame(k_.Mw[j])  # R and p of M^w_j, once per joint
        for k in range(m.iv[j], m.iv[j + 1]):
            w0, w1, w2, v0, v1, v2 = physical(m.S[k])
            w0, w1, w2, v0, v1, v2 = rigid_motion(rot, pos, w0, w1, w2, v0, v1, v2)
            Sw[k, 0], Sw[k, 1], Sw[k, 2], Sw[k, 3], Sw[k, 4], Sw[k, 5] = v0, v1, v2, w0, w1, w2
    if not drift:
        return
    for j in range(m.n):
        p = m.parents[j]
        for i in range(6):
            tw[i] = 0.0
        for k in range(m.iv[j], m.iv[j + 1]):
            for i in range(6):
                tw[i] += Sw[k, i] * v[k]  # S_j q̇_j
        if p < 0:
            for i in range(6):
                Vb[j, i] = tw[i]
                Ab[j, i] = 0.0
            continue
        a1, a2, a3, w1, w2, w3 = Vb[p, 0], Vb[p, 1], Vb[p, 2], Vb[p, 3], Vb[p, 4], Vb[p, 5]
        Ab[j, 0] = Ab[p, 0] + w2 * tw[2] - w3 * tw[1] + a2 * tw[5] - a3 * tw[4]  # V_λ × S q̇
        Ab[j, 1] = Ab[p, 1] + w3 * tw[0] - w1 * tw[2] + a3 * tw[3] - a1 * tw[5]
        Ab[j, 2] = Ab[p, 2] + w1 * tw[1] - w2 * tw[0] + a1 * tw[4] - a2 * tw[3]
        Ab[j, 3] = Ab[p, 3] + w2 * tw[5] - w3 * tw[4]
        Ab[j, 4] = Ab[p, 4] + w3 * tw[3] - w1 * tw[5]
        Ab[j, 5] = Ab[p, 5] + w1 * tw[4] - w2 * tw[3]
        for i in range(6):
            Vb[j, i] = Vb[p, i] + tw[i]


@inline
def _end(m, cons, o, which, fixed, k_):
    """End ``which`` (0, 1) of the constraint at ``o``: its motor ``E[which]`` (``M^w_j P``,
    P in the frame of the joint j that carries it), matrix ``T[which]`` and body j (-1 for
    the world; its motor and matrix only with ``fixed``: the rows' wrenches and J never
    read a fixed end's, the drift does)."""
    E = k_.E
    body = int(cons[o + (BODY1 if which == 0 else BODY2)])
    at = o + (P1 if which == 0 else P2)
    if body < 0:
        if not fixed:
            return body
        for i in range(8):
            E[which, i] = cons[at + i]
    else:
        motor_mul(k_.Mw[body], cons[at:at + 8], E[which])  # M^w_j P
    motor_matrix(E[which], k_.T[which])
    return body


@inline
def _rotate(R, x, h, local):
    """``x[h:h+3] = Rᵀ x[h:h+3]`` where ``local``."""
    if local:
        x0, x1, x2 = x[h], x[h + 1], x[h + 2]
        for i in range(3):
            x[h + i] = R[0, i] * x0 + R[1, i] * x1 + R[2, i] * x2


@inline
def _add_columns(Sw, parents, iv, body, sign, p, size, r0, J, R, local):
    """Add ``sign`` times the columns of the body's world Jacobian seen at the point p
    (``shift(S, p) = [v + ω × p, ω]``, whose first three rows are the velocity of p) to
    rows ``r0 ..`` of J: the first three (C1), or all six (C2); each block of three in
    frame 1's axes (``Rᵀ``) where ``local``. Only the columns of the body's path are
    touched."""
    j = body
    while j >= 0:
        for k in range(iv[j], iv[j + 1]):
            w1, w2, w3 = Sw[k, 3], Sw[k, 4], Sw[k, 5]
            x1, x2, x3 = point_velocity(Sw[k, 0], Sw[k, 1], Sw[k, 2], w1, w2, w3, p[0], p[1],
                                        p[2])  # v + ω × p (C1)
            if local:
                x1, x2, x3 = (R[0, 0] * x1 + R[1, 0] * x2 + R[2, 0] * x3,
                              R[0, 1] * x1 + R[1, 1] * x2 + R[2, 1] * x3,
                              R[0, 2] * x1 + R[1, 2] * x2 + R[2, 2] * x3)
                if size == 6:
                    w1, w2, w3 = (R[0, 0] * w1 + R[1, 0] * w2 + R[2, 0] * w3,
                                  R[0, 1] * w1 + R[1, 1] * w2 + R[2, 1] * w3,
                                  R[0, 2] * w1 + R[1, 2] * w2 + R[2, 2] * w3)
            J[r0, k] += sign * x1
            J[r0 + 1, k] += sign * x2
            J[r0 + 2, k] += sign * x3
            if size == 6:  # C2
                J[r0 + 3, k] += sign * w1
                J[r0 + 4, k] += sign * w2
                J[r0 + 5, k] += sign * w3
        j = parents[j]


@inline
def _motion(Vb, Ab, body, x, row):
    """``x[row]`` the body's twist V, ``x[row + 1]`` its acceleration A (zero for the
    world)."""
    for i in range(6):
        x[row, i] = Vb[body, i] if body >= 0 else 0.0
        x[row + 1, i] = Ab[body, i] if body >= 0 else 0.0


@inline
def _shift(X, p, out):
    """``out[:3]`` the first three rows of ``shift(X, p)``: ``v - p × ω``."""
    out[0] = X[0] - (p[1] * X[5] - p[2] * X[4])
    out[1] = X[1] - (p[2] * X[3] - p[0] * X[5])
    out[2] = X[2] - (p[0] * X[4] - p[1] * X[3])


@inline
def _drift(m, cons, o, b1, b2, r0, g, k_):
    """``γ`` of the constraint at ``o`` into ``g[r0 ..]``: C3 (a point) or C4 (a frame), plus
    the corrector's terms (C5). The ends' matrices are in ``k_.T``."""
    x, T, E, tw = k_.x, k_.T, k_.E, k_.tw
    _motion(k_.Vb, k_.Ab, b1, x, 0)  # V₁, A₁
    _motion(k_.Vb, k_.Ab, b2, x, 2)  # V₂, A₂
    R = T[0]
    p1, p2 = T[0, :3, 3], T[1, :3, 3]
    kp, kd = cons[o + KP], cons[o + KD]
    local = cons[o + FRAME] == 0.0
    if cons[o + KIND] == 0.0:  # a point
        for e in range(2):
            p = p1 if e == 0 else p2
            V, A = x[2 * e], x[2 * e + 1]
            _shift(V, p, x[4])  # ṗ, the velocity of the point
            _shift(A, p, x[5])
            sg = 1.0 if e == 0 else -1.0
            w1, w2, w3, u1, u2, u3 = V[3], V[4], V[5], x[4, 0], x[4, 1], x[4, 2]
            g[r0] += sg * (x[5, 0] + w2 * u3 - w3 * u2 + kd * u1)  # a(p) + ω × ṗ (C3), Kd ṗ
            g[r0 + 1] += sg * (x[5, 1] + w3 * u1 - w1 * u3 + kd * u2)
            g[r0 + 2] += sg * (x[5, 2] + w1 * u2 - w2 * u1 + kd * u3)
        for i in range(3):
            k_.e[r0 + i] = p1[i] - p2[i]
            g[r0 + i] += kp * k_.e[r0 + i]  # Kp (p₁ - p₂) (C5)
        _rotate(R, g, r0, local)
        return
    for i in range(6):  # relative twist V₁ - V₂ into x[4], A₁ - A₂ (+ the bracket) into x[5]
        x[4, i] = x[0, i] - x[2, i]
        x[5, i] = x[1, i] - x[3, i]
    if local:  # + (V₁ - V₂) × V₂ (C4)
        a1, a2, a3, w1, w2, w3 = x[4, 0], x[4, 1], x[4, 2], x[4, 3], x[4, 4], x[4, 5]
        V = x[2]
        x[5, 0] += w2 * V[2] - w3 * V[1] + a2 * V[5] - a3 * V[4]
        x[5, 1] += w3 * V[0] - w1 * V[2] + a3 * V[3] - a1 * V[5]
        x[5, 2] += w1 * V[1] - w2 * V[0] + a1 * V[4] - a2 * V[3]
        x[5, 3] += w2 * V[5] - w3 * V[4]
        x[5, 4] += w3 * V[3] - w1 * V[5]
        x[5, 5] += w1 * V[4] - w2 * V[3]
    _shift(x[5], p1, tw)  # shift(·, p₁) (C4)
    _shift(x[4], p1, x[0])  # shift(V₁ - V₂, p₁) for Kd (C5)
    for i in range(3):
        g[r0 + i] = tw[i] + kd * x[0, i]
        g[r0 + 3 + i] = x[5, 3 + i] + kd * x[4, 3 + i]
    # the error -log(~M₁ M₂), the shortest twist in frame 1 (C5)
    motor_reverse(E[0], k_.tmp8)
    motor_mul(k_.tmp8, E[1], E[2])
    motor_normalize(E[2], k_.tmp8)
    sign = -1.0 if k_.tmp8[0] < 0.0 else 1.0  # of -M where its angle passes π (the same motion)
    for i in range(8):
        E[2, i] = sign * k_.tmp8[i]
    motor_log(E[2], tw)
    w1, w2, w3, v1, v2, v3 = physical(tw)
    x[1, 0], x[1, 1], x[1, 2], x[1, 3], x[1, 4], x[1, 5] = -v1, -v2, -v3, -w1, -w2, -w3
    if not local:  # its halves in the world's axes
        for h in range(0, 6, 3):
            e0, e1, e2 = x[1, h], x[1, h + 1], x[1, h + 2]
            for i in range(3):
                x[1, h + i] = R[i, 0] * e0 + R[i, 1] * e1 + R[i, 2] * e2
    _rotate(R, g, r0, local)
    _rotate(R, g, r0 + 3, local)
    for i in range(6):
        k_.e[r0 + i] = x[1, i]
        g[r0 + i] += kp * x[1, i]


@inline
def _row_wrenches(cons, o, b1, b2, r0, size, k_):
    """Rows ``r0 .. r0 + size`` of the constraint at ``o`` as wrenches on the bodies of its
    ends (C12): a force along each row's direction (frame 1's axes in ``"local"``, the
    world's otherwise) at each end's point (both at frame 1's origin for a frame), then a
    torque for a frame's last three. The ends' matrices are in ``k_.T``."""
    R, local = k_.T[0], cons[o + FRAME] == 0.0
    ends = 1 if b2 < 0 else 2  # the world takes no wrench
    for i in range(size):
        a = i % 3
        e1 = R[0, a] if local else (1.0 if a == 0 else 0.0)
        e2 = R[1, a] if local else (1.0 if a == 1 else 0.0)
        e3 = R[2, a] if local else (1.0 if a == 2 else 0.0)
        for end in range(ends):
            p = k_.T[end if size == 3 else 0, :3, 3]
            row_wrench(p, e1, e2, e3, i < 3, k_.W[end, r0 + i])
        k_.rb[0, r0 + i] = b1
        k_.rb[1, r0 + i] = b2
    k_.blocks[0, (o - HEAD) // ROW] = r0
    k_.blocks[1, (o - HEAD) // ROW] = r0 + size


@inline
def constraint_wrenches(m, cons, drift, g, k_):
    """The rows' wrenches and bodies (``_row_wrenches``) of every constraint, without J:
    what C12 and C13 need; with ``drift`` also γ (C3-C5) from the bodies' twists and
    accelerations in ``k_.Vb``, ``k_.Ab``. The world motors are in ``k_.Mw``."""
    r0 = 0
    for c in range(int(cons[0])):
        o = HEAD + ROW * c
        size = 3 if cons[o + KIND] == 0.0 else 6
        b1 = _end(m, cons, o, 0, True, k_)
        b2 = _end(m, cons, o, 1, drift, k_)
        _row_wrenches(cons, o, b1, b2, r0, size, k_)
        if drift:
            for i in range(size):
                g[r0 + i] = 0.0
            _drift(m, cons, o, b1, b2, r0, g, k_)
        r0 += size


@inline
def _physical_motion(m, k_):
    """``k_.Vb``, ``k_.Ab``: the bodies' world twists and accelerations at q̈ = 0 of
    ``body_motion`` as Pinocchio's arrays ``[v, ω]``, which C3-C5 read."""
    for j in range(m.n):
        w1, w2, w3, v1, v2, v3 = physical(k_.Vw[j])
        k_.Vb[j, 0], k_.Vb[j, 1], k_.Vb[j, 2] = v1, v2, v3
        k_.Vb[j, 3], k_.Vb[j, 4], k_.Vb[j, 5] = w1, w2, w3
        w1, w2, w3, v1, v2, v3 = physical(k_.Aw[j])
        k_.Ab[j, 0], k_.Ab[j, 1], k_.Ab[j, 2] = v1, v2, v3
        k_.Ab[j, 3], k_.Ab[j, 4], k_.Ab[j, 5] = w1, w2, w3


@inline
def constraint_system(m, cons, q, v, drift, J, g, k_):
    """J (nr, nv) (C1, C2) and, with ``drift``, γ (nr) (C3-C5)."""
    nc = int(cons[0])
    _world_columns(m, q, v, drift, k_)
    for r in range(J.shape[0]):
        g[r] = 0.0
        for k in range(m.nv):
            J[r, k] = 0.0
    r0 = 0
    for c in range(nc):
        o = HEAD + ROW * c
        size = 3 if cons[o + KIND] == 0.0 else 6
        b1 = _end(m, cons, o, 0, True, k_)
        b2 = _end(m, cons, o, 1, drift, k_)
        p1 = k_.T[0, :3, 3]
        p2 = k_.T[1, :3, 3] if size == 3 else p1
        local = cons[o + FRAME] == 0.0
        _add_columns(k_.Sw, m.parents, m.iv, b1, 1.0, p1, size, r0, J, k_.T[0], local)
        _add_columns(k_.Sw, m.parents, m.iv, b2, -1.0, p2, size, r0, J, k_.T[0], local)
        if drift:
            _drift(m, cons, o, b1, b2, r0, g, k_)
        r0 += size


@inline
def _delassus(m, J, k_, G):
    """``G = J M⁻¹ Jᵀ`` (C7) from M's factors ``H = Lᵀ D L`` as ``Wᵀ D⁻¹ W``, ``W = L⁻ᵀ
    Jᵀ`` by the first of the two sweeps alone (L5, L7): a rank-one term per coordinate over
    the rows whose column of W it reaches (W keeps Jᵀ's pattern along the tree, nonzero
    on the coordinates that support a row's bodies). ``M⁻¹ Jᵀ`` itself is never formed: a
    caller that needs ``M⁻¹ Jᵀ λ`` solves for the one column ``Jᵀ λ`` (L5, L6)."""
    nr, nv = J.shape[0], m.nv
    W, H = k_.LJt, k_.H
    for k in range(nv):
        for r in range(nr):
            W[k, r] = J[r, k]
    ltdl_lower_rows(m, H, W)  # W = L⁻ᵀ Jᵀ (L5)
    for r in range(nr):
        for s in range(r + 1):
            G[r, s] = 0.0
    for k in range(nv):  # G += W[k]ᵀ W[k] / D_k, its lower triangle (L7)
        w, d = W[k], 1.0 / H[k, k]
        for r in range(nr):
            x = w[r] * d
            if x != 0.0:
                for s in range(r + 1):
                    G[r, s] += x * w[s]
    for r in range(nr):
        for s in range(r):
            G[s, r] = G[r, s]


@inline
def _finite(G, n):
    """Whether the n x n matrix G is finite: ``Σ 0·G_rs`` is 0 unless an entry is inf or NaN
    (a branch-free sum where a test per entry would branch n² times)."""
    acc = 0.0
    for r in range(n):
        for s in range(n):
            acc += 0.0 * G[r, s]
    return acc == 0.0


@inline
def _residual(G, lam, b, n):
    """``|G λ - b|∞`` and its row."""
    worst, row = 0.0, 0
    for r in range(n):
        acc = -b[r]
        for s in range(n):
            acc += G[r, s] * lam[s]
        if abs(acc) > worst or r == 0:
            worst, row = abs(acc), r
    return worst, row


@inline
def solve_forces(G, b, settings, lam, info, k_):
    """``λ`` of ``G λ = b`` (C7): with ``μ = 0`` once, through the Cholesky factor of the
    diagonal-scaled G (``DELASSUS_SINGULAR`` at the first row that makes it singular); with
    ``μ > 0`` by the proximal iterations ``(G + μ I) λ_{k+1} = b + μ λ_k`` from ``λ₀ = 0``
    (C8). ``info`` as in the module's docstring; a status."""
    n = b.shape[0]
    C, y, d = k_.C, k_.y, k_.d
    info[4] = -1.0
    if n == 0:
        info[0], info[1], info[2], info[3] = 0.0, 0.0, 0.0, 1.0
        return OK
    bmax = 0.0
    for r in range(n):
        bmax = max(bmax, abs(b[r]))
    if not _finite(G, n) or not math.isfinite(bmax):
        return fault(NONFINITE_RESULT, -1)
    mu, iterations, accuracy = settings[MU], int(settings[ITERATIONS]), settings[ACCURACY]
    if mu == 0.0:
        scale = 0.0
        for r in range(n):
            d[r] = math.sqrt(max(G[r, r], 0.0))
            scale = max(scale, d[r])
        scale = max(scale, 1e-300)
        for r in range(n):
            if d[r] <= 1e-12 * scale:
                return fault(DELASSUS_SINGULAR, r)
        for r in range(n):
            d[r] = 1.0 / d[r]  # the scaling's reciprocals
        for r in range(n):
            for s in range(r + 1):
                C[r, s] = G[r, s] * (d[r] * d[s])  # the lower half: what cholesky reads
        row = cholesky(C, n, SINGULAR_PIVOT)
        if row >= 0:
            return fault(DELASSUS_SINGULAR, row)
        for r in range(n):
            lam[r] = b[r] * d[r]
        cholesky_substitute(C, n, lam)
        change = 0.0
        for r in range(n):
            lam[r] *= d[r]
            change = max(change, abs(lam[r]))
        res, _ = _residual(G, lam, b, n)
        info[0], info[1], info[2], info[3] = 1.0, res, change, 1.0
        return OK
    for r in range(n):
        lam[r] = 0.0
        for s in range(n):
            C[r, s] = G[r, s] + (mu if r == s else 0.0)
    if cholesky(C, n, 0.0) >= 0:
        return fault(DELASSUS_SINGULAR, -1)
    res = change = math.inf
    row = 0
    it = 0
    while it < iterations:
        it += 1
        for r in range(n):
            y[r] = b[r] + mu * lam[r]
        cholesky_substitute(C, n, y)  # (G + μ I) λ_{k+1} = b + μ λ_k (C8)
        change = 0.0
        for r in range(n):
            change = max(change, abs(y[r] - lam[r]))
            lam[r] = y[r]
        res, row = _residual(G, lam, b, n)
        if res <= accuracy or change <= accuracy:
            break
    converged = res <= accuracy or change <= accuracy
    info[0], info[1], info[2], info[3] = float(it), res, change, 1.0 if converged else 0.0
    if not converged and res > CONFLICT * max(1.0, bmax):
        info[4] = float(row)
    return OK


@inline
def _articulated_delassus(m, cons, q, v, f, mode, g, G, k_):
    """What every mode but J's computes first: the world motors, S_k and I_j (eqs. 4, 16);
    for the dynamics the bodies' motion at q̈ = 0 and ABA's bias; the rows' wrenches (and γ
    for ``FORWARD``), the articulated inertias (M1, M2) and G by C12. A status."""
    status = check_configuration(m, q)
    if status != OK:
        return status
    world_motors(m, q, k_.c, k_.s, k_.tmp8, k_.M, k_.Mw)
    move_axes_inertias(m, k_.Mw, k_.par, k_.Sa, k_.Ih)  # S_k, I_j in the world (eqs. 4, 16)
    if mode != DELASSUS:
        body_motion(m, v, f, k_, mode == FORWARD)  # V_j, c_j, A_j at q̈ = 0; ABA's bias
        _physical_motion(m, k_)
    constraint_wrenches(m, cons, mode == FORWARD, g, k_)
    j = articulated_inertias(m, k_)  # M1, M2
    if j >= 0:
        return fault(SINGULAR, j)
    delassus_rows(m, int(cons[0]), int(cons[1]), k_, G)  # C12
    return OK


@core
def delassus_core(m, cons, q, settings, G, work):
    """``G + μ I`` of one sample (``DELASSUS``); a status. A function of its own, apart
    from the dynamics' ``constraint_core``: compiled alone, the Delassus pass is faster."""
    nr = int(cons[1])
    k_ = workspace(data_pointer(work), m, nr)
    status = _articulated_delassus(m, cons, q, q, k_.Es, DELASSUS, k_.g, G, k_)
    if status != OK:
        return status
    for r in range(nr):
        G[r, r] += settings[MU]
    if not _finite(G, nr):
        return fault(NONFINITE_RESULT, -1)
    return OK


@core
def constraint_core(m, cons, q, v, tau, settings, mode, J, g, G, a, lam, info, work, f):
    """One sample of ``mode`` (the module's docstring); a status. ``f`` the external
    wrenches on the bodies (n, 6) in their frames, as ``aba``'s, or (0, 6) for none."""
    nr = int(cons[1])
    k_ = workspace(data_pointer(work), m, nr)
    if mode == SYSTEM or mode == DRIFT:
        constraint_system(m, cons, q, v, mode == DRIFT, J, g, k_)
        for r in range(nr):
            if not math.isfinite(g[r]):
                return fault(NONFINITE_RESULT, -1)
            for k in range(m.nv):
                if not math.isfinite(J[r, k]):
                    return fault(NONFINITE_RESULT, -1)
        return OK
    if mode == DELASSUS:
        return delassus_core(m, cons, q, settings, G, work)
    return dynamics_core(m, cons, q, v, tau, settings, mode, G, a, lam, info, work, f)


@core
def dynamics_core(m, cons, q, v, tau, settings, mode, G, a, lam, info, work, f):
    """One sample of ``FORWARD`` or ``IMPULSE``: ``a`` the accelerations or the velocities
    after the impact, ``lam`` the forces or impulses, ``info`` the solve's; a status. ``G``
    the Delassus matrix, as scratch. A function of its own, as ``delassus_core`` is."""
    nr = int(cons[1])
    k_ = workspace(data_pointer(work), m, nr)
    g = k_.g
    status = _articulated_delassus(m, cons, q, v, f, mode, g, G, k_)
    if status != OK:
        return status
    b, E = k_.b, k_.Es
    if mode == FORWARD:
        for j in range(m.n):
            for i in range(6):
                E[j, i] = k_.Eb[j, i]
        articulated_sweeps(m, tau, E, True, m.gravity, k_, k_.af)  # q̈_f, ABA (C13)
        for j in range(m.n):  # the bodies' twists of q̈_f alone: A_j - g - Σ c (C13)
            for i in range(6):
                E[j, i] -= m.gravity[i] + k_.Aw[j, i]
        row_values(m, nr, E, k_, b)  # J q̈_f
        for r in range(nr):
            b[r] = -g[r] - b[r]  # b = -γ - J q̈_f (C7)
    else:
        e = settings[RESTITUTION]
        for k in range(m.nv):
            k_.af[k] = v[k]
        row_values(m, nr, k_.Vw, k_, b)  # J v⁻
        for r in range(nr):
            b[r] = -(1.0 + e) * b[r]  # b = -(1 + e) J v⁻ (C9)
    status = solve_forces(G, b, settings, lam, info, k_)
    if status != OK:
        return status
    row_forces(m, nr, lam, k_, E)  # Jᵀ λ as wrenches on the bodies
    for k in range(m.nv):
        k_.h[k] = 0.0
    articulated_sweeps(m, k_.h, E, False, m.gravity, k_, k_.dq)  # M⁻¹ Jᵀ λ (C13)
    for i in range(m.nv):  # q̈ = q̈_f + M⁻¹ Jᵀ λ (C7), v⁺ = v⁻ + M⁻¹ Jᵀ Λ (C9)
        a[i] = k_.af[i] + k_.dq[i]
    for i in range(m.nv):
        if not math.isfinite(a[i]):
            return fault(NONFINITE_RESULT, -1)
    return OK


@serial
def constraint_single(packed, cons, q, v, tau, settings, mode, J, g, G, a, lam, info):
    """One sample of ``constraint_core``, its workspace on this call's stack (on the heap
    above ``STACK_FLOATS``)."""
    m = unpack(packed)
    size = workspace_size(m.n, m.nq, m.nv, m.nl, int(cons[1]))
    buf = stack_buffer(size) if size <= STACK_FLOATS else np.empty(size)
    if mode == DELASSUS:
        return delassus_core(m, cons, q, settings, G, buf)
    return constraint_core(m, cons, q, v, tau, settings, mode, J, g, G, a, lam, info, buf,
                           buf[:0].reshape((0, 6)))


@native(SIGNATURE)
def constraint_native(pk, x, f, nf, o, options):
    """One sample on raw pointers, for ``cgadyn._native`` (``delassus_core`` or
    ``constraint_core``, its workspace on this call's stack): inputs ``cons, q, v,
    tau, settings``, option ``mode``; outputs ``J, γ`` (``SYSTEM``, ``DRIFT``), ``G``
    (``DELASSUS``) or ``q̈ (or v⁺), λ, info`` (``FORWARD``, ``IMPULSE``)."""
    packed = packed_array(pk)
    m = unpack(packed)
    head = carray(x[0], (HEAD,))
    nc, nr = int(head[0]), int(head[1])
    cons = carray(x[0], (HEAD + ROW * nc,))
    q = carray(x[1], (m.nq,))
    v = carray(x[2], (m.nv,))
    tau = carray(x[3], (m.nv,))
    settings = carray(x[4], (4,))
    mode = options[0]
    size = workspace_size(m.n, m.nq, m.nv, m.nl, nr)
    buf = stack_buffer(size) if size <= STACK_FLOATS else np.empty(size)
    if mode == DELASSUS:
        return delassus_core(m, cons, q, settings, carray(o[0], (nr, nr)), buf)
    # the outputs a mode does not return, as scratch on this call's stack (no allocation)
    k = nr * nr + m.nv + nr + INFO
    spare = stack_buffer(k) if k <= STACK_FLOATS else np.empty(k)
    G = spare[:nr * nr].reshape((nr, nr))  # views that keep a heap ``spare`` alive
    o1 = nr * nr
    a = spare[o1:o1 + m.nv]
    lam = spare[o1 + m.nv:o1 + m.nv + nr]
    info = spare[o1 + m.nv + nr:o1 + m.nv + nr + INFO]
    f0 = buf[:0].reshape((0, 6))
    if mode == SYSTEM or mode == DRIFT:
        return constraint_core(m, cons, q, v, tau, settings, mode, carray(o[0], (nr, m.nv)),
                               carray(o[1], (nr,)), G, a, lam, info, buf, f0)
    return dynamics_core(m, cons, q, v, tau, settings, mode, G, carray(o[0], (m.nv,)),
                         carray(o[1], (nr,)), carray(o[2], (INFO,)), buf, f0)


@parallel
def constraint_batch(packed, cons, q, v, tau, settings, mode, J, g, G, a, lam, info,
                     threads):
    """(B, ...) samples of ``constraint_core`` in parallel chunks; a status."""
    m = unpack(packed)
    batch = q.shape[0]
    nr = int(cons[1])
    size = workspace_size(m.n, m.nq, m.nv, m.nl, nr)
    starts, stops = chunks(batch, threads)
    status = np.zeros(starts.shape[0], dtype=np.int64)
    for c in prange(starts.shape[0]):
        mc = unpack(packed)
        work = np.empty(size)
        f0 = np.empty((0, 6))
        for b in range(starts[c], stops[c]):
            s = constraint_core(mc, cons, q[b], v[b], tau[b], settings, mode, J[b], g[b],
                                G[b], a[b], lam[b], info[b], work, f0)
            if s != OK:
                status[c] = at_sample(s, b)
                break
    for c in range(starts.shape[0]):
        if status[c] != OK:
            return status[c]
    return OK
