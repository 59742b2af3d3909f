"""dask arrays in, dask arrays out: the batch algorithms and ``simulate`` on chunks of samples.

A dask array of states ``(B, n)``, chunked along B, is computed chunk by chunk: each chunk
is one compiled batch call (``calls.run`` on numpy arrays, parallel over the chunk's
samples with numba's threads), scheduled by dask (``dask.array.map_blocks``). The same code
therefore runs on a laptop (dask's threads) or on a ``dask.distributed`` cluster (the
model travels to the workers by pickle: a ``Model`` pickles to a few kilobytes).

This module lies above the call layer and ``sim``: it imports them, they never import it.
``cgadyn/__init__.py`` declares it the server of dask arrays (``_arrays``), and the checked
paths of ``calls.run`` and ``simulate`` hand it their inputs when one of them is a dask
array (``run``, ``simulate`` below); nothing here is imported, nor dask, before such an
array arrives. The one-sample fast path never sees a dask array.
"""

from __future__ import annotations

import re
import threading
import warnings

import numpy as np

from .algorithms.table import BY_NAME


def is_dask(x) -> bool:
    """True for a dask collection (without importing dask)."""
    return type(x).__module__.startswith("dask")


def _aligned(arrays: tuple, sizes: tuple[int, ...], lead=None):
    """The inputs as dask arrays ``(B, size)`` with the row chunks of ``lead`` (by default
    the first dask input); a numpy (size,) input is shared by every row."""
    import dask.array as da

    lead = next(a for a in arrays if is_dask(a)) if lead is None else lead
    if lead.ndim != 2 and lead is arrays[0]:
        raise ValueError(f"a dask array of states must have shape (B, n), got {lead.shape}")
    B, rows = lead.shape[0], lead.chunks[0]
    out = []
    for a, size in zip(arrays, sizes, strict=True):
        if not is_dask(a):
            a = np.asarray(a, dtype=float)
            if a.shape != (size,):
                raise ValueError(f"with dask arrays of states, every other state must be a "
                                 f"dask array (B, {size}) or one sample ({size},), got "
                                 f"{a.shape}")
            a = da.broadcast_to(a, (B, size), chunks=(rows, size))
        if a.ndim != 2 or a.shape != (B, size):
            raise ValueError(f"dask arrays of states must have shapes (B, n) with one B: "
                             f"expected ({B}, {size}), got {a.shape}")
        out.append(a.astype(float).rechunk((rows, size)))
    return out


def _first_row(block_info) -> int:
    """The global index of a chunk's first row (sample or rollout): dask's ``block_info``
    gives the output block's location in the whole array."""
    if not block_info or None not in block_info:  # dask's call on empty arrays for meta
        return 0
    return int(block_info[None]["array-location"][0][0])


_SAMPLE_INDEX = (
    re.compile(r"\bat index \((?P<i>\d+), "),  # "q contains NaN or inf at index (i, k)"
    re.compile(r"^sample (?P<i>\d+): "),        # "sample i: singular ..."
    re.compile(r"\b\w+\[(?P<i>\d+), "),          # "q[i, 3:7], the quaternion ..."
)
"""Where ``errors.explain`` names a sample of a batch: the index ``i`` is the chunk's."""


def _shift(match: re.Match, offset: int) -> str:
    start, end = match.span("i")
    text = match.group(0)
    base = match.start(0)
    return text[:start - base] + str(int(match.group("i")) + offset) + text[end - base:]


def _global_samples(message: str, offset: int) -> str:
    """A chunk's error message with its sample indices made indices of the whole array:
    ``calls.run`` sees the chunk alone and counts its samples from 0."""
    for pattern in _SAMPLE_INDEX:
        message = pattern.sub(lambda m: _shift(m, offset), message)
    return message


