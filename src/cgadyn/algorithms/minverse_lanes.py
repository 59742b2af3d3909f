"""``minverse`` on a batch: M1-M3 of ``minverse.py`` for ``W`` samples at once.

Every sample of a batch runs the same recursion; only the numbers differ. Here the samples
of a group of ``W`` are laid side by side (element ``x`` of sample ``l`` at ``x * W + l``),
so that each multiply-add of M1-M3 is one vector instruction on the group
(``kernels/lanes.py``) instead of ``W`` scalar ones. The equations are the scalar pass's
in its two special cases, which cover every model cgadyn reads: a joint of one
coordinate, whose D_j is a number and whose sums into its parent take one multiply-add
each, and a free-flyer root in its own frame (M5), whose unit twists pair by one
coefficient. (A model with any other joint would take the one-sample pass.) After the
articulated inertias they are taken one torque column at a time (``_lanes_pass``), so that
the working set stays small. The numbers agree with the scalar pass to rounding. Each
sample's matrix is written out whole, row by row, ``W`` columns at a time (a transpose of
``W`` vectors in registers, ``store_transposed``), the lower half read from the upper (M4).

Each sample's joint scalars (eq. 6) are computed one sample at a time and laid side by
side; from them the world motors and the S_k and I_j in the world (eqs. 4-6 and 16, M5) are
computed for the whole group at once, by the scalar pass's own ``chain_motors`` and
``move_axes_inertias`` on arrays of vectors (``kernels.lane_arrays``). A group
in which any sample fails a check (a quaternion, a pivot D_j that is not positive, a result
that is not finite) is computed again one sample at a time by ``minverse_core``, which
reports the first fault exactly as a single call does; so do the samples after the last
whole group.
"""

from __future__ import annotations

import math

from .._jit import core, inline
from ..kernels.lane_arrays import lane_array, lane_matrix, lane_tensor
from ..kernels.lanes import (
    W,
    add,
    div,
    fence,
    fma,
    fnma,
    lane,
    load,
    mul,
    scatter,
    splat,
    store,
    store_transposed,
    sub,
)
from ..multibody.joints import joint_scalars
from . import _workspace as ws
from ._checks import check_configuration
from ._stream import STREAM_FLOATS, stream_copy
from .kinematics import chain_motors, free_root, unit_coefficient
from .minverse import minverse_core, mirror_upper, move_axes_inertias
from .status import OK, at_sample
from .work.minverse_lanes import workspace

WORKSPACE = {  # a group's arrays, in order (tools/generate_workspaces.py)
    "scalar": ("size(minverse)",),  # the one-sample pass's, for a sample on its own
    "Sw": ("nv", 6),  # the first sample's S_k
    "c": ("nq",),  # one sample's joint scalars
    "s": ("nq",),
    "Ql": ("nq * W",),  # the group's q and joint scalars c, s
    "Cl": ("nq * W",),
    "Snl": ("nq * W",),
    "T8l": ("8 * W",),  # a motor's scratch
    "Mjl": ("n * 8 * W",),  # the joint and world motors
    "Mwl": ("n * 8 * W",),
    "Rl": ("10 * W",),  # ten parameters of an inertia
    "Sl": ("nv * 6 * W",),  # S, Î, U, G (``_lanes_pass``'s layout)
    "Il": ("n * 36 * W",),
    "Ul": ("nv * 6 * W",),
    "Gl": ("nv * 6 * W",),
    "Al": ("n * 6 * W",),  # one column's A_j
    "Ml": ("nv * nv * W",),  # M⁻¹
    "Dl": ("36 * W",),  # D, D⁻¹
    "Pl": ("36 * W",),
    "Tl": ("12 * W",),  # two scratch rows
    "pk": (12,),  # a free root's unit coefficients
    "Ol": ("W", "nv", "nv"),  # the group's results before they are streamed
}


