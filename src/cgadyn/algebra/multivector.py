"""The dense reference multivector: slow, general, and the oracle for every kernel.

Coefficients are a numpy array whose last axis runs over the algebra's 2^n blades; any
leading axes are batch axes. Coefficients may be floats or Python objects (sympy symbols):
``tools/generate_kernels.py`` runs these very products on symbols to write the kernels.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from .algebra import Algebra

Scalar = int | float | np.floating


def _product(alg: Algebra, table, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    sign, index = table
    if a.dtype == object or b.dtype == object:
        shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
        out = np.zeros(shape + (alg.size,), dtype=object)
        ii, jj = np.nonzero(sign)
        for i, j in zip(ii, jj, strict=True):
            ai, bj = a[..., i], b[..., j]
            if _is_zero(ai) or _is_zero(bj):
                continue
            out[..., index[i, j]] = out[..., index[i, j]] + sign[i, j] * ai * bj
        return out
    c = _dense_cache(alg, table)
    return np.einsum("...i,...j,ijk->...k", a, b, c, optimize=True)


def _is_zero(x) -> bool:
    return isinstance(x, (int, float)) and x == 0 if not isinstance(x, np.ndarray) else False


_DENSE: dict = {}


def _dense_cache(alg: Algebra, table) -> np.ndarray:
    key = (alg, id(table[0]))
    if key not in _DENSE:
        _DENSE[key] = alg.dense(table)
    return _DENSE[key]


class Multivector:
    """An element of an ``Algebra``; ``coeffs[..., k]`` is the coefficient of blade k.

    Operators: ``*`` geometric product, ``^`` outer product, ``|`` left contraction
    (the CGA paper's ``·``: it is only ever applied there to two bivectors, where every
    inner product reduces to the scalar part ⟨AB⟩₀), ``&`` regressive product (join),
    ``~`` reverse. Scalars may stand on either side of ``*``, ``+`` and ``-``.
    """

    __array_priority__ = 1000

    def __init__(self, algebra: Algebra, coeffs):
        coeffs = np.asarray(coeffs)
        if coeffs.dtype != object:
            coeffs = coeffs.astype(float)
        if coeffs.shape[-1:] != (algebra.size,):
            raise ValueError(
                f"coefficients must have last axis {algebra.size} for {algebra}, "
                f"got shape {coeffs.shape}"
            )
        self.algebra = algebra
        self.coeffs = coeffs

    # --- construction --------------------------------------------------------------

    @classmethod
    def zeros(cls, algebra: Algebra, batch: tuple[int, ...] = (), dtype=float) -> Multivector:
        return cls(algebra, np.zeros(tuple(batch) + (algebra.size,), dtype=dtype))

    @classmethod
    def scalar(cls, algebra: Algebra, s) -> Multivector:
        s = np.asarray(s)
        out = np.zeros(s.shape + (algebra.size,), dtype=s.dtype if s.dtype == object else float)
        out[..., 0] = s
        return cls(algebra, out)

    @classmethod
    def blade(cls, algebra: Algebra, name: str, value=1.0) -> Multivector:
        out = cls.zeros(algebra, dtype=object if not isinstance(value, Scalar) else float)
        out.coeffs[algebra.blade(name)] = value
        return out

    @classmethod
    def from_blades(
        cls, algebra: Algebra, names: Iterable[str], values
    ) -> Multivector:
        """A multivector from coefficient arrays ``values[..., i]`` on the named blades."""
        values = np.asarray(values)
        names = list(names)
        if values.shape[-1:] != (len(names),):
            raise ValueError(f"values must have last axis {len(names)}, got {values.shape}")
        dtype = object if values.dtype == object else float
        out = np.zeros(values.shape[:-1] + (algebra.size,), dtype=dtype)
        for i, name in enumerate(names):
            out[..., algebra.blade(name)] = values[..., i]
        return cls(algebra, out)

    def on_blades(self, names: Iterable[str]) -> np.ndarray:
        """Coefficients on the named blades, last axis in the order given."""
        idx = [self.algebra.blade(n) for n in names]
        return self.coeffs[..., idx]

    # --- structure -----------------------------------------------------------------

    @property
    def batch_shape(self) -> tuple[int, ...]:
        return self.coeffs.shape[:-1]

    def __getitem__(self, name: str):
        return self.coeffs[..., self.algebra.blade(name)]

    def grade(self, *grades: int) -> Multivector:
        """Grade projection ⟨A⟩_g (several grades may be given)."""
        mask = np.isin(self.algebra.grades, grades)
        return self._new(np.where(mask, self.coeffs, 0) if self.coeffs.dtype != object
                         else self.coeffs * mask)

    def scalar_part(self):
        return self.coeffs[..., 0]

    def _new(self, coeffs) -> Multivector:
        return Multivector(self.algebra, coeffs)

    def _coerce(self, other) -> Multivector:
        if isinstance(other, Multivector):
            if other.algebra != self.algebra:
                raise ValueError(f"cannot combine {self.algebra} with {other.algebra}")
            return other
        return Multivector.scalar(self.algebra, other)

    # --- unary ---------------------------------------------------------------------

    def reverse(self) -> Multivector:
        return self._new(self.coeffs * self.algebra.reverse_signs)

    __invert__ = reverse

    def involute(self) -> Multivector:
        """Grade involution: odd grades change sign."""
        return self._new(self.coeffs * self.algebra.involution_signs)

    def conjugate(self) -> Multivector:
        """Clifford conjugate: reverse of the grade involution."""
        return self.involute().reverse()

    def __neg__(self) -> Multivector:
        return self._new(-self.coeffs)

    def __pos__(self) -> Multivector:
        return self

    # --- binary --------------------------------------------------------------------

    def gp(self, other) -> Multivector:
        o = self._coerce(other)
        return self._new(_product(self.algebra, self.algebra.gp_table, self.coeffs, o.coeffs))

    def op(self, other) -> Multivector:
        o = self._coerce(other)
        return self._new(_product(self.algebra, self.algebra.op_table, self.coeffs, o.coeffs))

    def lc(self, other) -> Multivector:
        """Left contraction A ⌋ B."""
        o = self._coerce(other)
        return self._new(_product(self.algebra, self.algebra.lc_table, self.coeffs, o.coeffs))

    def rc(self, other) -> Multivector:
        """Right contraction A ⌊ B."""
        o = self._coerce(other)
        return self._new(_product(self.algebra, self.algebra.rc_table, self.coeffs, o.coeffs))

    def scalar_product(self, other):
        """⟨A B⟩₀ as an array (batch shape)."""
        o = self._coerce(other)
        return _product(self.algebra, self.algebra.scalar_table, self.coeffs, o.coeffs)[..., 0]

    def commutator(self, other) -> Multivector:
        """A × B = ½(AB − BA), eq. (11) of the CGA paper."""
        o = self._coerce(other)
        return (self.gp(o) - o.gp(self)) * 0.5

    def __mul__(self, other):
        if isinstance(other, Multivector):
            return self.gp(other)
        return self._new(self.coeffs * other)

    def __rmul__(self, other):
        return self._new(other * self.coeffs)

    def __truediv__(self, other):
        if isinstance(other, Multivector):
            return self.gp(other.inverse())
        return self._new(self.coeffs / other)

    def __xor__(self, other):
        return self.op(other)

    def __or__(self, other):
        return self.lc(other)

    def __and__(self, other):
        return self.regressive(other)

    def __add__(self, other):
        return self._new(self.coeffs + self._coerce(other).coeffs)

    __radd__ = __add__

    def __sub__(self, other):
        return self._new(self.coeffs - self._coerce(other).coeffs)

    def __rsub__(self, other):
        return self._new(self._coerce(other).coeffs - self.coeffs)

    # --- duality -------------------------------------------------------------------

    def dual(self) -> Multivector:
        """Right complement: e_k ∧ dual(e_k) = e_{1..n}.

        A Hodge-style dual that needs no inverse pseudoscalar, so it is defined for the
        degenerate PGA metrics as well (De Keninck & Dorst's complement duality).
        """
        sign, index = self.algebra.complement
        out = np.zeros_like(self.coeffs)
        out[..., index] = self.coeffs * sign
        return self._new(out)

    def undual(self) -> Multivector:
        """Inverse of ``dual``."""
        sign, index = self.algebra.complement
        return self._new(self.coeffs[..., index] * sign)

    def regressive(self, other) -> Multivector:
        """Regressive product (join) A ∨ B = undual(dual(A) ∧ dual(B))."""
        o = self._coerce(other)
        return self.dual().op(o.dual()).undual()

    # --- norms, inverse ------------------------------------------------------------

    def norm_squared(self):
        """⟨A Ã⟩₀ (may be negative in non-Euclidean signatures)."""
        return self.scalar_product(self.reverse())

    def norm(self):
        return np.sqrt(np.abs(self.norm_squared()))

    def inverse(self) -> Multivector:
        """Inverse of a versor: Ã / ⟨A Ã⟩₀. Raises for null elements."""
        n2 = np.asarray(self.norm_squared(), dtype=float)
        if np.any(np.abs(n2) < 1e-300):
            raise ValueError("multivector has zero norm: it is not an invertible versor")
        return self.reverse() * (1.0 / n2)[..., None] if n2.ndim else self.reverse() * (1 / n2)

    # --- exp -----------------------------------------------------------------------

    def exp(self, terms: int = 24) -> Multivector:
        """exp(A) by scaling and squaring of the Taylor series (any element, any metric)."""
        if self.coeffs.dtype == object:
            raise TypeError("exp needs float coefficients")
        scale = float(np.max(np.abs(self.coeffs))) if self.coeffs.size else 0.0
        k = max(0, int(np.ceil(np.log2(scale))) + 1) if scale > 0 else 0
        x = self * (0.5**k)
        term = Multivector.scalar(self.algebra, np.ones(self.batch_shape))
        total = term
        for i in range(1, terms):
            term = term.gp(x) * (1.0 / i)
            total = total + term
        for _ in range(k):
            total = total.gp(total)
        return total

    def left_matrix(self) -> np.ndarray:
        """The matrix L of left multiplication: (A X)_k = L[k, j] X_j (batch dims first)."""
        c = _dense_cache(self.algebra, self.algebra.gp_table)
        return np.einsum("...i,ijk->...kj", self.coeffs, c)

    def general_inverse(self) -> Multivector:
        """Inverse of any invertible element, by solving ``L_A X = 1`` (not only versors)."""
        L = self.left_matrix()
        one = np.zeros(L.shape[:-1])
        one[..., 0] = 1.0
        try:
            return self._new(np.linalg.solve(L, one[..., None])[..., 0])
        except np.linalg.LinAlgError:
            raise ValueError("multivector is not invertible") from None

    def sqrt(self, iterations: int = 60) -> Multivector:
        """Principal square root by the Denman-Beavers iteration (any associative algebra)."""
        y = self
        z = Multivector.scalar(self.algebra, np.ones(self.batch_shape))
        for _ in range(iterations):
            y, z = (y + z.general_inverse()) * 0.5, (z + y.general_inverse()) * 0.5
        return y

    def log(self, terms: int = 40) -> Multivector:
        """Principal logarithm, the inverse of ``exp``: inverse scaling and squaring.

        Square roots bring the element near 1, then the series
        ``log M = 2 Σ X^(2i+1) / (2i+1)`` with ``X = (M - 1)(M + 1)^-1`` is summed and scaled
        back. For a motor ``exp(B)`` with rotation angle below π this gives B (plus rounding
        in other grades; take ``.grade(2)``).
        """
        if self.coeffs.dtype == object:
            raise TypeError("log needs float coefficients")
        m, k = self, 0
        one = Multivector.scalar(self.algebra, np.ones(self.batch_shape))
        while k < 60 and np.max(np.abs((m - one).coeffs)) > 1e-3:
            m, k = m.sqrt(), k + 1
        x = (m - one).gp((m + one).general_inverse())
        x2, term, total = x.gp(x), x, x
        for i in range(1, terms):
            term = term.gp(x2)
            total = total + term * (1.0 / (2 * i + 1))
        return total * (2.0 ** (k + 1))

    # --- display -------------------------------------------------------------------

    def __repr__(self) -> str:
        """Terms on the algebra's display basis (CGA: the null basis, ``- 2 e1∞``)."""
        if self.batch_shape:
            return f"Multivector({self.algebra}, batch {self.batch_shape})"
        view = self.algebra.display
        if view is not None and self.coeffs.dtype != object:
            return view.repr(self)
        return format_terms(self.coeffs, self.algebra.blade_names)

    def allclose(self, other, **kw) -> bool:
        return bool(np.allclose(self.coeffs, self._coerce(other).coeffs, **kw))


def format_terms(coeffs, names, tol: float = 1e-12) -> str:
    """``1.0 + 0.5 e12 - 2.0 e1∞`` from coefficients and blade names."""
    parts = []
    for c, name in zip(coeffs, names, strict=True):
        if c is None or (not isinstance(c, np.ndarray) and c == 0):
            continue
        if isinstance(c, (float, np.floating)) and abs(c) < tol:
            continue
        label = "" if name == "1" else " " + name
        if isinstance(c, (int, float, np.floating)):
            sign = "-" if c < 0 else "+"
            magnitude = "" if label and abs(float(c)) == 1.0 else f"{abs(float(c)):g}"
            parts.append((sign, f"{magnitude}{label}".strip()))
        else:
            parts.append(("+", f"({c}){label}"))
    if not parts:
        return "0"
    first_sign, first = parts[0]
    text = ("-" if first_sign == "-" else "") + first
    for sign, p in parts[1:]:
        text += f" {sign} {p}"
    return text
