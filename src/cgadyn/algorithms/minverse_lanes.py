"""``minverse`` on a batch: M1-M3 of ``minverse.py`` for ``W`` samples at once.

Every sample of a batch runs the same recursion; only the numbers differ. Here the samples
of a group of ``W`` are laid side by side (element ``x`` of sample ``l`` at ``x * W + l``),
so that each multiply-add of M1-M3 is one vector instruction on the group
(``kernels/lanes.py``) instead of ``W`` scalar ones: the scalar pass's own
``chain_motors``, ``move_axes_inertias`` and ``minverse_recursion`` run on the lane twin of
its workspace (``kernels.lane_arrays``), the same operations in the same order, so that
each sample's numbers are those of its single call. Only the joint scalars (eq. 6) are
computed one sample at a time. Each sample's matrix is written out whole, row by row, ``W``
columns at a time (a transpose of ``W`` vectors in registers, ``store_transposed``), the
lower half read from the upper (M4).

A group in which any sample fails a check (a quaternion, a pivot D_j that is not positive,
a result that is not finite) is computed again one sample at a time by ``minverse_core``,
which reports the first fault exactly as a single call does; so are the samples after the
last whole group (``_groups.in_groups``).
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels.lane_arrays import lane_array, lane_matrix
from ..kernels.lanes import W, fma, lane, load, scatter, splat, store_transposed
from ..multibody.joints import joint_scalars
from . import _workspace as ws
from ._checks import check_configuration
from ._groups import in_groups
from ._stream import STREAM_FLOATS, stream_copy
from .kinematics import chain_motors
from .minverse import minverse_core, minverse_recursion, mirror_upper, move_axes_inertias
from .status import OK
from .work.minverse import lane_workspace
from .work.minverse import workspace as scalar_workspace
from .work.minverse_lanes import workspace

WORKSPACE = {  # a group's arrays, in order (tools/generate_workspaces.py)
    "scalar": ("size(minverse)",),  # the one-sample pass's, for a sample on its own
    "lanes": ("W * size(minverse)",),  # its lane twin, for a group
    "c": ("nq",),  # one sample's joint scalars
    "s": ("nq",),
    "Ql": ("nq * W",),  # the group's q and joint scalars c, s
    "Cl": ("nq * W",),
    "Snl": ("nq * W",),
    "Xl": ("nv * nv * W",),  # M⁻¹, its entry [r, c] at (r nv + c) W
    "Ol": ("W", "nv", "nv"),  # the group's results before they are streamed
}


@core
def minverse_group(m, q, Minv, start, stop, work):
    """``Minv[b] = M(q[b])⁻¹`` for the samples ``start .. stop`` of a batch; a status (at
    the sample of the first fault)."""
    k_ = workspace(ws.data_pointer(work), m)
    return in_groups(_group, _single, start, stop,
                     (m, q, Minv, Minv.size > STREAM_FLOATS, k_, work))


@inline
def _single(i, args):
    """Sample ``i`` alone (``minverse_core``); a status."""
    m, q, Minv, _, _, work = args
    return minverse_core(m, q[i], Minv[i], work)


@core
def group_inverse(m, Ql, Cl, Snl, Minv, b, work):
    """``Minv[b + l] = M(q[b + l])⁻¹`` for the ``W`` samples from ``b``, from their q and
    joint scalars c, s (nq) side by side, configurations already checked; in a workspace of
    ``workspace_size``. False if one of them needs the one-at-a-time path."""
    return _from_scalars(m, Ql, Cl, Snl, Minv, b, False, workspace(ws.data_pointer(work), m))


@inline
def _group(b, args):
    """Samples ``b .. b + W``; False if one of them needs the one-at-a-time path. ``Minv``
    is C-contiguous (the batch's output, allocated by ``calls``)."""
    m, q, Minv, streamed, k_, _ = args
    c, s, Ql, Cl, Snl = k_.c, k_.s, k_.Ql, k_.Cl, k_.Snl
    for l in range(W):  # each sample's q and joint scalars, laid side by side
        x = q[b + l]
        if check_configuration(m, x) != OK:
            return False
        joint_scalars(x, c, s)
        for i in range(m.nq):
            Ql[i * W + l], Cl[i * W + l], Snl[i * W + l] = x[i], c[i], s[i]
    return _from_scalars(m, Ql, Cl, Snl, Minv, b, streamed, k_)


@inline
def _from_scalars(m, Ql, Cl, Snl, Minv, b, streamed, k_):
    """``_group`` from the group's q and joint scalars c, s side by side on: the world
    motors, then S_k and I_j (eqs. 4, 16, a free root at rest: M5), then M1-M3, on the
    lane twin of ``minverse``'s workspace."""
    kl, Xl, Ol, nv = lane_workspace(k_.lanes, m), k_.Xl, k_.Ol, m.nv
    chain_motors(m, lane_array(Ql, 0), lane_array(Cl, 0), lane_array(Snl, 0), kl.tmp8, kl.M,
                 kl.Mw, True)
    move_axes_inertias(m, kl.Mw, kl.par, kl.Sw, kl.Ih)
    units = scalar_workspace(ws.data_pointer(k_.scalar), m).units  # numbers (M5)
    if minverse_recursion(m, kl, units, lane_matrix(Xl, 0, nv)) >= 0:
        return False
    zero = splat(0.0)
    bad = zero
    for r in range(nv):
        for col in range(r, nv):  # NaN where a number is not finite
            bad = fma(load(Xl, (r * nv + col) * W), zero, bad)
    for l in range(W):
        if lane(bad, l) != 0.0:
            return False
    if nv < W:  # each sample's upper triangle, then mirrored within its matrix (M4)
        for r in range(nv):
            for col in range(r, nv):
                scatter(Minv, (b * nv + r) * nv + col, nv * nv, load(Xl, (r * nv + col) * W))
        for l in range(W):
            mirror_upper(Minv[b + l])
        return True
    out, o = (Ol, 0) if streamed else (Minv, b * nv * nv)  # streamed: written, then copied
    for r in range(nv):  # row r of each sample, W columns at a time, the lower half (M4)
        c = 0  # read from the upper one; the last W columns overlap the ones before
        while c < nv:
            c = min(c, nv - W)
            store_transposed(out, o + r * nv + c, nv * nv, _entry(Xl, nv, r, c),
                             _entry(Xl, nv, r, c + 1), _entry(Xl, nv, r, c + 2),
                             _entry(Xl, nv, r, c + 3), _entry(Xl, nv, r, c + 4),
                             _entry(Xl, nv, r, c + 5), _entry(Xl, nv, r, c + 6),
                             _entry(Xl, nv, r, c + 7))
            c += W
    if streamed:
        for l in range(W):
            stream_copy(Ol[l], Minv[b + l])
    return True


@inline
def _entry(Xl, nv, r, c):
    """M⁻¹[r, c] of the group, from its upper triangle (M4)."""
    if c < r:
        return load(Xl, (c * nv + r) * W)
    return load(Xl, (r * nv + c) * W)
