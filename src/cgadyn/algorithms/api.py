"""The Python-facing algorithms: validate, dispatch to one compiled call, return arrays.

Every function takes the model first and accepts one sample ``(n,)`` or a batch ``(B, n)``
(run in parallel over samples), returning the same leading shape. ``q, v, a, tau`` are
ordered like ``model.joint_names`` (Pinocchio's order); gravity is a world-frame 3-vector.
"""

from __future__ import annotations

import numba
import numpy as np

from ..cga.conventions import matrix_from_motor, motion_from_twist
from . import _inputs as chk
from ._fastcall import Compiled
from ._workspace import all_finite
from .aba import aba_batch, aba_single, aba_single_ext
from .crba import crba_batch, crba_single
from .energy import energy_batch
from .jacobian import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, jacobian_batch, jacobian_single
from .kinematics import link_motors_batch, link_motors_single
from .rnea import rnea_batch, rnea_single, rnea_single_ext

G = chk.DEFAULT_GRAVITY
_RNEA, _ABA, _CRBA = Compiled(rnea_single), Compiled(aba_single), Compiled(crba_single)
_RNEA_B, _ABA_B, _CRBA_B = Compiled(rnea_batch), Compiled(aba_batch), Compiled(crba_batch)
_RNEA_ALL = (_RNEA, Compiled(rnea_single_ext), _RNEA_B)
_ABA_ALL = (_ABA, Compiled(aba_single_ext), _ABA_B)
_ndarray, _empty = np.ndarray, np.empty  # module globals: one lookup less per call
_FAST_PATH_MISSES = (TypeError, ValueError, FloatingPointError, ZeroDivisionError)
"""A fast call that raises one of these is redone on the checked path, which normalises
the inputs or explains what is wrong with them."""


def rnea(model, q, v, a, gravity=G, f_ext=None) -> np.ndarray:
    """Joint torques ``τ`` of inverse dynamics (Algorithm 2): ``M(q) a + C(q, v) v + g(q)``.

    ``f_ext``: optional external force per joint, Pinocchio's ``[f, τ]`` in the joint frame.
    """
    if f_ext is None and gravity is G and type(q) is _ndarray:
        if q.ndim == 1:
            tau = _empty(len(q))  # the common case: one float64 sample, straight to the
            try:  # compiled code, which checks the types, lengths and finiteness
                _RNEA.fast(model.packed, q, v, a, tau)
                return tau
            except _FAST_PATH_MISSES:
                pass
        elif (tau := _fast_batch(_RNEA, _RNEA_B, model, (q, v, a), (model.nv,), None)) is not None:
            return tau
    return _checked(model, _RNEA_ALL, {"q": q, "v": v, "a": a}, gravity, f_ext)


def aba(model, q, v, tau, gravity=G, f_ext=None) -> np.ndarray:
    """Joint accelerations ``q̈`` of forward dynamics (Algorithms 1 and 3)."""
    if f_ext is None and gravity is G and type(q) is _ndarray:
        if q.ndim == 1:
            qdd = _empty(len(q))
            try:
                _ABA.fast(model.packed, q, v, tau, qdd)
                return qdd
            except _FAST_PATH_MISSES:
                pass
        elif (qdd := _fast_batch(_ABA, _ABA_B, model, (q, v, tau), (model.nv,), None)) is not None:
            return qdd
    return _checked(model, _ABA_ALL, {"q": q, "v": v, "tau": tau}, gravity, f_ext)


def crba(model, q) -> np.ndarray:
    """Joint-space mass matrix ``M(q)``, full and symmetric, (n, n) or (B, n, n)."""
    if type(q) is _ndarray:
        H = _empty(model.mass_matrix_shape)
        try:
            _CRBA.fast(model.packed, q, H)
            return H
        except _FAST_PATH_MISSES:  # not one float64 sample: a batch, or the checked path
            if (H := _fast_batch(_CRBA, _CRBA_B, model, (q,), model.mass_matrix_shape)) is not None:
                return H
    q = chk.state(model, q, "q")
    try:
        if q.ndim == 2 and len(q) > 1:
            return _CRBA_B.call(model.packed, q, _threads())
        H = np.empty(q.shape[:-1] + model.mass_matrix_shape)  # one sample, or (1, n)
        for b in np.ndindex(q.shape[:-1]):
            _CRBA.call(model.packed, q[b], H[b])
        return H
    except FloatingPointError:
        raise chk.explain(model, q=q) from None


def _fast_batch(single: Compiled, batch: Compiled, model, states: tuple, row: tuple,
                *options):
    """A (B, n) batch of C-contiguous float64 arrays straight to compiled code, which checks
    shapes and finiteness: one call of the batch entry (``options``: its arguments after the
    states), or a one-sample call for a (1, n) batch (starting numba's parallel loop costs
    more). ``row``: the shape of one sample's result. None when the arrays are refused or a
    result is not finite: the checked path then converts the inputs, or explains what is
    wrong."""
    q = states[0]
    try:
        if len(q) != 1:
            out = batch.fast(model.packed, *states, *options, _threads())
        else:
            for x in states:
                if type(x) is not _ndarray or x.shape != q.shape:
                    return None
            out = _empty((1, *row))
            single.fast(model.packed, *[x[0] for x in states], out[0])
    except _FAST_PATH_MISSES:
        return None
    return out if all_finite(out) else None


