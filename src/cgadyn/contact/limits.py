"""Joint limits as unilateral constraints of the contact problem (``docs/contact.md``, "Joint
limits", K26): which joints have them (``joint_limits``) and which bounds are rows of a
step (``active_limits``), for ``contact_step`` and the compiled rollout loop alike; and the
coordinates whose friction loss is a box-bounded row of every step (``joint_frictions``,
"Friction loss", K30).

A limit applies to a joint of one coordinate (``nq = nv = 1``: revolute, prismatic,
helical; a continuous joint's bounds are infinite), whose ``q`` moves by ``dt v`` in a step,
and to the angle θ of a joint's rotation bounded by a cone (``Model.cone_limit``: MuJoCo's
``ball`` ``range``; K26'), whose rate is ``θ̇ = aᵀ ω`` (a the rotation's unit axis, ω the
joint's angular velocity), and to the length ``L = c · q`` of a fixed tendon
(``Model.tendon_range``; K26''), whose rate is ``c · v``. Other joints of several
coordinates (planar, translation, free flyer) get no limit rows: their
``Model.lower``/``upper`` are not enforced.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import inline, serial
from .additive import additive_move, additive_value
from .problem import open_gap

__all__ = ["LIMIT_COLUMNS", "ROW_COLUMNS", "active_limits", "joint_frictions", "joint_limits",
           "limit_gap", "limit_row", "limit_shift", "tendon_arrays"]

Q, V, LOWER, UPPER, CONE = range(5)
LIMIT_COLUMNS = 5
"""Columns of ``joint_limits``: the coordinate's index in q and in v, its lower and upper
bound (``±inf`` where it has none), and 1 for a cone limit (then the index of the joint's
quaternion ``(x, y, z, w)`` in q, of its first angular velocity coordinate in v, and the
largest angle as the upper bound), 2 for a fixed tendon's (then the tendon's index in the
first column, its row of ``tendon_arrays``, and -1 in the second), else 0."""
JOINT, CONE_LIMIT, TENDON_LIMIT = 0.0, 1.0, 2.0
ROW_V, ROW_WIDTH, ROW_GAP, ROW_SLOT, ROW_COEF = 0, 1, 2, 3, 4
ROW_COLUMNS = 7
"""Columns of the rows ``active_limits`` finds: the first v index and the count of v
coordinates the row reads (1, or 3 for a cone; 0 for a tendon, whose row is ``±c``: then
its index in the first column), the gap ``d``, the bound's slot (``2 j`` for limit j's
lower bound, ``2 j + 1`` for its upper), which keeps its impulse for the next step's warm
start (K25), and the row's coefficients on those coordinates (three columns: +1 for a
lower bound, -1 for an upper one, ``-a`` for a cone; for a tendon the sign alone), each
the gradient of d."""


def joint_limits(model) -> np.ndarray:
    """(L, 5) ``[q index, v index, lower, upper, cone]`` of each joint of one coordinate with
    a finite lower or upper bound (``Model.lower``, ``Model.upper``), and of each joint with a
    finite ``Model.cone_limit``: the joints whose limits a step enforces, in joint order."""
    from ..multibody.joints import TYPES

    rows = []
    iq, iv = model.idx_q, model.idx_v
    for j, t in enumerate(model.joint_types):
        record = TYPES[int(t)]
        if record.cone and np.isfinite(model.cone_limit[j]):
            rows.append([iq[j] + record.quaternion, iv[j], -np.inf, model.cone_limit[j], 1.0])
            continue
        if record.nq != 1 or record.nv != 1:
            continue
        lo, hi = float(model.lower[iq[j]]), float(model.upper[iq[j]])
        if np.isfinite(lo) or np.isfinite(hi):
            rows.append([iq[j], iv[j], lo, hi, JOINT])
    for t, (lo, hi) in enumerate(model.tendon_range):  # then the fixed tendons' (K26'')
        if np.isfinite(lo) or np.isfinite(hi):
            rows.append([t, -1, lo, hi, TENDON_LIMIT])
    return np.array(rows, dtype=float).reshape(len(rows), LIMIT_COLUMNS)


def tendon_arrays(model) -> np.ndarray:
    """(nt, 2 nv) per fixed tendon of ``model``: its coefficients ``c`` (its length ``c ·
    q``), then the index in q of each velocity coordinate (-1 on those of joints whose
    coordinates do not add, where no tendon reads): what a tendon's limit reads (K26'')."""
    from ..multibody.joints.table import additive_index

    nt = len(model.tendon_names)
    out = np.zeros((nt, 2 * model.nv))
    out[:, :model.nv] = model.tendon_coefficients
    out[:, model.nv:] = additive_index(model)
    return np.ascontiguousarray(out)