@core
def minverse_group(m, q, Minv, start, stop, work):
    """``Minv[b] = M(q[b])⁻¹`` for the samples ``start .. stop`` of a batch; a status (at
    the sample of the first fault)."""
    k_ = workspace(ws.data_pointer(work), m)
    b = start
    lanes = in_lanes(m)
    streamed = Minv.size > STREAM_FLOATS
    while lanes and b + W <= stop:
        if not _group(m, q, Minv, b, streamed, k_):
            for l in range(W):  # again one at a time, for the exact fault
                s = minverse_core(m, q[b + l], Minv[b + l], work)
                if s != OK:
                    return at_sample(s, b + l)
        b += W
    for i in range(b, stop):
        s = minverse_core(m, q[i], Minv[i], work)
        if s != OK:
            return at_sample(s, i)
    fence()
    return OK


@core
def group_inverse(m, Ql, Cl, Snl, Minv, b, work):
    """``Minv[b + l] = M(q[b + l])⁻¹`` for the ``W`` samples from ``b``, from their q and
    joint scalars c, s (nq) side by side, configurations already checked; in a workspace of
    ``workspace_size``, for a model of ``in_lanes``. False if one of them needs the
    one-at-a-time path."""
    return _from_scalars(m, Ql, Cl, Snl, Minv, b, False, workspace(ws.data_pointer(work), m))


@inline
def in_lanes(m):
    """True when every joint has one coordinate or is a free-flyer root, the two forms
    ``_lanes_pass`` has. (A joint of several coordinates below the root, which no model
    that cgadyn reads has, would take the one-sample pass.)"""
    for j in range(m.n):
        if m.iv[j + 1] - m.iv[j] != 1 and not free_root(m.parents[j], m.types[j]):
            return False
    return True


