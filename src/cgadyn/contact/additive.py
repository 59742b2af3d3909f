"""A linear function ``c · q`` of a model's additive coordinates, and the move of q along
``c``: what a fixed tendon's length (K26'') and a coupling's error (K45a) read and what
their position corrections (K26a, K45a) write, from one table layout. A row of such a
table holds the coefficients ``c`` (one per velocity coordinate) at one column and, at
another, the index in q of each velocity coordinate (``multibody.joints.table.
additive_index``; -1 on the coordinates of joints whose coordinates do not add, where
``c`` is zero): for a hinge or a slide, q and v share a coordinate, so ``c · v`` is the
rate of ``c · q``."""

from __future__ import annotations

from .._jit import inline

__all__ = ["additive_move", "additive_value"]


@inline
def additive_value(table, r, coef, index, nv, q):
    """``c · q`` of row ``r`` of ``table``: its coefficients from column ``coef``, the
    index in q of each from column ``index``."""
    out = 0.0
    for k in range(nv):
        c = table[r, coef + k]
        if c != 0.0:
            out += c * q[int(table[r, index + k])]
    return out


@inline
def additive_move(table, r, coef, index, nv, amount, q):
    """``q ← q + amount x`` with ``x`` row ``r``'s coefficients from column ``coef``, each
    on the coordinate of q that column ``index`` names (as ``additive_value``)."""
    for k in range(nv):
        x = table[r, coef + k]
        if x != 0.0:
            q[int(table[r, index + k])] += amount * x
