"""What the C entry points of ``entries/`` share: their signature and the packed model.

``cgadyn._native`` calls an entry as ``entry(packed, x, f, nf, o, options) -> status``:
``packed`` the model's buffer (``multibody/packed.py``), ``x`` and ``o`` arrays of pointers
to the inputs' and outputs' data, ``f`` the ``nf`` external wrenches (0 or n), ``options``
the integer arguments, so that one signature serves an algorithm of any arity.
"""

from numba import carray, types

from .._jit import serial
from .._views import as_int64
from ..multibody.packed import HEADER

_P = types.CPointer(types.float64)
SIGNATURE = types.int64(_P, types.CPointer(_P), _P, types.int64, types.CPointer(_P),
                        types.CPointer(types.int64))
"""``(packed, x, f, nf, o, options) -> status``."""


@serial
def packed_array(pk):
    """The packed model at ``pk`` as an array, its length read from its header."""
    return carray(pk, (carray(as_int64(pk), (HEADER,))[HEADER - 1],))
