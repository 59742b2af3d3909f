"""``rnea_derivatives`` on a batch: the forward pass for ``W`` samples at once.

The forward pass of the rnea derivatives (motors, axes, inertias and their rates, twists,
accelerations, momenta, wrenches and the per-coordinate twists u, ψ, w: D2-D6, eqs. 4, 15,
16) does the same arithmetic on every sample. Here it runs on a group of ``W`` samples
laid side by side, one vector instruction per operation, by the scalar pass's own
``forward_from_scalars`` on arrays of vectors (``kernels.lane_arrays``), in a workspace
laid out as the scalar one with every number replaced by ``W`` (``lane_workspace``). Only the
joint scalars (eq. 6: the half-angle sines and cosines) are computed one sample at a time.
The first half of the backward pass, the composites and P, Q, G, H (D7,
D11, ``composites``), runs on the group too. What the entries read (S, u, ψ, w, P, Q, G,
H) is then written into each sample's own workspace, ``W`` numbers of every sample at a
time (a transpose in registers, ``store_transposed``), and the entries (D8-D10), whose
loops differ from joint to joint, are formed for each sample as in a single call; the
numbers agree with it to rounding.

A group in which a sample fails a check (a quaternion, a result that is not finite) is
computed again one sample at a time by ``rnea_derivatives_core``, which reports the first
fault exactly as a single call does; so are the samples after the last whole group
(``_groups.in_groups``).
Results larger than ``_stream.STREAM_FLOATS`` are written past the caches (``_stream``).
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels.lane_arrays import lane_array, lane_matrix, offset_in
from ..kernels.lanes import W, gather, load, store, store_transposed
from ..multibody.joints import joint_scalars
from . import _workspace as ws
from ._checks import check_configuration, check_result
from ._groups import in_groups
from ._stream import STREAM_FLOATS, stream_copy
from .rnea_derivatives import (
    composites,
    entries,
    forward_from_scalars,
    rnea_derivatives_core,
)
from .status import OK
from .work.rnea_derivatives import lane_workspace
from .work.rnea_derivatives import workspace as scalar_workspace
from .work.rnea_derivatives_lanes import workspace

WORKSPACE = {  # a group's arrays, in order (tools/generate_workspaces.py)
    "samples": ("W", "size(rnea_derivatives)"),  # each sample's scalar workspace
    "lanes": ("W * size(rnea_derivatives)",),  # the group's: every number W numbers
    "Ql": ("nq * W",),  # the group's q, v, a side by side
    "Vl": ("nv * W",),
    "Al": ("nv * W",),
    "Fl": ("n * 6 * W",),  # and its external wrenches
    "r0": ("nv", "nv"),  # a sample's three results before they are streamed
    "r1": ("nv", "nv"),
    "r2": ("nv", "nv"),
}


@core
def rnea_derivatives_group(m, q, v, a, f, o0, o1, o2, start, stop, work):
    """``rnea_derivatives`` of the samples ``start .. stop`` of a batch, ``W`` at a time; a
    status (at the sample of the first fault)."""
    streamed = o0.size + o1.size + o2.size > STREAM_FLOATS
    none = ws.bare_view(ws.data_pointer(work), (0, 6))  # no external wrenches
    return in_groups(_group, _single, start, stop,
                     (m, q, v, a, f, o0, o1, o2, streamed, workspace(ws.data_pointer(work), m),
                      none))


@inline
def _single(i, args):
    """Sample ``i`` alone (``rnea_derivatives_core``); a status."""
    m, q, v, a, f, o0, o1, o2, streamed, k_, none = args
    fi = f[i] if f.shape[0] > 0 else none  # no external wrenches
    t0, t1, t2 = (k_.r0, k_.r1, k_.r2) if streamed else (o0[i], o1[i], o2[i])
    s = rnea_derivatives_core(m, q[i], v[i], a[i], fi, t0, t1, t2, k_.samples[0])
    if s == OK and streamed:
        _stream_out(k_.r0, k_.r1, k_.r2, o0[i], o1[i], o2[i])
    return s


@inline
def _group(b, args):
    """Samples ``b .. b + W``; False if one of them needs the one-at-a-time path."""
    m, q, v, a, f, o0, o1, o2, streamed, k_, _ = args
    samples, r0, r1, r2 = k_.samples, k_.r0, k_.r1, k_.r2
    if not forward_in_lanes(m, q, v, a, f, b, True, samples, 0, k_.lanes, k_.Ql, k_.Vl, k_.Al,
                            k_.Fl):
        return False
    for l in range(W):
        t0, t1, t2 = (r0, r1, r2) if streamed else (o0[b + l], o1[b + l], o2[b + l])
        entries(m, samples[l], t0, t1, t2)
        if check_result(t0) != OK or check_result(t1) != OK:
            return False
        if streamed:
            _stream_out(r0, r1, r2, o0[b + l], o1[b + l], o2[b + l])
    return True


@inline
def _stream_out(r0, r1, r2, o0, o1, o2):
    """A sample's three results, computed in ``r0, r1, r2``, copied out past the caches."""
    stream_copy(r0, o0)
    stream_copy(r1, o1)
    stream_copy(r2, o2)


