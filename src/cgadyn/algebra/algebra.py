"""A geometric algebra of any signature G(p, q, r), with basis blades as bitmaps.

Blade ``k`` of an algebra is a bitmap over the basis vectors: bit ``i`` set means basis
vector ``i`` is a factor, in increasing order. Blades are ordered by grade, then
lexicographically (``1, e1, e2, ..., e12, e13, ...``). The metric is diagonal: each basis
vector squares to +1, -1 or 0, which covers the conformal model G(4,1) (in its orthonormal
basis e1, e2, e3, e+, e-) and the plane-based models G(d,0,1).

The Cayley table of the geometric product (Dorst, Fontijne & Mann, "Geometric Algebra for
Computer Science", section 19.1) is the one source of every product in this package: the
dense reference ``Multivector`` uses it, and ``tools/generate_kernels.py`` expands it
symbolically into the compiled kernels.
"""

from __future__ import annotations

from functools import cached_property
from itertools import combinations

import numpy as np


def _reorder_sign(a: int, b: int) -> int:
    """Sign of the permutation that sorts the basis vectors of blade ``a`` times ``b``."""
    a >>= 1
    swaps = 0
    while a:
        swaps += bin(a & b).count("1")
        a >>= 1
    return -1 if swaps & 1 else 1


class Algebra:
    """G(p, q, r) given by the squares of its basis vectors.

    Parameters
    ----------
    metric:
        The square (+1, -1 or 0) of each basis vector, in order.
    names:
        A name for each basis vector, used in blade names (``e1``, ``e0`` ...).
    """

    def __init__(self, metric: tuple[int, ...], names: tuple[str, ...] | None = None):
        metric = tuple(int(m) for m in metric)
        if not metric or any(m not in (-1, 0, 1) for m in metric):
            raise ValueError(f"metric must be a non-empty tuple of +1, -1, 0; got {metric}")
        if names is None:
            names = tuple(str(i + 1) for i in range(len(metric)))
        if len(names) != len(metric):
            raise ValueError(f"{len(names)} names for {len(metric)} basis vectors")
        self.metric = metric
        self.names = tuple(names)
        self.dim = len(metric)
        self.size = 1 << self.dim
        order = sorted(range(self.size), key=lambda b: (bin(b).count("1"), _bits(b)))
        self.bitmaps = np.array(order, dtype=np.int64)
        self.index_of = {int(b): i for i, b in enumerate(order)}
        self.grades = np.array([bin(b).count("1") for b in order], dtype=np.int64)
        #: an optional BasisView in which multivectors print (set for CGA's null basis)
        self.display = None

    @classmethod
    def signature(cls, p: int, q: int = 0, r: int = 0, first: int = 1) -> Algebra:
        """G(p, q, r): p vectors squaring to +1, then q to -1, then r to 0.

        ``first`` is the index of the first basis vector's name. PGA G(d,0,1) is usually
        written with the null vector first and named e0: use ``Algebra.pga(d)``.
        """
        metric = (1,) * p + (-1,) * q + (0,) * r
        return cls(metric, tuple(str(first + i) for i in range(len(metric))))

    @classmethod
    def pga(cls, d: int) -> Algebra:
        """Plane-based G(d,0,1): e0 squares to 0, e1..ed to +1."""
        if not 1 <= d <= 4:
            raise ValueError(f"PGA dimension must be in 1..4, got {d}")
        return cls((0,) + (1,) * d, tuple(str(i) for i in range(d + 1)))

    @classmethod
    def cga(cls) -> Algebra:
        """Conformal G(4,1) in its orthonormal basis e1, e2, e3, e+ (squares 1), e- (-1)."""
        return cls((1, 1, 1, 1, -1), ("1", "2", "3", "+", "-"))

    def __repr__(self) -> str:
        p = self.metric.count(1)
        q = self.metric.count(-1)
        r = self.metric.count(0)
        return f"Algebra(G({p},{q},{r}), basis {', '.join('e' + n for n in self.names)})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Algebra) and (self.metric, self.names) == (
            other.metric,
            other.names,
        )

    def __hash__(self) -> int:
        return hash((self.metric, self.names))

    def blade_name(self, k: int) -> str:
        """Name of blade ``k``: ``1``, ``e1``, ``e12`` ... (multi-letter names joined)."""
        b = int(self.bitmaps[k])
        if b == 0:
            return "1"
        return "e" + "".join(self.names[i] for i in _bits(b))

    @cached_property
    def blade_names(self) -> tuple[str, ...]:
        return tuple(self.blade_name(k) for k in range(self.size))

    def blade(self, name: str) -> int:
        """Index of a blade from its name (``'e12'``); the factors must be in basis order."""
        if name in ("1", ""):
            return 0
        try:
            return self.blade_names.index(name)
        except ValueError:
            raise ValueError(
                f"unknown blade {name!r}; blades are {', '.join(self.blade_names)}"
            ) from None

    def blades_of_grade(self, g: int) -> np.ndarray:
        return np.flatnonzero(self.grades == g)

    # --- Cayley tables -----------------------------------------------------------------

    def _product_table(self, keep) -> tuple[np.ndarray, np.ndarray]:
        n = self.size
        sign = np.zeros((n, n), dtype=np.int64)
        index = np.zeros((n, n), dtype=np.int64)
        for i, a in enumerate(self.bitmaps):
            for j, b in enumerate(self.bitmaps):
                a_, b_ = int(a), int(b)
                s = _reorder_sign(a_, b_)
                for bit in _bits(a_ & b_):
                    s *= self.metric[bit]
                res = a_ ^ b_
                index[i, j] = self.index_of[res]
                if s and keep(a_, b_, res):
                    sign[i, j] = s
        return sign, index

    @cached_property
    def gp_table(self) -> tuple[np.ndarray, np.ndarray]:
        """(sign, index): e_i e_j = sign[i, j] * e_index[i, j]."""
        return self._product_table(lambda a, b, r: True)

    @cached_property
    def op_table(self) -> tuple[np.ndarray, np.ndarray]:
        """Outer product: the geometric product of blades sharing no basis vector."""
        return self._product_table(lambda a, b, r: (a & b) == 0)

    @cached_property
    def lc_table(self) -> tuple[np.ndarray, np.ndarray]:
        """Left contraction A ⌋ B: grade(B) - grade(A) part, zero when negative."""
        return self._product_table(lambda a, b, r: (a & b) == a)

    @cached_property
    def rc_table(self) -> tuple[np.ndarray, np.ndarray]:
        """Right contraction A ⌊ B: grade(A) - grade(B) part."""
        return self._product_table(lambda a, b, r: (a & b) == b)

    @cached_property
    def scalar_table(self) -> tuple[np.ndarray, np.ndarray]:
        """Scalar product ⟨A B⟩₀."""
        return self._product_table(lambda a, b, r: r == 0)

    def dense(self, table: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """The table as a dense (n, n, n) tensor C with (AB)_k = A_i B_j C[i, j, k]."""
        sign, index = table
        n = self.size
        c = np.zeros((n, n, n))
        i, j = np.nonzero(sign)
        c[i, j, index[i, j]] = sign[i, j]
        return c

    @cached_property
    def reverse_signs(self) -> np.ndarray:
        g = self.grades
        return np.where((g * (g - 1) // 2) % 2 == 1, -1.0, 1.0)

    @cached_property
    def involution_signs(self) -> np.ndarray:
        return np.where(self.grades % 2 == 1, -1.0, 1.0)

    @cached_property
    def complement(self) -> tuple[np.ndarray, np.ndarray]:
        """Right complement: e_k ∧ comp(e_k) = e_{12..n} (metric-free, so fine for PGA).

        Returns (sign, index) with comp(e_k) = sign[k] * e_index[k].
        """
        n = self.size
        full = n - 1
        sign = np.zeros(n)
        index = np.zeros(n, dtype=np.int64)
        for k, b in enumerate(self.bitmaps):
            c = full ^ int(b)
            index[k] = self.index_of[c]
            sign[k] = _reorder_sign(int(b), c)
        return sign, index


def _bits(b: int) -> list[int]:
    return [i for i in range(b.bit_length()) if b >> i & 1]


def all_blades(dim: int) -> list[tuple[int, ...]]:
    """Every subset of ``range(dim)``, by grade then lexicographically."""
    return [c for g in range(dim + 1) for c in combinations(range(dim), g)]
