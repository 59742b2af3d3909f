"""The model's dynamics arrays packed into two buffers, for the compiled algorithms.

Every array handed to a compiled function costs about 40 ns to unbox on each call, a
large share of a one-sample call that computes in under a microsecond. So the compiled
entry points take the five arrays the recursions read (``parents``, ``joint_types``,
``placements``, ``axes``, ``inertias``) as two buffers, one of integers and one of floats,
and ``unpack`` cuts them back into C-contiguous views at no cost worth measuring::

    tree   = [parents (n) | joint_types (n)]                    int64
    bodies = [placements (n, 8) | axes (n, 6) | inertias (n, 6, 6)]   float64
"""

from __future__ import annotations

import numpy as np
from numba import njit

BODY_FLOATS = 8 + 6 + 36
"""Floats per body in ``bodies``: motor, twist, inertia."""


def pack(model) -> tuple[np.ndarray, np.ndarray]:
    """``(tree, bodies)`` of a model: new writable arrays (numba dispatches faster on
    writable arrays; the compiled code never writes to them)."""
    tree = np.concatenate([model.parents, model.joint_types]).astype(np.int64)
    bodies = np.concatenate(
        [model.placements.ravel(), model.axes.ravel(), model.inertias.ravel()]
    ).astype(np.float64)
    return tree, bodies


@njit(cache=True, nogil=True, inline="always")
def unpack(tree, bodies):
    """``(parents, joint_types, placements, axes, inertias)``: views into the buffers."""
    n = tree.shape[0] // 2
    parents = tree[:n]
    types = tree[n:]
    placements = bodies[: 8 * n].reshape((n, 8))
    axes = bodies[8 * n : 14 * n].reshape((n, 6))
    inertias = bodies[14 * n : BODY_FLOATS * n].reshape((n, 6, 6))
    return parents, types, placements, axes, inertias
