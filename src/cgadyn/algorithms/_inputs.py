"""Input checks shared by the algorithm wrappers: shapes, dtypes, finiteness, gravity.

The checks on the hot path are cheap (a contiguous float64 view and a shape test); the
finiteness of the inputs is checked inside the compiled code, which raises a bare
``FloatingPointError`` that ``explain`` turns into a message naming the array and joint.
"""

from __future__ import annotations

import numpy as np

from ..cga.conventions import wrench_from_force
from ..multibody.packed import DEFAULT_GRAVITY, with_gravity


def state(model, x, name: str) -> np.ndarray:
    """``x`` as a contiguous writable float64 array of shape (n,) or (B, n) (the types
    the compiled code is specialised for)."""
    try:
        a = np.ascontiguousarray(x, dtype=np.float64)
        if not a.flags.writeable:
            a = a.copy()
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be an array of floats: {exc}") from None
    if a.shape[-1:] != (model.nv,) or a.ndim > 2:
        raise ValueError(
            f"{name} must have shape ({model.nv},) or (B, {model.nv}) for {model.name!r}, "
            f"got {a.shape}; joint order: {', '.join(model.joint_names)}"
        )
    return a


def states(model, arrays: tuple, names: tuple[str, ...]) -> tuple[np.ndarray, ...]:
    """State arrays of one shape (n,) or (B, n), as contiguous writable float64."""
    out = [state(model, a, name) for a, name in zip(arrays, names, strict=True)]
    same_batch(*out, names=names)
    return tuple(out)


def same_batch(*arrays: np.ndarray, names: tuple[str, ...]) -> None:
    first = arrays[0].shape
    if not all(a.shape == first for a in arrays):
        detail = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays, strict=True))
        raise ValueError(f"inputs must share one shape: {detail}")


def packed(model, gravity) -> np.ndarray:
    """The model's packed buffer with the base acceleration ``V̇_0 = -g`` of ``gravity``
    (Featherstone's trick): the model's own for the default gravity, else a copy."""
    if gravity is DEFAULT_GRAVITY:
        return model.packed
    return with_gravity(model.packed, gravity_vector(gravity))


def gravity_vector(gravity) -> tuple[float, float, float]:
    g = np.asarray(gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise ValueError(f"gravity must be 3 finite numbers (world frame), got {gravity!r}")
    return (float(g[0]), float(g[1]), float(g[2]))


def external(model, f_ext, batch: tuple[int, ...]) -> np.ndarray | None:
    """External wrenches as CGA wrench coefficients (..., n, 6), or None when absent.

    ``f_ext`` follows Pinocchio: one force per joint, ``[f, τ]`` (linear, angular), applied
    to the joint's body and expressed in that joint's frame.
    """
    n = model.nv
    if f_ext is None:
        return None
    f = np.asarray(f_ext, dtype=float)
    if f.shape not in ((n, 6), batch + (n, 6)):
        raise ValueError(
            f"f_ext must have shape ({n}, 6) or {batch + (n, 6)} (one [f, τ] per joint, "
            f"in the joint's frame), got {f.shape}"
        )
    if not np.all(np.isfinite(f)):
        raise ValueError("f_ext contains NaN or inf")
    w = np.ascontiguousarray(wrench_from_force(f))
    if batch and w.ndim == 2:
        w = np.ascontiguousarray(np.broadcast_to(w, batch + (n, 6)))
    return w


def explain(model, **arrays) -> ValueError:
    """A message naming the first non-finite input and its joint."""
    for name, a in arrays.items():
        if a is None:
            continue
        bad = np.argwhere(~np.isfinite(a))
        if bad.size:
            idx = tuple(int(i) for i in bad[0])
            joint = model.joint_names[idx[-1]] if a.shape[-1] == model.nv else "?"
            return ValueError(f"{name} contains NaN or inf at index {idx} (joint {joint!r})")
    return ValueError("the computation produced NaN or inf from finite inputs")
