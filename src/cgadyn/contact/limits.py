"""Joint limits as unilateral constraints of the contact problem (``docs/contact.md``, "Joint
limits", K26): which joints have them (``joint_limits``) and which bounds are rows of a
step (``active_limits``), for ``contact_step`` and the compiled rollout loop alike; and the
coordinates whose friction loss is a box-bounded row of every step (``joint_frictions``,
"Friction loss", K30).

A limit applies to a joint of one coordinate (``nq = nv = 1``: revolute, prismatic,
helical; a continuous joint's bounds are infinite), whose ``q`` moves by ``dt v`` in a step.
Joints of several coordinates (spherical, planar, translation, free flyer) get no limit
rows: their ``Model.lower``/``upper`` are not enforced.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import serial

__all__ = ["LIMIT_COLUMNS", "active_limits", "joint_frictions", "joint_limits"]

Q, V, LOWER, UPPER = range(4)
LIMIT_COLUMNS = 4
"""Columns of ``joint_limits``: the coordinate's index in q and in v, its lower and upper
bound (``±inf`` where it has none)."""
ROW_V, ROW_SIGN, ROW_GAP, ROW_SLOT = range(4)
"""Columns of the rows ``active_limits`` finds: the v index, the sign of the row (+1 for the
lower bound, -1 for the upper), the gap ``d`` and the bound's slot (``2 j`` for limit j's
lower bound, ``2 j + 1`` for its upper), which keeps its impulse for the next step's warm
start (K25)."""


def joint_limits(model) -> np.ndarray:
    """(L, 4) ``[q index, v index, lower, upper]`` of each joint of one coordinate with a
    finite lower or upper bound (``Model.lower``, ``Model.upper``): the joints whose limits
    a step enforces (the module's docstring)."""
    from ..multibody.joints import TYPES

    rows = []
    iq, iv = model.idx_q, model.idx_v
    for j, t in enumerate(model.joint_types):
        if TYPES[int(t)].nq != 1 or TYPES[int(t)].nv != 1:
            continue
        lo, hi = float(model.lower[iq[j]]), float(model.upper[iq[j]])
        if np.isfinite(lo) or np.isfinite(hi):
            rows.append([iq[j], iv[j], lo, hi])
    return np.array(rows, dtype=float).reshape(len(rows), LIMIT_COLUMNS)


def joint_frictions(model) -> np.ndarray:
    """(F, 2) ``[v index, friction]`` of each velocity coordinate with a friction loss
    (``Model.friction`` > 0), of any joint: each is a row ``e_k`` of every step whose
    impulse lies in ``[-f dt, f dt]`` (K30)."""
    k = np.flatnonzero(model.friction > 0.0)
    return np.ascontiguousarray(np.column_stack([k, model.friction[k]]).astype(float))


@serial
def active_limits(limits, q, v, vn, dt, margin, rows):
    """The bounds of ``limits`` (``joint_limits``) that are rows of the step (K26): the lower
    bound where its gap ``d = q - lower`` (row ``+e_v``), the upper where ``d = upper - q``
    (row ``-e_v``) is below ``margin`` plus how far the coordinate may move in the step,
    ``dt sqrt(v_i² + v_free,i²)`` (``vn`` the free velocity). Fills ``rows`` (2 L, 4, see
    ``ROW_V``...) in the order of ``limits``, lower before upper; returns their number."""
    count = 0
    for j in range(limits.shape[0]):
        i, k = int(limits[j, Q]), int(limits[j, V])
        reach = margin + dt * math.sqrt(v[k] * v[k] + vn[k] * vn[k])
        for side in range(2):
            sign = 1.0 if side == 0 else -1.0
            d = q[i] - limits[j, LOWER] if side == 0 else limits[j, UPPER] - q[i]
            if d < reach:  # an infinite bound never is a row
                rows[count, ROW_V], rows[count, ROW_SIGN] = k, sign
                rows[count, ROW_GAP], rows[count, ROW_SLOT] = d, 2 * j + side
                count += 1
    return count
