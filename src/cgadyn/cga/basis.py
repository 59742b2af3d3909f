"""The conformal model G(4,1) in the null basis of the CGA paper, and its typed subspaces.

e0 = ½(e− − e+) is the origin and e∞ = e+ + e− the point at infinity, so that e0·e∞ = −1
(the paper's convention). Blades are written in the vector order e0, e1, e2, e3, e∞: ``e01``,
``e1∞``, ``e123∞``. The typed subspaces are

- motors (8 floats): ``1, e12, e13, e23, e1∞, e2∞, e3∞, e123∞``;
- twists (6 floats, eq. 7): ``e23, e13, e12, e1∞, e2∞, e3∞``;
- wrenches (6 floats, eq. 8) and inertia elements (eqs. 12-14): ``e23, e13, e12, e01, e02, e03``.
"""

from __future__ import annotations

from ..algebra import Algebra, BasisView, Multivector

CGA = Algebra.cga()

MOTOR_BLADES = ("1", "e12", "e13", "e23", "e1∞", "e2∞", "e3∞", "e123∞")
TWIST_BLADES = ("e23", "e13", "e12", "e1∞", "e2∞", "e3∞")
WRENCH_BLADES = ("e23", "e13", "e12", "e01", "e02", "e03")
ROTOR_BLADES = ("1", "e12", "e13", "e23")


def _basis() -> tuple[BasisView, dict[str, Multivector]]:
    e = {n: Multivector.blade(CGA, "e" + n) for n in CGA.names}
    vectors = {
        "e0": (e["-"] - e["+"]) * 0.5,
        "e1": e["1"],
        "e2": e["2"],
        "e3": e["3"],
        "e∞": e["+"] + e["-"],
    }
    view = BasisView(list(vectors.values()), ["0", "1", "2", "3", "∞"])
    return view, vectors


NULL, VECTORS = _basis()
CGA.display = NULL  # multivectors of this algebra print in the null basis: 1 + 0.5 e12 - 2 e1∞
e0, e1, e2, e3, einf = (VECTORS[k] for k in ("e0", "e1", "e2", "e3", "e∞"))


def motor_mv(values) -> Multivector:
    """Reference multivector of motor coefficients (..., 8)."""
    return NULL.multivector(values, list(MOTOR_BLADES))


def twist_mv(values) -> Multivector:
    """Reference multivector of twist coefficients (..., 6)."""
    return NULL.multivector(values, list(TWIST_BLADES))


def wrench_mv(values) -> Multivector:
    """Reference multivector of wrench coefficients (..., 6)."""
    return NULL.multivector(values, list(WRENCH_BLADES))


def motor_of(mv: Multivector):
    return NULL.coeffs(mv, list(MOTOR_BLADES))


def twist_of(mv: Multivector):
    return NULL.coeffs(mv, list(TWIST_BLADES))


def wrench_of(mv: Multivector):
    """Wrench coefficients of ``mv``: its projection on the wrench blades."""
    return NULL.coeffs(mv, list(WRENCH_BLADES))
