"""Plane-based GA G(d,0,1), d = 1..4, as fast products on coefficient arrays.

One ``PGA`` object per dimension d holds the product tables of ``Algebra.pga(d)`` (the
reference algebra) as dense ``(n*n, n)`` matrices, so that every product is one numpy matmul
on coefficient arrays ``x[..., n]`` with n = 2^(d+1) (batch axes first, as in
``cgadyn.algebra.Multivector``). Every function of the dynamics takes such arrays and a
``PGA``, and runs the same code for every d (Dorst & De Keninck, "May the Forque be with
You", section 2.5.3: "a true dimension agnostic implementation").

Geometry (sections 1.1, 1.2, 2.5.5): hyperplanes are vectors ``n . x = delta`` ->
``n_i e_i - delta e0``; a point at x is the complement ``*(e0 + x_i e_i)``, a d-vector; its
ideal part ``x I`` is the vanishing point (direction) of x. ``*`` is the right complement
(``Multivector.dual``), which is defined for the degenerate metric.

Orientation conventions are not assumed but measured on the algebra when the model is built:
``translation_rate(v)`` is the bivector B for which ``exp(-B t/2)`` moves every point by
``v t`` and ``rotation_rate`` the one that turns e_i towards e_j (eq. 2.1 and section 2.1.4).
"""

from __future__ import annotations

from functools import cache, cached_property
from itertools import combinations

import numpy as np

from cgadyn.algebra import Algebra, Multivector

__all__ = ["PGA", "pga"]


def check_dimension(d: int) -> int:
    """The PGA dimension as an int; ``ValueError`` unless it is one of 1, 2, 3, 4."""
    if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or not 1 <= int(d) <= 4:
        raise ValueError(f"dimension must be an integer in 1..4 (G(d,0,1)), got {d!r}")
    return int(d)


@cache
def pga(d: int) -> PGA:
    """The (cached) model of d-dimensional Euclidean space, G(d,0,1)."""
    return PGA(check_dimension(d))