def _checked(model, algorithm: tuple, states: dict, gravity, f_ext) -> np.ndarray:
    """Any accepted input: normalise and check it, then a one-sample call (one sample, or a
    (1, n) batch) or one compiled call over a (B, n) batch. ``algorithm``: the single-sample
    entry points without and with external forces, and the batch entry."""
    single, single_ext, parallel = algorithm
    x = chk.states(model, tuple(states.values()), tuple(states))
    states = dict(zip(states, x, strict=True))
    packed = chk.packed(model, gravity)
    fe = chk.external(model, f_ext, x[0].shape[:-1])
    try:
        if x[0].ndim == 2 and len(x[0]) > 1:
            out = parallel.call(packed, *x, fe, _threads())
        else:  # one sample, or a (1, n) batch
            out = np.empty(x[0].shape)
            for b in np.ndindex(x[0].shape[:-1]):
                if fe is None:
                    single.call(packed, *(s[b] for s in x), out[b])
                else:
                    single_ext.call(packed, *(s[b] for s in x), fe[b], out[b])
    except FloatingPointError:
        raise chk.explain(model, **states) from None
    except ZeroDivisionError:
        raise _singular(model) from None
    if not all_finite(out):
        raise _singular(model) if single is _ABA else chk.explain(model, **states)
    return out


def gravity_torques(model, q, gravity=G) -> np.ndarray:
    """Generalized gravity ``g(q)``: RNEA with zero velocity and acceleration."""
    q = chk.state(model, q, "q")
    z = np.zeros_like(q)
    return rnea(model, q, z, z, gravity)


def nonlinear_effects(model, q, v, gravity=G) -> np.ndarray:
    """``C(q, v) v + g(q)``: RNEA with zero acceleration."""
    q = chk.state(model, q, "q")
    return rnea(model, q, v, np.zeros_like(q), gravity)


def forward_kinematics(model, q) -> tuple[np.ndarray, np.ndarray]:
    """World motors of the joint frames (..., n, 8) and of every link frame (..., nl, 8)."""
    q = chk.state(model, q, "q")
    _require_finite(model, q=q)
    args = (model.parents, model.joint_types, model.placements, model.axes, model.link_joint,
            model.link_placements, q)
    return link_motors_single(*args) if q.ndim == 1 else link_motors_batch(*args, _threads())


def link_placements(model, q) -> np.ndarray:
    """World 4x4 homogeneous matrices of every link frame, (..., nl, 4, 4)."""
    _, links = forward_kinematics(model, q)
    return matrix_from_motor(links)


_FRAMES = {"world": WORLD, "local": LOCAL, "local_world_aligned": LOCAL_WORLD_ALIGNED}


def jacobian(model, q, link: str | int, frame: str = "world", layout: str = "pinocchio"):
    """Geometric Jacobian of a link.

    ``frame``: ``'world'`` (twists at the world origin, Pinocchio's WORLD), ``'local'`` (in
    the link frame, LOCAL) or ``'local_world_aligned'`` (at the link origin, world axes).
    ``layout='pinocchio'`` returns Pinocchio's (..., 6, n) matrix, rows ``[v, ω]``;
    ``layout='twist'`` returns the CGA twist of each joint's column, (..., n, 6).
    """
    q = chk.state(model, q, "q")
    _require_finite(model, q=q)
    if frame not in _FRAMES:
        raise ValueError(f"frame must be one of {sorted(_FRAMES)}, got {frame!r}")
    if layout not in ("pinocchio", "twist"):
        raise ValueError(f"layout must be 'pinocchio' or 'twist', got {layout!r}")
    index = model.link_index(link) if isinstance(link, str) else int(link)
    if not 0 <= index < model.nlinks:
        raise ValueError(f"link index {index} out of range 0..{model.nlinks - 1}")
    args = (model.parents, model.joint_types, model.placements, model.axes, model.link_joint,
            model.link_placements, q, index, _FRAMES[frame])
    J = jacobian_single(*args) if q.ndim == 1 else jacobian_batch(*args, _threads())
    if layout == "twist":
        return J
    return np.swapaxes(motion_from_twist(J), -1, -2)


def energy(model, q, v, gravity=G) -> np.ndarray:
    """Kinetic and potential energy, ``[..., (T, U)]``; ``U = -Σ m g·c`` as in Pinocchio."""
    q = chk.state(model, q, "q")
    v = chk.state(model, v, "v")
    chk.same_batch(q, v, names=("q", "v"))
    _require_finite(model, q=q, v=v)
    g = np.array(chk.gravity_vector(gravity))
    out = energy_batch(model.packed, model.body_mass, model.body_com, np.atleast_2d(q),
                       np.atleast_2d(v), g, _threads())
    return out[0] if q.ndim == 1 else out


def kinetic_energy(model, q, v) -> np.ndarray | float:
    """``T = ½ Σ_j p(V_j, I_j[V_j])`` (eqs. 9, 15)."""
    e = energy(model, q, v)
    return e[..., 0] if e.ndim > 1 else float(e[0])


def potential_energy(model, q, gravity=G) -> np.ndarray | float:
    """``U = -Σ_j m_j g · c_j`` with c_j the world centre of mass of body j."""
    q = chk.state(model, q, "q")
    e = energy(model, q, np.zeros_like(q), gravity)
    return e[..., 1] if e.ndim > 1 else float(e[1])


def _threads() -> int:
    """numba's current thread count (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``)."""
    return numba.get_num_threads()


def _require_finite(model, **arrays) -> None:
    for a in arrays.values():
        if not all_finite(a):
            raise chk.explain(model, **arrays)


def _singular(model) -> ValueError:
    massless = [
        model.joint_names[j]
        for j in range(model.nv)
        if sum(model.body_mass[k] for k in model.subtree(j)) <= 0.0
    ]
    detail = (
        f"the subtree moved by joint(s) {', '.join(massless)} has zero mass"
        if massless
        else "a joint's articulated inertia along its axis is zero"
    )
    return ValueError(f"singular articulated-body inertia: {detail}; ABA cannot solve for q̈")