def _run_block(name, model, gravity, f_ext, options, *blocks, block_info=None):
    """One chunk: one compiled batch call; several outputs stacked on axis 1. An error
    names the sample by its index in the whole dask array, not in the chunk."""
    from .algorithms.calls import run

    try:
        out = run(name, model, blocks, gravity, f_ext, options)
    except ValueError as exc:
        raise ValueError(_global_samples(str(exc), _first_row(block_info))) from None
    return np.stack(out, axis=1) if isinstance(out, tuple) else out


def run(name: str, model, arrays: tuple, gravity, f_ext, options: tuple[int, ...] = ()):
    """Algorithm ``name`` (``table.py``) on dask arrays of states: a dask array, or a
    tuple of them, chunked along B like the inputs; ``f_ext`` one (n, 6) for all."""
    import dask.array as da

    alg = BY_NAME[name]
    sizes = {"n": model.njoints, "nq": model.nq, "nv": model.nv, "nl": model.nlinks}
    if f_ext is not None and np.shape(f_ext) != (model.njoints, 6):
        raise ValueError(f"with dask arrays of states, f_ext must be one (n, 6) = "
                         f"({model.njoints}, 6) array for every sample, got "
                         f"{np.shape(f_ext)}")
    x = _aligned(arrays, tuple(sizes[s] for _, s in alg.inputs))
    shapes = [tuple(sizes.get(d, d) for d in dims) for dims in alg.outputs]
    if len(shapes) == 1:
        return da.map_blocks(_run_block, name, model, gravity, f_ext, options, *x,
                             dtype=float, chunks=(x[0].chunks[0], *shapes[0]),
                             drop_axis=1, new_axis=list(range(1, 1 + len(shapes[0]))))
    if len(set(shapes)) != 1:  # not the case of any algorithm the dask path serves
        raise ValueError(f"{name} has outputs of different shapes; no dask path for it")
    stacked = da.map_blocks(_run_block, name, model, gravity, f_ext, options, *x,
                            dtype=float, chunks=(x[0].chunks[0], len(shapes), *shapes[0]),
                            drop_axis=1, new_axis=list(range(1, 2 + len(shapes[0]))))
    return tuple(stacked[:, i] for i in range(len(shapes)))


_ROLLOUT = re.compile(r"\brollout (\d+)\b")
_STOPPED = re.compile(r"\((\d+) of (\d+) rollouts stopped\)")


def _global_rollouts(message: str, offset: int, total: int) -> str:
    """A chunk's divergence message (``sim.simulate._message``) in terms of the whole
    batch: its rollout index plus the chunk's offset, and which rollouts the chunk holds
    (the others' stops are reported by their own chunks)."""
    message = _ROLLOUT.sub(lambda m: f"rollout {int(m.group(1)) + offset}", message)
    return _STOPPED.sub(lambda m: _chunk_note(int(m.group(1)), int(m.group(2)), offset, total),
                        message)


def _chunk_note(stopped: int, size: int, offset: int, total: int) -> str:
    """"(k of the b rollouts i-j of this dask chunk stopped; the batch holds B)"."""
    if size == 1:
        return f"(the only rollout of its dask chunk; the batch holds {total})"
    return (f"({stopped} of the {size} rollouts {offset}-{offset + size - 1} of this dask "
            f"chunk stopped; the batch holds {total})")


_WARNINGS = threading.Lock()
"""``warnings.catch_warnings`` swaps process-wide state: chunks running on dask's threads
take turns (their compiled loops take turns anyway, under ``simulate``'s lock)."""


def _simulate_chunk(model, dt, steps, kwargs, q0, v0, tau, offset: int, total: int):
    """``simulate`` on one chunk, its warnings and errors naming rollouts by their index
    in the whole batch of ``total``."""
    from .sim.simulate import SimulationDiverged, simulate

    try:
        with _WARNINGS, warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", SimulationDiverged)
            traj = simulate(model, q0, v0, dt, steps, tau=tau, **kwargs)
    except ValueError as exc:
        raise ValueError(_global_samples(str(exc), offset)) from None
    for w in caught:
        text = str(w.message)
        if issubclass(w.category, SimulationDiverged):
            text = _global_rollouts(text, offset, total)
        warnings.warn(text, w.category, stacklevel=3)
    return traj