def joint_frictions(model) -> np.ndarray:
    """(F, nv + 1) ``[J row, friction]`` of each velocity coordinate with a friction loss
    (``Model.friction`` > 0), of any joint, its row ``e_k``, then of each fixed tendon with
    one (``Model.tendon_friction`` > 0), its row ``c``: each a row of every step whose
    impulse lies in ``[-f dt, f dt]`` (K30)."""
    k = np.flatnonzero(model.friction > 0.0)
    t = np.flatnonzero(model.tendon_friction > 0.0)
    rows = np.zeros((len(k) + len(t), model.nv + 1))
    rows[np.arange(len(k)), k] = 1.0
    rows[len(k):, :model.nv] = model.tendon_coefficients[t]
    rows[:, model.nv] = np.concatenate([model.friction[k], model.tendon_friction[t]])
    return np.ascontiguousarray(rows)


@serial
def active_limits(limits, tendons, q, v, vn, dt, margin, rows):
    """The bounds of ``limits`` (``joint_limits``) that are rows of the step (K26): the lower
    bound where its gap ``d = q - lower`` (row ``+e_v``), the upper where ``d = upper - q``
    (row ``-e_v``) is below ``margin`` plus how far the coordinate may move in the step,
    ``dt sqrt(v_i² + v_free,i²)`` (``vn`` the free velocity); a cone where
    ``d = θ_max - θ`` is below ``margin`` plus ``dt sqrt(|ω|² + |ω_free|²)`` (row ``-aᵀ``
    on ω, K26'); a fixed tendon's where ``d = L - lower`` or ``upper - L`` is below
    ``margin`` plus ``dt sqrt((c · v)² + (c · v_free)²)`` (row ``±c``, K26''; ``tendons``
    its ``tendon_arrays``). Fills ``rows`` (2 L, ``ROW_COLUMNS``) in the order of
    ``limits``, lower before upper; returns their number."""
    count = 0
    for j in range(limits.shape[0]):
        i, k = int(limits[j, Q]), int(limits[j, V])
        if limits[j, CONE] == CONE_LIMIT:
            count = _cone(limits[j, UPPER], q, v, vn, i, k, dt, margin, 2 * j + 1, rows, count)
            continue
        if limits[j, CONE] == TENDON_LIMIT:
            x, r0, r1 = _tendon(tendons, i, q, v, vn)
        else:
            x, r0, r1 = q[i], v[k], vn[k]
        reach = margin + dt * math.sqrt(r0 * r0 + r1 * r1)
        for side in range(2):
            sign = 1.0 if side == 0 else -1.0
            d = x - limits[j, LOWER] if side == 0 else limits[j, UPPER] - x
            if d < reach:  # an infinite bound never is a row
                rows[count, ROW_V] = k if limits[j, CONE] == JOINT else i
                rows[count, ROW_WIDTH] = 1.0 if limits[j, CONE] == JOINT else 0.0
                rows[count, ROW_GAP], rows[count, ROW_SLOT] = d, 2 * j + side
                rows[count, ROW_COEF] = sign
                rows[count, ROW_COEF + 1] = rows[count, ROW_COEF + 2] = 0.0
                count += 1
    return count


@inline
def _tendon(tendons, t, q, v, vn):
    """``(c · q, c · v, c · v_free)`` of fixed tendon ``t`` (a row of ``tendon_arrays``)."""
    nv = tendons.shape[1] // 2
    rate, rate_free = 0.0, 0.0
    for k in range(nv):
        rate += tendons[t, k] * v[k]
        rate_free += tendons[t, k] * vn[k]
    return additive_value(tendons, t, 0, nv, nv, q), rate, rate_free


@inline
def limit_row(rows, k, tendons, J, r):
    """Row ``r`` of J for the limit bound ``rows[k]``: ``±e_v``, a cone's ``-aᵀ`` on ω, or
    a fixed tendon's ``±c`` (K26, K26', K26'')."""
    width = int(rows[k, ROW_WIDTH])
    if width == 0:
        t, nv = int(rows[k, ROW_V]), tendons.shape[1] // 2
        for i in range(nv):
            J[r, i] = rows[k, ROW_COEF] * tendons[t, i]
        return
    for i in range(width):
        J[r, int(rows[k, ROW_V]) + i] = rows[k, ROW_COEF + i]


