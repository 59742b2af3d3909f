"""The Euclidean parameters of the CGA primitives, read off their blades.

In the null basis (``e0·e∞ = -1``, ``X = e0 + x + ½x² e∞``) and with ``I = e0123∞``:

- a line ``A ∧ B ∧ e∞ = e0 ∧ (b - a) ∧ e∞ + (a ∧ b) ∧ e∞``: its ``e0i∞`` coefficients are the
  direction u, its ``eij∞`` ones the moment ``m = a × b``; the point nearest the origin is
  ``u × m / |u|²``;
- a plane ``P`` (grade 4): ``P I⁻¹ = α (n + d e∞)``, the plane ``n·x = d``;
- a sphere ``S`` (grade 4): ``S I⁻¹ = α (C - ½ ρ² e∞)``, C the conformal centre;
- a circle ``K`` (grade 3): its plane is ``K ∧ e∞``, its centre ``K e∞ K`` (a multiple of the
  conformal centre) and its radius ``ρ² = -K² / (K ∧ e∞)²``.
"""

from __future__ import annotations

import numpy as np

from ..cga.basis import NULL, einf
from ..cga.objects import Circle, Geometric, Line, Plane, Point, Sphere, _pseudoscalar

_VECTOR = ["e0", "e1", "e2", "e3", "e∞"]


def _single(obj: Geometric, kind: str) -> None:
    if not isinstance(obj, Geometric) or obj.mv.batch_shape:
        raise ValueError(f"expected one {kind}, got {obj!r}")


def _undual(mv) -> np.ndarray:
    """The vector ``X I⁻¹`` on e0, e1, e2, e3, e∞."""
    return np.asarray(NULL.coeffs(mv * _pseudoscalar().inverse(), _VECTOR), dtype=float)


def point_coordinates(point: Point) -> np.ndarray:
    """x of a point."""
    _single(point, "Point")
    return np.asarray(point.down(), dtype=float)


def line_parameters(line: Line) -> tuple[np.ndarray, np.ndarray]:
    """``(a, u)``: the point of the line nearest the origin and its unit direction."""
    _single(line, "Line")
    u = np.asarray(NULL.coeffs(line.mv, ["e01∞", "e02∞", "e03∞"]), dtype=float)
    b = np.asarray(NULL.coeffs(line.mv, ["e12∞", "e13∞", "e23∞"]), dtype=float)
    m = np.array([b[2], -b[1], b[0]])  # a ∧ b as the vector a × b
    nu = float(np.linalg.norm(u))
    if not nu > 0.0:
        raise ValueError("the line has no direction (it is not a line A ∧ B ∧ e∞)")
    return np.cross(u, m) / nu**2, u / nu


def plane_parameters(plane: Plane) -> tuple[np.ndarray, float]:
    """``(n, d)``: the unit normal and the offset of the plane ``n·x = d``."""
    _single(plane, "Plane")
    x = _undual(plane.mv)
    n = float(np.linalg.norm(x[1:4]))
    if not n > 0.0 or abs(x[0]) > 1e-9 * max(n, 1.0):
        raise ValueError("the object is not a plane (its dual has an e0 part or no normal)")
    return x[1:4] / n, float(x[4] / n)


def sphere_parameters(sphere: Sphere) -> tuple[np.ndarray, float]:
    """``(c, ρ)``: centre and radius."""
    _single(sphere, "Sphere")
    x = _undual(sphere.mv)
    if not abs(x[0]) > 0.0:
        raise ValueError("the object is not a sphere (its dual has no e0 part: a plane?)")
    c = x[1:4] / x[0]
    r2 = float(c @ c - 2.0 * x[4] / x[0])
    if not r2 > 0.0:
        raise ValueError(f"the sphere is imaginary (ρ² = {r2:g})")
    return c, float(np.sqrt(r2))


def circle_parameters(circle: Circle) -> tuple[np.ndarray, np.ndarray, float]:
    """``(c, n, ρ)``: centre, unit normal of its plane and radius."""
    _single(circle, "Circle")
    k = circle.mv
    n, _ = plane_parameters(Plane(k ^ einf))
    centre = np.asarray(NULL.coeffs(k * einf * k, _VECTOR), dtype=float)
    if not abs(centre[0]) > 0.0:
        raise ValueError("the object is not a circle (it has no finite centre)")
    r2 = -float((k * k).scalar_part()) / float(((k ^ einf) * (k ^ einf)).scalar_part())
    if not r2 > 0.0:
        raise ValueError(f"the circle is imaginary (ρ² = {r2:g})")
    return centre[1:4] / centre[0], n, float(np.sqrt(r2))
