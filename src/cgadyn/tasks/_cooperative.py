"""The cooperative dual-task space of two end-effectors in compiled code (Adorno's, in motors).

With ``F_1``, ``F_2`` the world motors of the two tool frames (eq. 5, ``F = M^w_L P``), the
relative motor and the absolute motor are

    M_r = ~F_1 F_2                (the second hand seen from the first)              (C1)
    M_a = F_1 M_r^½ = F_1 exp(V_r / 4)      (halfway between the hands; ``M_r = exp(V_r / 2)``,
                                             eq. 6, ``ξ_r = (v, ω)`` of ``V_r``)      (C2)

and their body velocities follow from the tools' local Jacobians ``J_1, J_2`` (rows
``[v, ω]``, ``Ad`` the adjoint of a motor on them):

    J_r = J_2 - Ad(~M_r) J_1                                                        (C3)
    J_a = Ad(M_r^-½) J_1 + ½ J_r(ξ_r / 2) Jlog6(ξ_r) J_r                            (C4)

(C3) is the body velocity of ``~F_1 F_2``: the second hand's minus the first's carried into
the second frame. (C4) differentiates ``F_1 exp(ξ_r / 2)``: the first hand's velocity carried
through ``M_r^½``, plus the rate of the half logarithm, ``½ Jlog6(ξ_r) J_r``, turned into a
body velocity by the right Jacobian of the exponential (``_lie``). A task on either motor
asks ``log6(~M_t M)`` to vanish, with the Jacobian ``Jlog6 · J`` (as the ``POSE`` task).

A task row (``_rows``) of kind ``RELATIVE`` or ``ABSOLUTE`` holds the first link in ``LINK``
and its tool motor in ``TOOL``, the second link in ``SECOND`` and its tool motor in the
``CARRIED`` slot, and the target motor in the first 8 floats of ``TARGET``.
"""

from __future__ import annotations

from .._jit import inline, serial
from ..algorithms.kinematics import link_motor
from ..kernels import motor_log, motor_mul, motor_reverse, twist_exp
from ..kernels.layout import physical
from ..kernels.rigid import rigid_frame, rigid_rotate
from ._lie import jexp6, jlog6
from ._rows import ABSOLUTE, CARRIED, LINK, RELATIVE, SECOND, TARGET, TOOL, WEIGHT, local_jacobian

__all__ = ["ABSOLUTE", "RELATIVE", "cooperative", "cooperative_rows"]


@inline
def _log6(M, tw, xi):
    """``xi = (v, ω)`` of ``log M`` with the rotation angle in [0, π] (Pinocchio's ``log6``;
    ``-M`` is the same motion); M's sign is flipped in place when needed. ``tw``: the twist."""
    if M[0] < 0.0:
        for i in range(8):
            M[i] = -M[i]
    motor_log(M, tw)
    w0, w1, w2, v0, v1, v2 = physical(tw)
    xi[0], xi[1], xi[2], xi[3], xi[4], xi[5] = v0, v1, v2, w0, w1, w2


@inline
def _adjoint_add(M, sign, Jin, Jout):
    """``Jout += sign · Ad(M) Jin`` column by column: ``(v, ω) ↦ (R v + p × R ω, R ω)``."""
    R, p = rigid_frame(M)
    for k in range(Jin.shape[1]):
        v0, v1, v2 = rigid_rotate(R, Jin[0, k], Jin[1, k], Jin[2, k])
        w0, w1, w2 = rigid_rotate(R, Jin[3, k], Jin[4, k], Jin[5, k])
        Jout[0, k] += sign * (v0 + p[1] * w2 - p[2] * w1)
        Jout[1, k] += sign * (v1 + p[2] * w0 - p[0] * w2)
        Jout[2, k] += sign * (v2 + p[0] * w1 - p[1] * w0)
        Jout[3, k] += sign * w0
        Jout[4, k] += sign * w1
        Jout[5, k] += sign * w2


@serial
def cooperative(m, Mw, task, Ma, Ja, Mr, Jr, cw):
    """``Ma, Ja`` (8), (6, nv) and ``Mr, Jr`` of the task row's two tool frames, (C1-C4);
    ``Mw`` the joints' world motors, ``cw`` the stack's workspace (``_stack.WORKSPACE``)."""
    L, F1, F2, H, tw, xi = cw.L, cw.F, cw.F2, cw.H, cw.tw, cw.xi
    J1, K, K2, K3, t = cw.Jf, cw.J6, cw.K2, cw.K3, cw.t
    link_motor(m, Mw, int(task[LINK]), L)
    motor_mul(L, task[TOOL:TOOL + 8], F1)  # F_1 = M^w_L1 P_1
    link_motor(m, Mw, int(task[SECOND]), L)
    motor_mul(L, task[CARRIED:CARRIED + 8], F2)  # F_2 = M^w_L2 P_2
    local_jacobian(m, Mw, int(task[LINK]), F1, tw, J1)  # J_1
    local_jacobian(m, Mw, int(task[SECOND]), F2, tw, Jr)  # J_2
    motor_reverse(F1, L)
    motor_mul(L, F2, Mr)  # M_r = ~F_1 F_2 (C1)
    motor_reverse(Mr, L)
    _adjoint_add(L, -1.0, J1, Jr)  # J_r = J_2 - Ad(~M_r) J_1 (C3)
    for i in range(8):
        H[i] = Mr[i]
    _log6(H, tw, xi)  # ξ_r, M_r's sign taken so that its angle is at most π
    for i in range(6):
        tw[i] *= 0.5
    twist_exp(tw, H)  # M_r^½ = exp(V_r / 4)
    motor_mul(F1, H, Ma)  # M_a = F_1 M_r^½ (C2)
    jlog6(xi, K, t)
    for i in range(6):
        xi[i] *= 0.5
    jexp6(xi, K2, t)
    for i in range(6):  # K3 = J_r(ξ_r / 2) Jlog6(ξ_r)
        for j in range(6):
            acc = 0.0
            for h in range(6):
                acc += K2[i, h] * K[h, j]
            K3[i, j] = acc
    for i in range(6):
        for k in range(Ja.shape[1]):
            acc = 0.0
            for h in range(6):
                acc += K3[i, h] * Jr[h, k]
            Ja[i, k] = 0.5 * acc  # ½ K3 J_r
    motor_reverse(H, L)
    _adjoint_add(L, 1.0, J1, Ja)  # + Ad(M_r^-½) J_1 (C4)


@serial
def cooperative_rows(m, Mw, task, kind, r, J, o, cw, Ma, Ja, Mr, Jr):
    """Rows ``o .. o + 6`` of ``r`` and ``J``: ``w log6(~M_t M)`` and ``w Jlog6 · J`` for
    M the relative (``RELATIVE``) or absolute motor."""
    w = task[WEIGHT]
    cooperative(m, Mw, task, Ma, Ja, Mr, Jr, cw)
    M, JM = (Mr, Jr) if kind == RELATIVE else (Ma, Ja)
    L, E, tw, xi, K, t = cw.L, cw.E, cw.tw, cw.xi, cw.J6, cw.t
    motor_reverse(task[TARGET:TARGET + 8], L)
    motor_mul(L, M, E)  # ~M_t M
    _log6(E, tw, xi)
    jlog6(xi, K, t)
    for i in range(6):
        r[o + i] = w * xi[i]
        for k in range(JM.shape[1]):
            acc = 0.0
            for h in range(6):
                acc += K[i, h] * JM[h, k]
            J[o + i, k] = w * acc
