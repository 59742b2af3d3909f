"""Checks every compiled core makes on its sample: before computing, and after.

Before: the free flyers' quaternions are near unit length. After: the result is finite.
Non-finite inputs need no check of their own: NaN and inf propagate to the result, and
when it is not finite ``errors.explain`` looks at the inputs first, to name the array,
index and joint, before it speaks of an overflow. Each check returns a status
(``status.py``): compiled code never raises.
"""

from __future__ import annotations

from .._jit import inline
from .._views import carve, data_pointer
from ..multibody.joints import quaternion_error
from .status import NONFINITE_RESULT, OK, QUATERNION, fault


@inline
def finite(x):
    """True when a C-contiguous array holds no NaN or inf (``v - v`` is 0 exactly for
    finite v and NaN otherwise: a branch-free loop over a bare flat view, which unlike
    ``reshape`` touches no reference count)."""
    y, _ = carve(data_pointer(x), 0, (x.size,))
    ok = True
    for i in range(y.shape[0]):
        ok &= (y[i] - y[i]) == 0.0
    return ok


@inline
def check_configuration(m, q):
    """The free flyers' quaternions in ``q`` near unit length."""
    j = quaternion_error(m, q)
    return OK if j < 0 else fault(QUATERNION, j)


@inline
def check_result(out):
    """``NONFINITE_RESULT`` when the result is not finite."""
    return OK if finite(out) else fault(NONFINITE_RESULT, -1)
