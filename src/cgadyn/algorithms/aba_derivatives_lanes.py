"""``aba_derivatives`` on a batch: the forward pass at q̈ = 0 and M⁻¹ for ``W`` samples at
once.

The forward pass of the rnea derivatives at q̈ = 0, with which ``aba_derivatives`` begins
(D13), runs on a group of ``W`` samples side by side as in ``rnea_derivatives_lanes``
(``forward_in_lanes``), and so does M⁻¹, by the articulated-body recursion of ``minverse``
(M1-M5, ``minverse_lanes.group_inverse``), written straight into the result ∂q̈/∂τ. Each
sample then goes on alone (``from_inverse``: the bias, q̈ = M⁻¹ (τ - τ(q, v, 0)), the
backward pass and the products with M⁻¹): M is neither formed nor factorised, which on
a group costs more than the recursion does on eight samples at once. (A group whose M⁻¹
fails its checks goes on from the forward pass as a single call does, ``from_forward``.) A
group in which a sample fails a check is computed again one sample at a time by
``aba_derivatives_core``, which reports the first fault exactly as a single call does; so
are the samples after the last whole group (``_groups.in_groups``).
"""

from __future__ import annotations

from .._jit import core, inline
from ..kernels.lane_arrays import offset_in
from ..kernels.lanes import W
from . import _workspace as ws
from ._groups import in_groups
from .aba_derivatives import aba_derivatives_core, from_forward, from_inverse
from .minverse_lanes import group_inverse
from .rnea_derivatives_lanes import forward_in_lanes
from .status import OK
from .work.aba_derivatives import workspace as scalar_workspace
from .work.aba_derivatives_lanes import workspace
from .work.rnea_derivatives import workspace as rnea_derivatives_workspace

WORKSPACE = {  # a group's arrays, in order (tools/generate_workspaces.py)
    "samples": ("W", "size(aba_derivatives)"),  # each sample's scalar workspace
    "lanes": ("W * size(rnea_derivatives)",),  # the group's rnea derivatives workspace
    "Ql": ("nq * W",),  # the group's q, v, q̈ = 0 side by side
    "Vl": ("nv * W",),
    "Al": ("nv * W",),
    "Fl": ("n * 6 * W",),  # and its external wrenches
    "inverse": ("size(minverse_lanes)",),  # the workspace of ``group_inverse``
}


@core
def aba_derivatives_group(m, q, v, tau, f, o0, o1, o2, start, stop, work):
    """``aba_derivatives`` of the samples ``start .. stop`` of a batch, the forward pass
    and M⁻¹ ``W`` samples at a time; a status (at the sample of the first fault)."""
    k_ = workspace(ws.data_pointer(work), m)
    samples, lanes = k_.samples, k_.lanes
    o = offset_in(scalar_workspace(ws.data_pointer(samples[0]), m).rest, samples[0])
    c = offset_in(rnea_derivatives_workspace(ws.data_pointer(samples[0, o:]), m).c,
                  samples[0]) - o  # the group's joint scalars c, s in ``lanes``
    Cl, Snl = lanes[c * W:(c + m.nq) * W], lanes[(c + m.nq) * W:(c + 2 * m.nq) * W]
    none = ws.bare_view(ws.data_pointer(work), (0, 6))  # no external wrenches
    return in_groups(_group, _single, start, stop,
                     (m, q, v, tau, f, o0, o1, o2, o, Cl, Snl, k_, none))


@inline
def _single(i, args):
    """Sample ``i`` alone (``aba_derivatives_core``); a status."""
    m, q, v, tau, f, o0, o1, o2, _, _, _, k_, none = args
    fi = f[i] if f.shape[0] > 0 else none  # no external wrenches
    return aba_derivatives_core(m, q[i], v[i], tau[i], fi, o0[i], o1[i], o2[i],
                                k_.samples[0])


@inline
def _group(b, args):
    """Samples ``b .. b + W``: the forward pass and M⁻¹ at once, then each sample on its
    own; False if one of them needs the one-at-a-time path."""
    m, q, v, tau, f, o0, o1, o2, o, Cl, Snl, k_, _ = args
    samples = k_.samples
    if not forward_in_lanes(m, q, v, tau, f, b, False, samples, o, k_.lanes, k_.Ql, k_.Vl,
                            k_.Al, k_.Fl):
        return False
    inverted = group_inverse(m, k_.Ql, Cl, Snl, o2, b, k_.inverse)
    for l in range(W):
        i = b + l
        if inverted:
            s = from_inverse(m, tau[i], o0[i], o1[i], o2[i], samples[l])
        else:
            s = from_forward(m, tau[i], o0[i], o1[i], o2[i], samples[l])
        if s != OK:
            return False
    return True
