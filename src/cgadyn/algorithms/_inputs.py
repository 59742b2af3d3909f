"""Checks and conversions of what users pass to the algorithms: states, gravity, f_ext, links.

Everything here runs on the checked path only (``calls.run``): a one-sample call whose
arrays are already C-contiguous float64 of the right length goes straight to compiled code,
which checks finiteness itself. Each function raises a ``ValueError`` that names the
argument, what was expected and what was given.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..cga.conventions import wrench_from_force
from ..multibody.joints.table import layout
from ..multibody.packed import DEFAULT_GRAVITY, with_gravity

_NUMERIC = "biuf"
"""numpy dtype kinds taken as numbers: bool, signed and unsigned integers, floats."""


def nonnegative(x, name: str) -> float:
    """``x`` as a float: a finite real number >= 0 (a bool is not one), else a
    ``ValueError`` naming ``name``; every setting that must be such a number is checked
    here."""
    if isinstance(x, bool) or not isinstance(x, numbers.Real) or not np.isfinite(x) or x < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {x!r}")
    return float(x)


def time_step(dt) -> float:
    """``dt`` in seconds as a float: a finite real number > 0 (a bool is not one), else a
    ``ValueError`` that says so; every entry that takes a time step checks it here."""
    if isinstance(dt, bool) or not isinstance(dt, numbers.Real) or not np.isfinite(dt) \
            or dt <= 0:
        raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
    return float(dt)


def state(model, x, name: str, size: int) -> np.ndarray:
    """``x`` as a contiguous writable float64 array of shape (size,) or (B, size)."""
    if x is None:
        raise ValueError(f"{name} is None; expected an array of shape ({size},) or "
                         f"(B, {size}) for {model.name!r} ({_order(model, name)})")
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be an array of real numbers: {exc}") from None
    if a.dtype.kind == "c":
        raise ValueError(f"{name} has complex values; expected real numbers")
    if a.dtype.kind not in _NUMERIC:
        try:
            a = a.astype(np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be an array of real numbers, got an array of "
                             f"dtype {a.dtype}") from None
    if a.ndim not in (1, 2) or a.shape[-1] != size:
        raise ValueError(f"{name} must have shape ({size},) or (B, {size}) for "
                         f"{model.name!r}, got {a.shape}; {_order(model, name)}")
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a if a.flags.writeable else a.copy()  # one compiled signature: writable arrays


def _order(model, name: str) -> str:
    """The order of the entries of state ``name`` (``q``: configurations, else velocities),
    for an error's message: written only for one (the joints' names, a loop over them)."""
    return ("q: " if name == "q" else f"{name}: ") + layout(model, name != "q")


def states(model, arrays: tuple, inputs: tuple) -> tuple[np.ndarray, ...]:
    """The state arrays of one algorithm (``inputs``: its table entries ``(name, size)``),
    converted, each one sample or all one batch of the same size."""
    sizes = {"nq": model.nq, "nv": model.nv}
    out = tuple(state(model, a, name, sizes[size])
                for a, (name, size) in zip(arrays, inputs, strict=True))
    if any(a.shape[:-1] != out[0].shape[:-1] for a in out):
        detail = ", ".join(f"{name} {a.shape}" for (name, _), a in zip(inputs, out, strict=True))
        raise ValueError(f"inputs must be one sample each or batches of the same size: {detail}")
    return out


def packed(model, gravity) -> np.ndarray:
    """The model's packed buffer with the base acceleration ``V̇_0 = -g`` of ``gravity``
    (Featherstone's trick): the model's own for the default gravity, else a copy."""
    if gravity is DEFAULT_GRAVITY:
        return model.packed
    return with_gravity(model.packed, gravity_vector(gravity))


def gravity_vector(gravity) -> tuple[float, float, float]:
    try:
        g = np.asarray(gravity, dtype=float)
    except (TypeError, ValueError):
        g = None
    if g is None or g.shape != (3,) or not np.all(np.isfinite(g)):
        raise ValueError(f"gravity must be 3 finite numbers (world frame), got {gravity!r}")
    return (float(g[0]), float(g[1]), float(g[2]))


def external(model, f_ext, batch: tuple[int, ...]) -> np.ndarray | None:
    """External wrenches as CGA wrench coefficients, (n, 6) or (B, n, 6), or None.

    ``f_ext`` follows Pinocchio: one force per joint, ``[f, τ]`` (linear, angular), applied
    to the joint's body and expressed in that joint's frame.
    """
    if f_ext is None:
        return None
    n = model.njoints
    shapes = [(n, 6)] + ([batch + (n, 6)] if batch else [])
    try:
        f = np.asarray(f_ext)
    except (TypeError, ValueError):
        f = np.empty(0)
    if f.dtype.kind not in _NUMERIC or f.shape not in shapes:
        expected = " or ".join(str(s) for s in shapes)
        raise ValueError(
            f"f_ext must have shape {expected} (one [f, τ] per joint, in the joint's frame, "
            f"joints {', '.join(model.joint_names)}), got {f.shape} of dtype {f.dtype}")
    f = f.astype(np.float64)
    bad = np.argwhere(~np.isfinite(f))
    if bad.size:
        raise ValueError(f"f_ext contains NaN or inf at index {tuple(int(i) for i in bad[0])}")
    w = wrench_from_force(f)
    if batch and w.ndim == 2:
        w = np.broadcast_to(w, batch + (n, 6))
    return np.ascontiguousarray(w)


def link_index(model, link) -> int:
    """The index of a link given by name or by index (an integer, not a float)."""
    if isinstance(link, str):
        return model.link_index(link)
    if isinstance(link, numbers.Integral) and not isinstance(link, bool):
        if 0 <= link < model.nlinks:
            return int(link)
        raise ValueError(f"link index {link} out of range 0..{model.nlinks - 1} for "
                         f"{model.name!r}")
    raise ValueError(f"link must be a link name or an integer index, got {link!r}; links: "
                     f"{', '.join(model.link_names)}")
