"""``aba_derivatives`` on a batch: the forward pass at q̈ = 0 and M⁻¹ for ``W`` samples at
once.

The forward pass of the rnea derivatives at q̈ = 0, with which ``aba_derivatives`` begins
(D13), runs on a group of ``W`` samples side by side as in ``rnea_derivatives_lanes``
(``forward_in_lanes``), and so does M⁻¹, by the articulated-body recursion of ``minverse``
(M1-M5, ``minverse_lanes.group_inverse``), written straight into the result ∂q̈/∂τ. Each
sample then goes on alone (``from_inverse``: the bias, q̈ = M⁻¹ (τ - τ(q, v, 0)), the
backward pass and the products with M⁻¹): M is neither formed nor factorised, which on
a group costs more than the recursion does on eight samples at once. A group in which a
sample fails a check is computed again one sample at a time by ``aba_derivatives_core``,
which reports the first fault exactly as a single call does; so are the samples after the
last whole group. (A model with a joint that the recursion in lanes does not take would
go on from the forward pass as a single call does, ``from_forward``.)
"""

from __future__ import annotations

import numpy as np

from .._jit import core, inline
from ..kernels.lane_arrays import offset_in
from ..kernels.lanes import W
from . import _workspace as ws
from .aba_derivatives import _workspace as scalar_workspace
from .aba_derivatives import aba_derivatives_core, from_forward, from_inverse
from .aba_derivatives import workspace_size as scalar_size
from .minverse_lanes import group_inverse, in_lanes
from .minverse_lanes import workspace_size as inverse_size
from .rnea_derivatives import _workspace as rnea_derivatives_workspace
from .rnea_derivatives import workspace_size as rnea_derivatives_size
from .rnea_derivatives_lanes import forward_in_lanes
from .status import OK, at_sample


@core
def aba_derivatives_group(m, q, v, tau, f, o0, o1, o2, start, stop, work):
    """``aba_derivatives`` of the samples ``start .. stop`` of a batch, the forward pass
    and M⁻¹ ``W`` samples at a time; a status (at the sample of the first fault)."""
    samples, lanes, Ql, Vl, Al, Fl, inverse = _workspace(ws.data_pointer(work), m)
    o = offset_in(scalar_workspace(ws.data_pointer(samples[0]), m)[-1], samples[0])
    c = offset_in(rnea_derivatives_workspace(ws.data_pointer(samples[0, o:]), m)[-2],
                  samples[0]) - o  # the group's joint scalars c, s in ``lanes``
    Cl, Snl = lanes[c * W:(c + m.nq) * W], lanes[(c + m.nq) * W:(c + 2 * m.nq) * W]
    recursion = in_lanes(m)
    none = np.empty((0, 6))
    b = start
    while b + W <= stop:
        done = forward_in_lanes(m, q, v, tau, f, b, False, samples, o, lanes, Ql, Vl, Al, Fl)
        inverted = done and recursion and group_inverse(m, Ql, Cl, Snl, o2, b, inverse)
        for l in range(W):
            ok = False
            if inverted:
                ok = from_inverse(m, tau[b + l], o0[b + l], o1[b + l], o2[b + l],
                                  samples[l]) == OK
            elif done:
                ok = from_forward(m, tau[b + l], o0[b + l], o1[b + l], o2[b + l],
                                  samples[l]) == OK
            if ok:
                continue
            fb = f[b + l] if f.shape[0] > 0 else none  # again alone, for the exact fault
            s = aba_derivatives_core(m, q[b + l], v[b + l], tau[b + l], fb, o0[b + l],
                                     o1[b + l], o2[b + l], samples[l])
            if s != OK:
                return at_sample(s, b + l)
        b += W
    for i in range(b, stop):
        fb = f[i] if f.shape[0] > 0 else none
        s = aba_derivatives_core(m, q[i], v[i], tau[i], fb, o0[i], o1[i], o2[i],
                                 samples[0])
        if s != OK:
            return at_sample(s, i)
    return OK


@inline
def workspace_size(n, nq, nv, nl):
    return W * (scalar_size(n, nq, nv, nl) + rnea_derivatives_size(n, nq, nv, nl) + nq
                + 2 * nv + 6 * n) + inverse_size(n, nq, nv, nl)


@inline
def _workspace(buf, m):
    """``W`` one-sample workspaces (``aba_derivatives_core``'s, one after another), the
    group's workspace of the rnea derivatives (every number ``W`` numbers), the group's q
    (nq), v, q̈ = 0 (nv) and external wrenches (n, 6) side by side, and the workspace of
    ``group_inverse``."""
    samples, o = ws.carve(buf, 0, (W, scalar_size(m.n, m.nq, m.nv, m.nl)))
    lanes, o = ws.carve(buf, o, (W * rnea_derivatives_size(m.n, m.nq, m.nv, m.nl),))
    Ql, o = ws.carve(buf, o, (m.nq * W,))
    Vl, o = ws.carve(buf, o, (m.nv * W,))
    Al, o = ws.carve(buf, o, (m.nv * W,))
    Fl, o = ws.carve(buf, o, (m.n * 6 * W,))
    inverse, o = ws.carve(buf, o, (inverse_size(m.n, m.nq, m.nv, m.nl),))
    return samples, lanes, Ql, Vl, Al, Fl, inverse
