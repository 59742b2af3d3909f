"""The model packed into one float64 buffer, the form in which compiled code receives it.

Every array handed to compiled code from Python costs time to unbox, a large share of a
one-sample call, whose arithmetic is short; a pointer handed to a C entry point costs nothing. So
the compiled algorithms take everything they read about the model as one buffer, and
``unpack`` cuts it back into bare C-contiguous views (``cgadyn._views``), returned as a
``ModelView``. The integers are stored as their int64 bit patterns (both types are 8 bytes
wide)::

    ints:   n, nq, nv, nl, length | parents (n) | types (n) | iq (n + 1) | iv (n + 1)
            | dof_parent (nv) | dof_joint (nv) | subtree_end (n) | link_joint (nl)
            | unit_axis (nv) | flat
    floats: placements (n, 8) | S (nv, 6) | inertias (n, 6, 6) | base acceleration (6)
            | link_placements (nl, 8) | armature (nv)

``n`` joints, ``nq``/``nv`` the sizes of q and v, ``nl`` link frames, ``length`` the
buffer's length; ``iq``/``iv`` the first index of each joint in q and v (the last entries
nq and nv); ``dof_parent`` the velocity coordinate each one hangs from in the tree of
coordinates (Featherstone's expanded tree: a multi-dof joint is a chain of its
coordinates, the first hanging from the parent joint's last), -1 at the root, and
``dof_joint`` the joint of each coordinate, ``subtree_end`` one past the last coordinate of
each joint's subtree (contiguous: joints are in depth-first order), ``unit_axis`` the
index i of a one-dof joint's coordinate whose ``S`` is ``±e_i``, else -1
(``multibody.joints.unit_axes``), ``flat`` 1 when every joint is additive
(``q ⊕ v = q + v``, ``multibody.joints.table.flat``), else 0; ``S`` the motion subspace of
every velocity coordinate (``multibody.joints``); ``armature`` the rotor inertia of each
velocity coordinate (``Model.armature``), which the cores add to the mass matrix's diagonal.
The base acceleration is ``V̇_0 = -g`` as a twist (gravity as a fictitious acceleration of
the world, as Pinocchio keeps ``model.gravity``); ``with_gravity`` makes a copy for
another gravity.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from .._jit import inline
from .._views import as_int64, carve, data_pointer
from ..cga.conventions import twist_from_motion
from .joints.table import flat

DEFAULT_GRAVITY = (0.0, 0.0, -9.81)
HEADER = 5
"""n, nq, nv, nl, length."""

ModelView = namedtuple("ModelView", [
    "n", "nq", "nv", "nl", "parents", "types", "iq", "iv", "dof_parent", "dof_joint",
    "subtree_end", "link_joint", "unit_axis", "flat",
    "placements", "S", "inertias", "gravity", "link_placements", "armature"])
"""The model as compiled code reads it: sizes and views into the packed buffer.
``gravity`` is the base acceleration ``V̇_0 = -g`` (a twist)."""


def _ints(n: int, nv: int, nl: int) -> int:
    return HEADER + 3 * n + 2 * (n + 1) + 3 * nv + nl + 1


def base_acceleration(gravity) -> np.ndarray:
    """``V̇_0 = -g`` as a twist, for a world-frame gravity 3-vector."""
    g = np.asarray(gravity, dtype=np.float64)
    return twist_from_motion(np.array([-g[0], -g[1], -g[2], 0.0, 0.0, 0.0]))


def pack(model, gravity=DEFAULT_GRAVITY) -> np.ndarray:
    """One new writable float64 buffer of the model (compiled code never writes to it)."""
    n, nl = model.njoints, model.nlinks
    floats = [model.placements, model.motion_subspace, model.inertias,
              base_acceleration(gravity), model.link_placements, model.armature]
    length = _ints(n, model.nv, nl) + sum(a.size for a in floats)
    ints = np.concatenate([[n, model.nq, model.nv, nl, length], model.parents,
                           model.joint_types, model.idx_q, model.idx_v, model.dof_parent,
                           model.dof_joint, model.subtree_end,
                           model.link_joint, model.unit_axes,
                           [int(flat(model.joint_types))]]).astype(np.int64)
    out = np.concatenate([ints.view(np.float64)] + [np.ravel(a) for a in floats])
    assert out.shape == (length,)
    return out


def with_gravity(packed: np.ndarray, gravity) -> np.ndarray:
    """A copy of a packed model with another gravity."""
    n, nq, nv, nl, _ = packed[:HEADER].view(np.int64)
    at = _ints(n, nv, nl) + 8 * n + 6 * nv + 36 * n
    out = packed.copy()
    out[at:at + 6] = base_acceleration(gravity)
    return out


def with_armature(packed: np.ndarray, extra: np.ndarray) -> np.ndarray:
    """A copy of a packed model whose armature is ``armature + extra`` (nv,): the mass
    matrix every core then uses is ``M + diag(extra)`` (the implicit step's, K40)."""
    nv = int(packed[:HEADER].view(np.int64)[2])
    out = packed.copy()
    out[out.shape[0] - nv:] += np.asarray(extra, dtype=np.float64)  # armature comes last
    return out


@inline
def unpack(packed):
    """The ``ModelView`` of a packed buffer: views valid while the buffer lives (pass the
    buffer as an argument of the caller)."""
    at = data_pointer(packed)
    header, o = carve(as_int64(at), 0, (HEADER,))
    n, nq, nv, nl = header[0], header[1], header[2], header[3]
    parents, o = carve(as_int64(at), o, (n,))
    types, o = carve(as_int64(at), o, (n,))
    iq, o = carve(as_int64(at), o, (n + 1,))
    iv, o = carve(as_int64(at), o, (n + 1,))
    dof_parent, o = carve(as_int64(at), o, (nv,))
    dof_joint, o = carve(as_int64(at), o, (nv,))
    subtree_end, o = carve(as_int64(at), o, (n,))
    link_joint, o = carve(as_int64(at), o, (nl,))
    unit_axis, o = carve(as_int64(at), o, (nv,))
    flags, o = carve(as_int64(at), o, (1,))
    placements, o = carve(at, o, (n, 8))
    S, o = carve(at, o, (nv, 6))
    inertias, o = carve(at, o, (n, 6, 6))
    gravity, o = carve(at, o, (6,))
    link_placements, o = carve(at, o, (nl, 8))
    armature, o = carve(at, o, (nv,))
    return ModelView(n, nq, nv, nl, parents, types, iq, iv, dof_parent, dof_joint, subtree_end,
                     link_joint, unit_axis, flags[0] != 0, placements, S, inertias, gravity,
                     link_placements, armature)
