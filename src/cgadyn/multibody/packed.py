"""The model's dynamics arrays packed into one buffer, for the compiled algorithms.

Every array handed to a compiled function costs about 50 ns to unbox on each call, a
large share of a one-sample call that computes in under a microsecond. So the compiled
entry points take everything the recursions read about the model as one float64 buffer,
and ``unpack`` cuts it back into bare C-contiguous views (``cgadyn._views``)::

    [parents (n) | joint_types (n) | placements (n, 8) | axes (n, 6) | inertias (n, 6, 6)
     | base acceleration (6)]

The integers are stored as their int64 bit patterns (both types are 8 bytes wide) and
read back as int64. The base acceleration is ``V̇_0 = -g`` as a twist (gravity as a
fictitious base acceleration, as Pinocchio keeps ``model.gravity``); ``with_gravity``
makes a copy for another gravity.
"""

from __future__ import annotations

import numpy as np

from .._jit import inline
from .._views import as_int64, carve, data_pointer
from ..cga.conventions import twist_from_motion

FLOATS_PER_JOINT = 2 + 8 + 6 + 36
"""parent, type, motor, twist, inertia."""

DEFAULT_GRAVITY = (0.0, 0.0, -9.81)


def base_acceleration(gravity) -> np.ndarray:
    """``V̇_0 = -g`` as a twist, for a world-frame gravity 3-vector."""
    g = np.asarray(gravity, dtype=np.float64)
    return twist_from_motion(np.array([-g[0], -g[1], -g[2], 0.0, 0.0, 0.0]))


def pack(model, gravity=DEFAULT_GRAVITY) -> np.ndarray:
    """One new writable float64 buffer (numba dispatches faster on writable arrays; the
    compiled code never writes to it)."""
    ints = np.concatenate([model.parents, model.joint_types]).astype(np.int64)
    return np.concatenate([
        ints.view(np.float64),
        model.placements.ravel(),
        model.axes.ravel(),
        model.inertias.ravel(),
        base_acceleration(gravity),
    ])


def with_gravity(packed: np.ndarray, gravity) -> np.ndarray:
    """A copy of a packed model with another gravity."""
    out = packed.copy()
    out[-6:] = base_acceleration(gravity)
    return out


@inline
def njoints(packed):
    """n, from the length of a packed buffer."""
    return (packed.shape[0] - 6) // FLOATS_PER_JOINT


@inline
def unpack(packed):
    """``(parents, joint_types, placements, axes, inertias, base_acceleration)``: views
    into the buffer, valid while it lives (pass it as an argument of the caller)."""
    n = njoints(packed)
    at = data_pointer(packed)
    ints, o = carve(as_int64(at), 0, (2 * n,))
    placements, o = carve(at, o, (n, 8))
    axes, o = carve(at, o, (n, 6))
    inertias, o = carve(at, o, (n, 6, 6))
    base, o = carve(at, o, (6,))
    return ints[:n], ints[n:], placements, axes, inertias, base