class PGA:
    """G(d,0,1) with its products as matrices, and the PGA geometry of points and motions."""

    def __init__(self, d: int):
        self.d = check_dimension(d)
        self.algebra = Algebra.pga(self.d)
        alg = self.algebra
        self.n = alg.size
        n = self.n
        gp = alg.dense(alg.gp_table)
        self._gp = gp.reshape(n * n, n)
        self._op = alg.dense(alg.op_table).reshape(n * n, n)
        self._lc = alg.dense(alg.lc_table).reshape(n * n, n)
        self._cm = (0.5 * (gp - gp.transpose(1, 0, 2))).reshape(n * n, n)
        eye = np.eye(n)
        basis = Multivector(alg, eye)
        vee = np.stack([basis.regressive(Multivector(alg, eye[j])).coeffs for j in range(n)], 1)
        self._vee = vee.reshape(n * n, n)
        self._reverse = alg.reverse_signs
        comp_sign, comp_index = alg.complement
        self._comp_sign, self._comp_index = comp_sign, comp_index
        self.grades = alg.grades
        # Blade index sets used everywhere.
        self.bivectors = alg.blades_of_grade(2)
        self.dual_bivectors = alg.blades_of_grade(d - 1)
        self.even = np.flatnonzero(alg.grades % 2 == 0)
        self.euclidean_planes = list(combinations(range(1, d + 1), 2))
        self.e0 = alg.blade("e0")
        self.ei = np.array([alg.blade(f"e{i}") for i in range(1, d + 1)])
        self.e0i = np.array([alg.blade(f"e0{i}") for i in range(1, d + 1)])
        self.eij = np.array([alg.blade(f"e{i}{j}") for i, j in self.euclidean_planes], dtype=int)
        self.pseudoscalar = n - 1

    def __repr__(self) -> str:
        return f"PGA(d={self.d}, {self.algebra})"

    # --- products on coefficient arrays ------------------------------------------------

    def _product(self, table: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        a = np.asarray(a, dtype=float)
        b = np.asarray(b, dtype=float)
        outer = a[..., :, None] * b[..., None, :]
        return outer.reshape(outer.shape[:-2] + (self.n * self.n,)) @ table

    def gp(self, a, b) -> np.ndarray:
        """Geometric product ab."""
        return self._product(self._gp, a, b)

    def op(self, a, b) -> np.ndarray:
        """Outer product a ^ b (meet)."""
        return self._product(self._op, a, b)

    def lc(self, a, b) -> np.ndarray:
        """Left contraction a ⌋ b (the paper's inner product '·' on these grades)."""
        return self._product(self._lc, a, b)

    def vee(self, a, b) -> np.ndarray:
        """Regressive product (join) a ∨ b, through the complement duality."""
        return self._product(self._vee, a, b)

    def commutator(self, a, b) -> np.ndarray:
        """Commutator product a × b = ½(ab − ba), eq. (2.5)."""
        return self._product(self._cm, a, b)

    def reverse(self, a) -> np.ndarray:
        return np.asarray(a, dtype=float) * self._reverse

    def dual(self, a) -> np.ndarray:
        """Right complement ``*a`` (Multivector.dual)."""
        a = np.asarray(a, dtype=float)
        out = np.zeros_like(a)
        out[..., self._comp_index] = a * self._comp_sign
        return out

    def undual(self, a) -> np.ndarray:
        """Inverse of ``dual``."""
        a = np.asarray(a, dtype=float)
        return a[..., self._comp_index] * self._comp_sign

    def grade(self, a, k: int) -> np.ndarray:
        return np.where(self.grades == k, np.asarray(a, dtype=float), 0.0)

    def sandwich(self, m, x) -> np.ndarray:
        """M X M~: moves an element X by the motor M (section 2.5.4)."""
        return self.gp(self.gp(m, x), self.reverse(m))

    def scalar(self, s=1.0) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        out = np.zeros(s.shape + (self.n,))
        out[..., 0] = s
        return out

    def zeros(self, batch: tuple[int, ...] = ()) -> np.ndarray:
        return np.zeros(tuple(batch) + (self.n,))

    def blade(self, name: str, value: float = 1.0) -> np.ndarray:
        out = self.zeros()
        out[self.algebra.blade(name)] = value
        return out

    def mv(self, a) -> Multivector:
        """The reference ``Multivector`` with these coefficients (for display, checks)."""
        return Multivector(self.algebra, np.asarray(a, dtype=float))

    def exp(self, a, terms: int = 20) -> np.ndarray:
        """exp(A) by scaling and squaring of the Taylor series (any element; eq. 1.5 area).

        Used for motors ``exp(-B t / 2)`` of any bivector, also the non-simple bivectors of
        4D, where the closed forms of section 2.5.4 for 2-blades do not apply.
        """
        a = np.asarray(a, dtype=float)
        scale = float(np.max(np.abs(a))) if a.size else 0.0
        k = max(0, int(np.ceil(np.log2(scale))) + 2) if scale > 0 else 0
        x = a * 0.5**k
        term = self.scalar(np.ones(a.shape[:-1]))
        total = term
        for i in range(1, terms):
            term = self.gp(term, x) / i
            total = total + term
        for _ in range(k):
            total = self.gp(total, total)
        return total

    # --- geometry --------------------------------------------------------------------

    def _check_coords(self, x, what: str) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape[-1:] != (self.d,):
            raise ValueError(f"{what} must have last axis {self.d} (d={self.d}), got {x.shape}")
        if not np.all(np.isfinite(x)):
            raise ValueError(f"{what} must be finite, got {x}")
        return x

    def hyperplane(self, normal, offset: float = 0.0) -> np.ndarray:
        """The hyperplane ``normal . x = offset`` as the vector ``n_i e_i - offset e0`` (1.1)."""
        normal = self._check_coords(normal, "normal")
        out = np.zeros(normal.shape[:-1] + (self.n,))
        out[..., self.ei] = normal
        out[..., self.e0] = -np.asarray(offset, dtype=float)
        return out

    def point(self, x) -> np.ndarray:
        """The point at x: ``*(e0 + x_i e_i)`` (section 2.5.5), a d-vector."""
        x = self._check_coords(x, "point coordinates")
        v = np.zeros(x.shape[:-1] + (self.n,))
        v[..., self.e0] = 1.0
        v[..., self.ei] = x
        return self.dual(v)

    def direction(self, x) -> np.ndarray:
        """The vanishing (ideal) point ``x I`` of direction x: point(x) - point(0) (2.3.1)."""
        x = self._check_coords(x, "direction")
        v = np.zeros(x.shape[:-1] + (self.n,))
        v[..., self.ei] = x
        return self.dual(v)

    def coords(self, p) -> np.ndarray:
        """Euclidean coordinates of a (finite) point, the inverse of ``point``."""
        v = self.undual(p)
        return v[..., self.ei] / v[..., self.e0, None]

    @cached_property
    def origin(self) -> np.ndarray:
        return self.point(np.zeros(self.d))

    @cached_property
    def _translation_sign(self) -> float:
        # exp(-B/2) with B = s e01: does it move the origin to +x?  Measured, not assumed.
        m = self.exp(-0.5 * self.blade("e01"))
        return float(np.sign(self.coords(self.sandwich(m, self.origin))[0]))

    @cached_property
    def _rotation_signs(self) -> np.ndarray:
        signs = []
        for k, (i, j) in enumerate(self.euclidean_planes):
            b = self.zeros()
            b[self.eij[k]] = 0.1
            x = np.zeros(self.d)
            x[i - 1] = 1.0
            moved = self.coords(self.sandwich(self.exp(-0.5 * b), self.point(x)))
            signs.append(np.sign(moved[j - 1]))
        return np.array(signs, dtype=float)

    def translation_rate(self, v) -> np.ndarray:
        """The ideal bivector ``eps v`` whose motor ``exp(-B t/2)`` translates by ``v t``."""
        v = self._check_coords(v, "velocity")
        out = np.zeros(v.shape[:-1] + (self.n,))
        out[..., self.e0i] = self._translation_sign * v
        return out

    def rotation_rate(self, omega) -> np.ndarray:
        """The Euclidean bivector of angular rates ``omega[k]`` in the planes (i, j) of
        ``euclidean_planes`` (e_i turning towards e_j), about the origin."""
        omega = np.asarray(omega, dtype=float)
        if omega.shape[-1:] != (len(self.eij),):
            raise ValueError(
                f"angular rates must have last axis {len(self.eij)} (planes "
                f"{self.euclidean_planes}), got {omega.shape}"
            )
        out = np.zeros(omega.shape[:-1] + (self.n,))
        out[..., self.eij] = self._rotation_signs * omega
        return out

    def split_rate(self, b) -> tuple[np.ndarray, np.ndarray]:
        """Inverse of ``translation_rate + rotation_rate``: (v, omega) of a bivector, split at
        the origin (B = **B** + eps v, eq. 2.17)."""
        b = np.asarray(b, dtype=float)
        return b[..., self.e0i] * self._translation_sign, b[..., self.eij] * self._rotation_signs

    def motor(self, rotation=None, translation=None) -> np.ndarray:
        """Rotate (plane angles, as ``rotation_rate``) about the origin, then translate."""
        m = self.scalar()
        if rotation is not None:
            m = self.exp(-0.5 * self.rotation_rate(rotation))
        if translation is not None:
            m = self.gp(self.exp(-0.5 * self.translation_rate(translation)), m)
        return m
