"""The Python side of the distances: poses and shapes checked, the compiled kernels called,
their statuses worded."""

from __future__ import annotations

import numpy as np

from . import distance as D
from .shapes import KIND_NAMES, Shape

__all__ = ["check_rigid", "pose_matrix", "shape_distance"]


def pose_matrix(pose, what: str = "pose") -> np.ndarray:
    """A rigid 4x4 matrix from a ``cga.Motor``, its 8 coefficients, a 4x4 matrix or
    ``None`` (the identity)."""
    if pose is None:
        return np.eye(4)
    values = getattr(pose, "values", pose)
    T = np.asarray(values, dtype=float)
    if T.shape == (8,):
        from ..cga.conventions import matrix_from_motor

        T = matrix_from_motor(T)
    if T.shape != (4, 4):
        raise ValueError(f"{what}: expected a Motor, 8 motor coefficients or a 4x4 matrix, "
                         f"got shape {T.shape}")
    check_rigid(T, what)
    return np.ascontiguousarray(T)


def check_rigid(T: np.ndarray, what: str) -> None:
    """``ValueError`` unless every 4x4 matrix of ``T`` (..., 4, 4) is finite and rigid: an
    orthonormal rotation of determinant +1 (to 1e-9), a translation, ``[0, 0, 0, 1]``."""
    if not np.all(np.isfinite(T)):
        raise ValueError(f"{what} contains NaN or inf")
    R = T[..., :3, :3]
    off = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(axis=(-1, -2))
    bad = (off > 1e-9) | (np.linalg.det(R) < 0) | np.any(T[..., 3, :] != [0, 0, 0, 1], -1)
    if np.any(bad):
        where = f"{what}[{int(np.flatnonzero(bad)[0])}]" if np.ndim(bad) else what
        raise ValueError(f"{where} is not a rigid transform (rotation and translation)")


def _shape(shape, what: str) -> Shape:
    if not isinstance(shape, Shape):
        raise TypeError(f"{what} must be a cgadyn shape (Sphere, Capsule, Box, Cylinder, "
                        f"Plane, ConvexMesh), got {type(shape).__name__}")
    return shape


def explain(status: int, a: Shape, b: Shape) -> str:
    names = f"a {KIND_NAMES[a.kind]} and a {KIND_NAMES[b.kind]}"
    if status == D.PENETRATION_UNSUPPORTED:
        return (f"{names} overlap: their penetration depth is not computed here (EPA could "
                f"not grow its polytope, or, on a cylinder's or an ellipsoid's curved "
                f"surface, its depth and the refined one do not meet within "
                f"{D.DEPTH_GAP:g} m or {D.DEPTH_SLACK:.0%} of the depth; a few overlaps in a "
                f"hundred; a cylinder against a plane or a sphere has it in closed form)")
    if status == D.TWO_PLANES:
        return "the distance of two planes is not defined (both are unbounded half-spaces)"
    return f"unknown shape kind in {names}"


def shape_distance(shape_a: Shape, pose_a, shape_b: Shape, pose_b):
    """The signed distance of two shapes at their world poses (a ``Motor``, its 8
    coefficients or a 4x4 matrix; ``None``: the identity).

    Returns ``(distance, point_a, point_b, normal)``: ``point_a`` on ``a``, ``point_b`` on
    ``b``, ``normal`` the unit vector from ``a`` to ``b`` with ``point_b - point_a =
    distance * normal``; a negative distance is a penetration (coal's convention;
    docs/contact.md, K0-K9). Raises ``ValueError`` for two planes, and for a cylinder
    overlapping a shape other than a plane or a sphere (no penetration depth for those
    yet).
    """
    a, b = _shape(shape_a, "shape_a"), _shape(shape_b, "shape_b")
    Ta = pose_matrix(pose_a, "pose_a") @ a.placement  # a placed shape's own frame
    Tb = pose_matrix(pose_b, "pose_b") @ b.placement
    out, work = np.empty(D.OUT), np.empty(D.WORK)
    status = D.pair_distance(a.kind, a.packed_size, a.packed_vertices, Ta, b.kind,
                             b.packed_size, b.packed_vertices, Tb, work, out)
    if status != D.OK:
        raise ValueError(explain(status, a, b))
    return float(out[0]), out[1:4].copy(), out[4:7].copy(), out[7:10].copy()
