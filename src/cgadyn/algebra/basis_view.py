"""Coefficients of multivectors in another basis of vectors, such as CGA's null basis.

The reference ``Multivector`` stores coefficients on the orthonormal blades. The CGA paper
writes everything in the null basis e0, e1, e2, e3, e∞ (e0·e∞ = -1). A ``BasisView`` gives
the outer products of any chosen basis vectors as blades (ordered like ``Algebra``'s: by
grade, then lexicographically in the order the vectors are given) and converts
coefficient arrays both ways with one matrix each.
"""

from __future__ import annotations

from functools import reduce

import numpy as np

from .algebra import all_blades
from .multivector import Multivector, format_terms


class BasisView:
    """Blades of ``vectors`` (Multivectors of grade 1) named after ``names``."""

    def __init__(self, vectors: list[Multivector], names: list[str]):
        if len(vectors) != len(names):
            raise ValueError("one name per basis vector")
        alg = vectors[0].algebra
        if len(vectors) != alg.dim:
            raise ValueError(f"{alg} needs {alg.dim} basis vectors, got {len(vectors)}")
        self.algebra = alg
        self.names = tuple(names)
        one = Multivector.scalar(alg, 1.0)
        cols, blade_names = [], []
        for subset in all_blades(alg.dim):
            blade = reduce(lambda a, b: a.op(b), (vectors[i] for i in subset), one)
            cols.append(blade.coeffs)
            blade_names.append("e" + "".join(self.names[i] for i in subset) if subset else "1")
        # to_ortho @ view_coeffs = orthonormal coeffs
        self.to_ortho = np.array(cols).T
        self.from_ortho = np.linalg.inv(self.to_ortho)
        self.blade_names = tuple(blade_names)

    def index(self, name: str) -> int:
        try:
            return self.blade_names.index(name)
        except ValueError:
            raise ValueError(
                f"unknown blade {name!r}; blades are {', '.join(self.blade_names)}"
            ) from None

    def coeffs(self, mv: Multivector, names: list[str] | None = None) -> np.ndarray:
        """Coefficients of ``mv`` on this view's blades (or on the named ones)."""
        c = _matvec(self.from_ortho, mv.coeffs)
        if names is None:
            return c
        return c[..., [self.index(n) for n in names]]

    def multivector(self, values, names: list[str] | None = None) -> Multivector:
        """The multivector with coefficients ``values`` on this view's (or the named) blades."""
        values = np.asarray(values)
        if names is not None:
            full = np.zeros(values.shape[:-1] + (len(self.blade_names),), dtype=values.dtype)
            for i, n in enumerate(names):
                full[..., self.index(n)] = values[..., i]
            values = full
        return Multivector(self.algebra, _matvec(self.to_ortho, values))

    def repr(self, mv: Multivector) -> str:
        return format_terms(self.coeffs(mv), self.blade_names)


def _matvec(m: np.ndarray, v: np.ndarray) -> np.ndarray:
    if v.dtype == object:
        out = np.zeros(v.shape, dtype=object)
        for k in range(m.shape[0]):
            for j in np.flatnonzero(m[k]):
                out[..., k] = out[..., k] + _exact(m[k, j]) * v[..., j]
        return out
    return v @ m.T


def _exact(x: float):
    """Small dyadic floats as exact sympy rationals when generating symbolic code."""
    from fractions import Fraction

    f = Fraction(float(x)).limit_denominator(64)
    if abs(float(f) - x) > 1e-15:
        return x
    try:
        import sympy

        return sympy.Rational(f.numerator, f.denominator)
    except ImportError:  # pragma: no cover - sympy only needed by the generator
        return float(f)
