"""The path of a constraint call to ``constraints/core.py`` and back, as ``algorithms/calls.py``
is for the algorithms: one sample through the C entry of ``cgadyn._native`` (registered on
first use in a slot of its own per output shape) or numba's dispatcher, a batch through one
parallel call; a status becomes the ``ValueError`` that names its cause.
"""

from __future__ import annotations

import threading

import numba
import numpy as np

from .._threads import PARALLEL_LOCK
from ..algorithms import _inputs
from ..algorithms.calls import _native
from ..algorithms.errors import explain
from ..algorithms.status import DELASSUS_SINGULAR, decode
from ..algorithms.table import BY_NAME
from .core import (
    DELASSUS,
    DRIFT,
    FORWARD,
    IMPULSE,
    INFO,
    SYSTEM,
    constraint_batch,
    constraint_native,
    constraint_single,
)
from .model import Pack
from .solve import singular_constraint

FIRST_SLOT, LAST_SLOT = 32, 63
"""The slots of ``cgadyn._native`` the constraints use (the algorithms take the first)."""

SYSTEM_GROUP, DELASSUS_GROUP, DYNAMICS_GROUP = 0, 1, 2
"""The modes by their outputs: ``(J, γ)``, ``G``, ``(x, λ, info)``; a pack's native slot
per group is in ``Pack.slots`` once registered."""
_GROUPS = {SYSTEM: 0, DRIFT: 0, DELASSUS: 1, FORWARD: 2, IMPULSE: 2}
_SLOTS: dict[tuple[int, int, int], int] = {}
_REGISTER = threading.Lock()


def _no_fast_path(*args):
    return None


fast = _native.call if _native is not None else _no_fast_path
"""``fast(slot, packed, cons, q, v, tau, settings, mode)``: the outputs of a canonical
one-sample call, else something that is neither an array nor a tuple."""


def _outputs(mode: int, nr: int) -> list[list[int]]:
    if _GROUPS[mode] == 0:
        return [[nr, -3], [nr]]
    if _GROUPS[mode] == 1:
        return [[nr, nr]]
    return [[-3], [nr], [INFO]]


def slot(p: Pack, mode: int) -> int:
    """The native slot of ``mode`` for packs of this size, registered on first use; -1 where
    there is no extension or no free slot."""
    group = _GROUPS[mode]
    found = p.slots.get(group)
    if found is not None:
        return found
    if _native is None:
        return -1
    key = (group, p.nc, p.nr)
    with _REGISTER:
        s = _SLOTS.get(key)
        if s is None:
            s = FIRST_SLOT + len(_SLOTS)
            if s > LAST_SLOT:
                return -1
            _native.register(s, constraint_native.address, [len(p.array), -2, -3, -3, 4],
                             _outputs(mode, p.nr), False, 1)
            _SLOTS[key] = s
    p.slots[group] = s
    return s


def run(model, p: Pack, mode: int, q, v, tau, settings, gravity=_inputs.DEFAULT_GRAVITY):
    """``mode`` of ``constraints/core.py`` on checked states (one sample or a batch; v, tau
    ignored where the mode takes none): ``(J, γ)``, ``G`` or ``(q̈ or v⁺, λ, info)``."""
    packed = _inputs.packed(model, gravity)
    nr, nv = p.nr, model.nv
    batch = q.shape[:-1]
    if not batch:
        s = slot(p, mode)
        if s >= 0:
            r = _native.call(s, packed, p.array, q, v, tau, settings, mode)
            if isinstance(r, int):
                raise error(model, p, mode, r, q, v, tau)
            if r is not None:
                return r
    shapes = {"J": (nr, nv), "g": (nr,), "G": (nr, nr), "a": (nv,), "lam": (nr,),
              "info": (INFO,)}
    out = {k: np.empty(batch + s) for k, s in shapes.items()}
    if not batch:
        status = constraint_single(packed, p.array, q, v, tau, settings, mode, *out.values())
    elif batch[0] == 0:
        status = 0
    else:
        with PARALLEL_LOCK:
            status = constraint_batch(packed, p.array, q, v, tau, settings, mode,
                                      *out.values(), numba.get_num_threads())
    if status != 0:
        raise error(model, p, mode, int(status), q, v, tau)
    if _GROUPS[mode] == 0:
        return out["J"], out["g"]
    if _GROUPS[mode] == 1:
        return out["G"]
    return out["a"], out["lam"], out["info"]


def error(model, p: Pack, mode: int, status: int, q, v, tau) -> ValueError:
    """The error of a status: a singular Delassus matrix names its constraint
    (``solve.singular_constraint``); the others are the algorithms' (``errors.explain``)."""
    code, _, sample = decode(status)
    if code == DELASSUS_SINGULAR:
        x = q if q.ndim == 1 else q[sample]
        G = run(model, p, DELASSUS, x, p.zero, p.zero, np.zeros(4))
        why = singular_constraint(G, p.constraints)
        return ValueError(why or "the Delassus matrix G = J M⁻¹ Jᵀ is singular: the set is "
                          "redundant or conflicting; pass damping > 0 (e.g. 1e-8)")
    if mode == FORWARD:
        return explain(status, model, BY_NAME["aba"], {"q": q, "v": v, "tau": tau})
    if mode in (IMPULSE, DRIFT):
        return explain(status, model, BY_NAME["energy"], {"q": q, "v": v})
    return explain(status, model, BY_NAME["minverse"], {"q": q})