@inline
def _group(m, q, Minv, b, streamed, k_):
    """Samples ``b .. b + W``; False if one of them needs the one-at-a-time path. ``Minv``
    is C-contiguous (the batch's output, allocated by ``calls``)."""
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
    """``_group`` from the group's q and joint scalars c, s side by side on."""
    Sw, T8l, Mjl, Mwl, Rl, Sl, Il = k_.Sw, k_.T8l, k_.Mjl, k_.Mwl, k_.Rl, k_.Sl, k_.Il
    Ul, Gl, Al, Ml, Dl, Pl, Tl, pk, Ol = (k_.Ul, k_.Gl, k_.Al, k_.Ml, k_.Dl, k_.Pl, k_.Tl,
                                          k_.pk, k_.Ol)
    nv = m.nv
    Mw = lane_matrix(Mwl, 0, 8)  # the world motors, then S_k and I_j (eqs. 4, 16, M5)
    chain_motors(m, lane_array(Ql, 0), lane_array(Cl, 0), lane_array(Snl, 0),
                 lane_array(T8l, 0), lane_matrix(Mjl, 0, 8), Mw, True)
    move_axes_inertias(m, Mw, lane_array(Rl, 0), lane_matrix(Sl, 0, 6),
                       lane_tensor(Il, 0, 6, 6))
    for j in range(m.n):  # the first sample's S_k of a free root, for its unit twists
        if free_root(m.parents[j], m.types[j]):
            for x in range(m.iv[j] * 6, m.iv[j + 1] * 6):
                Sw[x // 6, x % 6] = lane(load(Sl, x * W), 0)
    if not _lanes_pass(m, Sw, Sl, Il, Ul, Gl, Al, Ml, Dl, Pl, Tl, pk):
        return False
    zero = splat(0.0)
    bad = zero
    for col in range(nv):
        for r in range(col + 1):  # NaN where a number is not finite
            bad = fma(load(Ml, (col * nv + r) * W), zero, bad)
    for l in range(W):
        if lane(bad, l) != 0.0:
            return False
    if nv < W:  # each sample's upper triangle, then mirrored within its matrix (M4)
        for r in range(nv):
            for col in range(r, nv):
                scatter(Minv, (b * nv + r) * nv + col, nv * nv, load(Ml, (col * nv + r) * W))
        for l in range(W):
            mirror_upper(Minv[b + l])
        return True
    out, o = (Ol, 0) if streamed else (Minv, b * nv * nv)  # streamed: written, then copied
    for r in range(nv):  # row r of each sample, W columns at a time, the lower half (M4)
        c = 0  # read from the upper one; the last W columns overlap the ones before
        while c < nv:
            c = min(c, nv - W)
            store_transposed(out, o + r * nv + c, nv * nv, _entry(Ml, nv, r, c),
                             _entry(Ml, nv, r, c + 1), _entry(Ml, nv, r, c + 2),
                             _entry(Ml, nv, r, c + 3), _entry(Ml, nv, r, c + 4),
                             _entry(Ml, nv, r, c + 5), _entry(Ml, nv, r, c + 6),
                             _entry(Ml, nv, r, c + 7))
            c += W
    if streamed:
        for l in range(W):
            stream_copy(Ol[l], Minv[b + l])
    return True


@inline
def _entry(Ml, nv, r, c):
    """M⁻¹[r, c] of the group, from the upper triangle (M4), stored by columns."""
    if c < r:
        return load(Ml, (r * nv + c) * W)
    return load(Ml, (c * nv + r) * W)


@core
def _lanes_pass(m, Sw, Sl, Il, Ul, Gl, Al, Ml, Dl, Pl, Tl, pk):
    """M1-M3 on ``W`` samples (``minverse_pass`` with a vector for every number): the upper
    triangle of M⁻¹ into ``Ml``, column by column; False if a pivot of some D_j is not
    positive. Offsets: S_k, U_k, G_k at ``(k*6 + i)*W``, Î_j at ``((j*6 + i)*6 + a)*W``,
    A_j at ``(j*6 + i)*W``, M⁻¹[r, c] at ``(c*nv + r)*W`` (a column is contiguous), D_j,
    D_j⁻¹ at ``(a*6 + b)*W``. ``Sw`` holds the first sample's S_k (a free root's unit
    twists, the same in every sample), ``pk`` (12) is scratch.

    The articulated inertias and D_j (M1 and M2's Î_λ) go first, joint by joint. What
    remains of M2, then M3, acts on each torque column c alone, and is done one column at
    a time: F_j[c] is zero unless j is on the path from c's joint to the root, so M2's
    sums into the parent carry a single wrench up that path (``_column_backward``), and M3
    needs the accelerations A_j[c] of one column only (``_column_forward``). The same
    products as joint by joint, in the same order for each entry; but the working set is
    one column (n x 6 vectors) instead of F's n x nv x 6, which for a humanoid does not
    fit in L1.

    Every joint has one coordinate or is a free-flyer root (M5): the scalar pass's two
    special cases, which between them cover every model cgadyn reads (``in_lanes``)."""
    nv = m.nv
    for j in range(m.n - 1, -1, -1):
        k0, parent = m.iv[j], m.parents[j]
        if free_root(parent, m.types[j]):
            _root_units(Sw, k0, pk)
            ok = _root_inertia(Il, Ml, Dl, Pl, pk, j, k0, nv, m.armature)
        else:
            ok = _one_inertia(Sl, Il, Ul, Gl, Ml, j, parent, k0, nv, m.armature[k0])
        if not ok:
            return False
    for col in range(nv):  # M2 reads D_j⁻¹ from the diagonal, which M3 then changes
        _column_backward(m, Sl, Ul, Ml, Pl, Tl, pk, col)
    for col in range(nv):
        _column_forward(m, Sl, Gl, Al, Ml, pk, col)
    return True


@inline
def _root_units(Sw, k0, pk):
    """A free root's unit twists S_k (M5): ``pk[a]`` the index of S_{k0+a}'s one
    coefficient, ``pk[6 + a]`` its value."""
    for a in range(6):
        i, x = unit_coefficient(Sw[k0 + a])
        pk[a], pk[6 + a] = i, x


@core
def _root_inertia(Il, Ml, Dl, Pl, pk, j, k0, nv, armature):
    """(M1, M2) for a free-flyer root in its own frame (M5): with S_a = s_a e_{i_a},
    ``D_j[a, b] = s_a s_b Î_j[i_a, i_b]``, and M⁻¹[j, j] = D_j⁻¹ (in ``Pl`` too); U_j and
    G_j are not needed, for there is no parent to pass anything to."""
    for a in range(6):
        o = (j * 6 + int(pk[a])) * 6
        for b in range(6):
            x = mul(splat(pk[6 + a] * pk[6 + b]), load(Il, (o + int(pk[b])) * W))
            if a == b:
                x = add(x, splat(armature[k0 + a]))  # + the rotors' inertia
            store(Dl, (a * 6 + b) * W, x)
    if not _spd_inverse(Dl, 6, Pl):
        return False
    for a in range(6):
        for b in range(6):  # M⁻¹[j, j] = D_j⁻¹ (M2)
            store(Ml, ((k0 + b) * nv + k0 + a) * W, load(Pl, (a * 6 + b) * W))
    return True


@core
def _one_inertia(Sl, Il, Ul, Gl, Ml, j, parent, k, nv, armature):
    """(M1, M2) for a joint of one coordinate ``k``: U_j, D_j (a number in every lane),
    M⁻¹[j, j] = D_j⁻¹, G_j = D_j⁻¹ U_j and the parent's articulated inertia."""
    for i in range(6):  # U_j = Î_j[S_j] (M1)
        store(Ul, (k * 6 + i) * W, _dot6(Il, (j * 6 + i) * 6 * W, Sl, k * 6 * W))
    d = add(_dot6(Sl, k * 6 * W, Ul, k * 6 * W), splat(armature))  # D_j = ⟨S_j, U_j⟩ + rotor
    for l in range(W):
        x = lane(d, l)
        if not (x > 0.0 and math.isfinite(1.0 / x)):
            return False
    omega = div(splat(1.0), d)
    store(Ml, (k * nv + k) * W, omega)  # M⁻¹[j, j] = D_j⁻¹ (M2)
    for i in range(6):  # G_j = D_j⁻¹ U_j
        store(Gl, (k * 6 + i) * W, mul(omega, load(Ul, (k * 6 + i) * W)))
    if parent < 0:
        return True
    for i in range(6):  # Î_λ += Î_j - U_j D_j⁻¹ U_jᵀ (M2)
        u = load(Ul, (k * 6 + i) * W)
        for e in range(6):
            o, f = ((parent * 6 + i) * 6 + e) * W, ((j * 6 + i) * 6 + e) * W
            store(Il, o, fnma(u, load(Gl, (k * 6 + e) * W), add(load(Il, o), load(Il, f))))
    return True


@core
def _column_backward(m, Sl, Ul, Ml, Pl, Tl, pk, col):
    """M2's column ``col`` on the path from its joint to the root: F_λ[c] = F_j[c] +
    U_j M⁻¹[j, c], carried up in ``Tl`` (the only nonzero F_j[c] are on that path), and
    M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ on the way. A free root's own columns are D_j⁻¹
    (``_root_inertia``)."""
    nv, j = m.nv, m.dof_joint[col]
    if free_root(m.parents[j], m.types[j]):
        return
    zero = splat(0.0)
    x = load(Ml, (col * nv + col) * W)
    for i in range(6):  # F_λ[c] = U_j M⁻¹[j, c], c being j's own coordinate
        store(Tl, i * W, fma(load(Ul, (col * 6 + i) * W), x, zero))
    j = m.parents[j]
    while j >= 0:
        k, parent = m.iv[j], m.parents[j]
        if free_root(parent, m.types[j]):  # M5: ⟨S_b, F⟩ = s_b F[i_b]
            for b in range(6):
                store(Tl, (6 + b) * W, mul(splat(pk[6 + b]), load(Tl, int(pk[b]) * W)))
            for a in range(6):
                store(Ml, (col * nv + k + a) * W, sub(zero, _dot6(Pl, a * 6 * W, Tl, 6 * W)))
            return
        minus = sub(zero, load(Ml, (k * nv + k) * W))
        x = mul(minus, _dot6(Sl, k * 6 * W, Tl, 0))
        store(Ml, (col * nv + k) * W, x)  # M⁻¹[j, c] = -D_j⁻¹ ⟨S_j, F_j[c]⟩ (M2)
        if parent >= 0:
            for i in range(6):  # F_λ[c] = F_j[c] + U_j M⁻¹[j, c] (M2)
                store(Tl, i * W, fma(load(Ul, (k * 6 + i) * W), x, load(Tl, i * W)))
        j = parent


@core
def _column_forward(m, Sl, Gl, Al, Ml, pk, col):
    """(M3) for column ``col``: every joint up to the column's own, in order. An entry
    M⁻¹[j, c] that M2 left out (``col`` not below j) starts from zero."""
    nv, last = m.nv, m.dof_joint[col]
    zero = splat(0.0)
    for j in range(last + 1):
        k, parent = m.iv[j], m.parents[j]
        if free_root(parent, m.types[j]):  # A_j[c] = S_j M⁻¹[j, c], a coefficient each
            for i in range(6):
                store(Al, (j * 6 + i) * W, zero)
            for a in range(6):
                x = load(Ml, (col * nv + k + a) * W)
                store(Al, (j * 6 + int(pk[a])) * W, mul(splat(pk[6 + a]), x))
            continue
        o = (col * nv + k) * W
        x = load(Ml, o) if col < m.subtree_end[j] else zero
        if parent >= 0:  # M⁻¹[j, c] -= ⟨D⁻¹U_j, A_λ[c]⟩ (M3)
            x = sub(x, _dot6(Gl, k * 6 * W, Al, parent * 6 * W))
        store(Ml, o, x)
        for i in range(6):  # A_j[c] = A_λ[c] + S_j M⁻¹[j, c] (M3)
            a = load(Al, (parent * 6 + i) * W) if parent >= 0 else zero
            store(Al, (j * 6 + i) * W, fma(load(Sl, (k * 6 + i) * W), x, a))


@core
def _dot6(X, x, Y, y):
    """``Σ_i X[i] Y[i]`` over six vectors of ``W`` lanes at offsets ``x`` and ``y``."""
    s = mul(load(X, x), load(Y, y))
    s = fma(load(X, x + W), load(Y, y + W), s)
    s = fma(load(X, x + 2 * W), load(Y, y + 2 * W), s)
    s = fma(load(X, x + 3 * W), load(Y, y + 3 * W), s)
    s = fma(load(X, x + 4 * W), load(Y, y + 4 * W), s)
    return fma(load(X, x + 5 * W), load(Y, y + 5 * W), s)


@core
def _spd_inverse(Dl, k, Pl):
    """``_dense.spd_inverse`` on ``W`` samples: ``Pl = Dl⁻¹`` (k x k, rows of 6), ``Dl``
    overwritten; False if a pivot of some sample is not positive or its inverse not
    finite."""
    one = splat(1.0)
    for i in range(k):
        for e in range(k):
            store(Pl, (i * 6 + e) * W, one if i == e else splat(0.0))
    for p in range(k):
        pivot = load(Dl, (p * 6 + p) * W)
        for l in range(W):
            x = lane(pivot, l)
            if not (x > 0.0 and math.isfinite(1.0 / x)):
                return False
        r = div(one, pivot)
        for e in range(k):
            store(Dl, (p * 6 + e) * W, mul(load(Dl, (p * 6 + e) * W), r))
            store(Pl, (p * 6 + e) * W, mul(load(Pl, (p * 6 + e) * W), r))
        for i in range(k):
            if i != p:
                f = load(Dl, (i * 6 + p) * W)
                for e in range(k):
                    o, t = (i * 6 + e) * W, (p * 6 + e) * W
                    store(Dl, o, fnma(f, load(Dl, t), load(Dl, o)))
                    store(Pl, o, fnma(f, load(Pl, t), load(Pl, o)))
    return True

