"""A reference geometric algebra of any signature G(p,q,r): the oracle for the kernels."""

from .algebra import Algebra
from .basis_view import BasisView
from .multivector import Multivector

__all__ = ["Algebra", "BasisView", "Multivector"]
