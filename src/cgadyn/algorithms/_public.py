"""The body of every public function that has a fast path, written once.

A public function of a compiled algorithm (``api.rnea``, ``derivatives_api.minverse``, ...)
is its signature, its docstring and one call of the function ``fast_first`` makes for its
algorithm: the C entry point first (``calls.fast``), the checked path (``calls.run``) for
anything that refuses (``docs/architecture.md``, "The path of one call"). A closure, not a
factory of the public functions themselves, so that these keep their own signatures
(keywords ``q=``, ``tau=``; ``help()``) at the cost of one plain Python call.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..multibody.packed import DEFAULT_GRAVITY
from .calls import SLOTS, fast, run
from .table import BY_NAME


def fast_first(name: str) -> Callable:
    """``call(model, x0, x1=None, x2=None, gravity=DEFAULT_GRAVITY, f_ext=None)`` for the
    algorithm ``name`` of ``table.py``, whose inputs ``x`` come in table order: the fast
    path's result when it gives one (default gravity, no ``f_ext``, one canonical sample
    and status 0), else that of ``calls.run``, which converts, batches and explains. The
    fast call has the algorithm's arity (``cgadyn._native`` refuses any other), so the
    closure is picked by the number of inputs and whether it takes wrenches."""
    alg = BY_NAME[name]
    slot, ndarray = SLOTS[name], np.ndarray
    if len(alg.inputs) == 3 and alg.forces:
        def call(model, x0, x1=None, x2=None, gravity=DEFAULT_GRAVITY, f_ext=None):
            if gravity is DEFAULT_GRAVITY and f_ext is None:
                out = fast(slot, model.packed, x0, x1, x2, None)
                if out.__class__ is ndarray or out.__class__ is tuple:
                    return out
            return run(name, model, (x0, x1, x2), gravity, f_ext)
    elif len(alg.inputs) == 1 and not alg.forces and not alg.options:
        def call(model, x0, x1=None, x2=None, gravity=DEFAULT_GRAVITY, f_ext=None):
            if gravity is DEFAULT_GRAVITY and f_ext is None:
                out = fast(slot, model.packed, x0)
                if out.__class__ is ndarray or out.__class__ is tuple:
                    return out
            return run(name, model, (x0,), gravity, f_ext)
    else:
        raise ValueError(f"no fast-first call for {name!r}: its arity has no closure here")

    call.__qualname__ = call.__name__ = f"{name}_fast_first"
    return call