@serial
def _cone(largest, q, v, vn, i, k, dt, margin, slot, rows, count):
    """The row of a cone limit (K26'), if the step may reach it: the quaternion
    ``(x, y, z, w)`` at ``q[i]`` (taken with ``w >= 0``, the same rotation) turns by
    ``θ = 2 atan2(|(x, y, z)|, w)`` about ``a = (x, y, z) / |(x, y, z)|``, and
    ``θ̇ = aᵀ ω`` for the angular velocity ω at ``v[k]`` (in the child's frame or the
    parent's alike: R a = a); the gap ``d = θ_max - θ``, the row ``-aᵀ``. The new count."""
    x, y, z, s, half = _axis_angle(q, i)
    d = largest - 2.0 * half
    speed = 0.0
    for c in range(3):
        speed += v[k + c] * v[k + c] + vn[k + c] * vn[k + c]
    if not d < margin + dt * math.sqrt(speed):
        return count
    if s > 0.0:
        x, y, z = x / s, y / s, z / s
    else:  # no rotation: any axis (the row binds only for a cone of angle 0, refused)
        x, y, z = 1.0, 0.0, 0.0
    rows[count, ROW_V], rows[count, ROW_WIDTH] = k, 3.0
    rows[count, ROW_GAP], rows[count, ROW_SLOT] = d, slot
    rows[count, ROW_COEF], rows[count, ROW_COEF + 1], rows[count, ROW_COEF + 2] = -x, -y, -z
    return count + 1


@inline
def limit_gap(rows, k, dt):
    """The gap's term of limit row ``k`` (K26, K26'): ``d / dt`` for an open gap (the step
    may close it, no sooner); for a coordinate or a cone past its bound (``d < 0``) 0, so
    that the step moves it no further out, and the step's position update takes it back by
    the fraction ``β`` of its overshoot (``limit_shift``, K26a): a velocity ``β d / dt``
    would stay in ``v`` and carry the joint on, adding the energy of a kick that nothing
    put in (a model started outside its ranges, Gymnasium's Ant at its neutral pose, jumped
    metres)."""
    return open_gap(rows[k, ROW_GAP], dt)


@inline
def limit_shift(limits, tendons, rows, count, beta, q):
    """``q`` after the step's position update, each coordinate that the step began past a
    bound of (``rows[:count]``, ``active_limits``'; ``d < 0``) moved back toward it by
    ``β |d|``, each ball joint that began past its cone turned back about its own axis
    by ``β |d|``, and each fixed tendon past a bound lengthened or shortened by ``β |d|``
    along its coefficients, ``q ← q ± β |d| c / |c|²`` (the least displacement of its
    coordinates that does it) (K26a): a correction of the position alone, with no
    velocity to keep."""
    for k in range(count):
        d = rows[k, ROW_GAP]
        if not d < 0.0:
            continue
        slot = int(rows[k, ROW_SLOT])
        i = int(limits[slot // 2, Q])
        if rows[k, ROW_WIDTH] == 1.0:
            q[i] += -beta * d if slot % 2 == 0 else beta * d
        elif rows[k, ROW_WIDTH] == 0.0:
            _lengthen(tendons, i, -beta * d if slot % 2 == 0 else beta * d, q)
        else:
            _turn_back(q, i, beta * d)


@inline
def _lengthen(tendons, t, amount, q):
    """``q`` moved by ``amount c / |c|²``: fixed tendon ``t`` lengthened by ``amount``."""
    nv = tendons.shape[1] // 2
    norm = 0.0
    for k in range(nv):
        norm += tendons[t, k] * tendons[t, k]
    additive_move(tendons, t, 0, nv, nv, amount / norm, q)


@inline
def _axis_angle(q, i):
    """``(x, y, z, |(x, y, z)|, θ / 2)`` of the quaternion ``(x, y, z, w)`` at ``q[i]``
    taken with ``w >= 0`` (the same rotation): it turns by ``θ = 2 atan2(|(x, y, z)|, w)``
    about ``(x, y, z) / |(x, y, z)|`` (K26')."""
    x, y, z, w = q[i], q[i + 1], q[i + 2], q[i + 3]
    if w < 0.0:
        x, y, z, w = -x, -y, -z, -w
    s = math.sqrt(x * x + y * y + z * z)
    return x, y, z, s, math.atan2(s, w)


@inline
def _turn_back(q, i, angle):
    """The quaternion ``(x, y, z, w)`` at ``q[i]`` turned by ``angle`` about its own axis
    (``θ ← θ + angle``, taken with ``w >= 0``; K26a on a cone): the rotation's axis ``a``
    is unchanged, so the cone's gap grows by ``-angle``."""
    x, y, z, s, half = _axis_angle(q, i)
    if s == 0.0:
        return
    half += 0.5 * angle
    c = math.sin(half) / s
    q[i], q[i + 1], q[i + 2], q[i + 3] = c * x, c * y, c * z, math.cos(half)