def _simulate_block(model, dt, steps, kwargs, total, q0, v0, tau, block_info=None):
    """One chunk of rollouts: ``[q, v, a, T, U, completed, diverged]`` on the last axis."""
    q0, v0 = q0[:, 0], v0[:, 0]  # (b, 1, n): aligned with tau's axes for map_blocks
    traj = _simulate_chunk(model, dt, steps, kwargs, q0, v0, tau, _first_row(block_info),
                           total)
    B = q0.shape[0]
    flags = np.stack([np.asarray(traj.completed, dtype=float).reshape(B),
                      np.asarray(traj.diverged, dtype=float).reshape(B)], axis=1)
    return np.concatenate([traj.q, traj.v, traj.a, traj.kinetic[..., None],
                           traj.potential[..., None],
                           np.broadcast_to(flags[:, None, :], (B, traj.q.shape[1], 2))],
                          axis=-1)


def simulate(model, q0, v0, dt, steps, tau, kwargs: dict):
    """``cgadyn.simulate`` on dask arrays: ``q0`` (B, nq), ``v0`` (B, nv) (either may be one
    numpy sample), ``tau`` None, numpy (steps, nv) or dask (B, steps, nv). A ``Trajectory``
    of dask arrays (``t`` is numpy); nothing runs until they are computed, so a blow-up
    shows in ``completed`` and ``diverged`` (and as a warning where the chunk ran)."""
    import dask.array as da

    from .sim.rollout import kept_rows
    from .sim.simulate import _every, _steps, _times
    from .sim.trajectory import Trajectory

    steps = _steps(steps)
    every = _every(kwargs.get("record_every", 1), kwargs.get("final_only", False), steps)
    kept = kept_rows(steps, every)  # the rows of each rollout (``rollout.kept_row``)
    q0, v0 = _aligned((q0, v0), (model.nq, model.nv),
                      lead=tau if not (is_dask(q0) or is_dask(v0)) else None)
    rows = q0.chunks[0]
    if is_dask(tau):
        if tau.shape != (q0.shape[0], steps, model.nv):
            raise ValueError(f"a dask tau must have shape (B, steps, nv) = ({q0.shape[0]}, "
                             f"{steps}, {model.nv}), got {tau.shape}")
        tau = tau.astype(float).rechunk((rows, steps, model.nv))
    elif tau is not None:
        tau = np.asarray(tau, dtype=float)
        if tau.shape != (steps, model.nv):
            raise ValueError(f"with dask states, tau must be a dask array (B, steps, nv) or "
                             f"one numpy sequence (steps, nv) = ({steps}, {model.nv}), got "
                             f"{tau.shape}")
        tau = da.broadcast_to(tau, (q0.shape[0], steps, model.nv),
                              chunks=(rows, steps, model.nv))
    else:
        tau = da.zeros((q0.shape[0], steps, model.nv), chunks=(rows, steps, model.nv))
    nq, nv = model.nq, model.nv
    width = nq + 2 * nv + 4
    out = da.map_blocks(_simulate_block, model, float(dt), steps, kwargs, q0.shape[0],
                        q0[:, None, :],
                        v0[:, None, :], tau, dtype=float,
                        chunks=(rows, (kept,), (width,)))
    cut = np.cumsum([0, nq, nv, nv, 1, 1, 1, 1])
    q, v, a, T, U, done, diverged = (out[..., cut[i]:cut[i + 1]] for i in range(7))
    return Trajectory(t=_times(dt, steps, every, kept), q=q, v=v, a=a, kinetic=T[..., 0],
                      potential=U[..., 0],
                      completed=done[:, 0, 0].astype(np.int64),
                      diverged=diverged[:, 0, 0].astype(bool), dt=float(dt),
                      integrator=kwargs.get("integrator", "rk4"))