@core
def forward_in_lanes(m, q, v, a, f, b, accelerated, samples, o, lanes, Ql, Vl, Al, Fl):
    """The forward pass of the samples ``b .. b + W`` on ``W`` samples at once in
    ``lanes``, then written into each sample's workspace: that of the rnea derivatives, at
    ``o`` in each row of ``samples``. With ``accelerated``, at q̈ = a and followed by the
    backward pass's first half (``composites``), whose results (S, u, ψ, w, P, Q, G, H) are
    all that the entries read; without, at q̈ = 0, and its results from A_j to w_k, all that
    the forward dynamics' passes read. False if a sample fails its configuration check."""
    nq, nv, size = m.nq, m.nv, samples.shape[1]
    k0 = scalar_workspace(ws.data_pointer(samples[0, o:]), m)  # every workspace's layout
    forces = f.shape[0] > 0
    for l in range(W):  # q, v, a, f_ext side by side; each sample's c, s in its workspace
        x = q[b + l]
        if check_configuration(m, x) != OK:
            return False
        k_ = scalar_workspace(ws.data_pointer(samples[l, o:]), m)
        joint_scalars(x, k_.c, k_.s)
        for i in range(nq):
            Ql[i * W + l] = x[i]
        for i in range(nv):
            Vl[i * W + l] = v[b + l, i]
            Al[i * W + l] = a[b + l, i] if accelerated else 0.0
        if forces:
            for j in range(m.n):
                for i in range(6):
                    Fl[(j * 6 + i) * W + l] = f[b + l, j, i]
    c0 = offset_in(k0.c, samples[0])
    for i in range(2 * nq):  # c, s follow one another
        store(lanes, (c0 - o + i) * W, gather(samples, c0 + i, size))
    kl = lane_workspace(lanes, m)  # the same arrays for the group
    forward_from_scalars(m, lane_array(Ql, 0), lane_array(Vl, 0), lane_array(Al, 0),
                         lane_matrix(Fl, 0, 6), forces, kl)
    if accelerated:  # S, u, ψ, w, P, Q, G, H follow one another
        composites(m, kl)
        lo, hi = offset_in(k0.Sw, samples[0]), offset_in(k0.H, samples[0]) + 6 * nv
    else:  # A, h, F, I, İ, S, u, ψ, w follow one another
        lo, hi = offset_in(k0.A, samples[0]), offset_in(k0.Wv, samples[0]) + 6 * nv
    x = lo
    while x < hi:  # into each sample's workspace, the last W overlapping
        x = min(x, hi - W)
        y = (x - o) * W
        store_transposed(samples, x, size, load(lanes, y), load(lanes, y + W),
                         load(lanes, y + 2 * W), load(lanes, y + 3 * W),
                         load(lanes, y + 4 * W), load(lanes, y + 5 * W),
                         load(lanes, y + 6 * W), load(lanes, y + 7 * W))
        x += W
    return True

