"""Couplings of coordinates as bilateral rows of the contact problem (``docs/contact.md``,
"Couplings", K45): the rows of a model's couplings (``coupling_rows``), for
``contact_step`` and the compiled rollout loop alike, and the step's correction of the
configuration back onto them (``coupling_shift``).

A coupling ``a · q = b`` (``Model.coupling_coefficients``, ``Model.coupling_offset``: a
MuJoCo ``<equality joint>`` or ``<equality tendon>`` of a linear polynomial) reads only
coordinates that add, which a step moves by ``dt v⁺``; so its row ``J_r = a``, unbounded,
with ``σ_r = a · v⁺ = 0`` keeps ``a · q`` where it was, and the position update takes what
other corrections (K26a, K43) or a start off the coupling left back by the fraction ``β``.
"""

from __future__ import annotations

import numpy as np

from .._jit import inline
from .additive import additive_move, additive_value

__all__ = ["coupling_errors", "coupling_rows", "coupling_shift"]


def coupling_rows(model) -> np.ndarray:
    """(ne, 3 nv + 1) per coupling of ``model``: its coefficients ``a`` (nv), its offset
    ``b``, its column of the pseudo-inverse ``A⁺ = Aᵀ (A Aᵀ)⁻¹`` of the couplings' matrix
    (nv; the least displacement that moves the couplings' values by a given amount,
    K45a), and the index in q of each velocity coordinate (nv; -1 for the coordinates of
    joints whose coordinates do not add, which no coupling reads)."""
    A, b = model.coupling_coefficients, model.coupling_offset
    ne, nv = A.shape
    out = np.zeros((ne, 3 * nv + 1))
    if ne == 0:
        return out
    from ..multibody.joints.table import additive_index

    out[:, :nv], out[:, nv] = A, b
    out[:, nv + 1:2 * nv + 1] = np.linalg.pinv(A).T
    out[:, 2 * nv + 1:] = additive_index(model)
    return np.ascontiguousarray(out)


@inline
def coupling_error(rows, c, nv, q):
    """``a_c · q - b_c``: how far ``q`` is off coupling ``c`` (a row of ``coupling_rows``)."""
    return additive_value(rows, c, 0, 2 * nv + 1, nv, q) - rows[c, nv]


def coupling_errors(rows, q) -> np.ndarray:
    """``A q - b`` of every coupling at ``q``, (ne,)."""
    nv = (rows.shape[1] - 1) // 3
    return np.array([coupling_error(rows, c, nv, q) for c in range(rows.shape[0])])


@inline
def coupling_shift(rows, beta, q, e):
    """``q`` moved by ``-β A⁺ (A q - b)`` on the coupled coordinates (K45a): the least
    displacement that takes the fraction ``β`` of every coupling's error back, a correction
    of the position alone, as a joint limit's (K26a). ``e`` (ne,): scratch, the errors."""
    ne = rows.shape[0]
    if ne == 0:
        return
    nv = (rows.shape[1] - 1) // 3
    for c in range(ne):
        e[c] = beta * coupling_error(rows, c, nv, q)
    for c in range(ne):
        if e[c] != 0.0:
            additive_move(rows, c, nv + 1, 2 * nv + 1, nv, -e[c], q)
