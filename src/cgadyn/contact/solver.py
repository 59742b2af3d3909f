"""The compiled entries of the contact solvers: one problem on the calling thread, or a batch
of problems of the same size split over numba's threads (``docs/contact.md``, K16-K19)."""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import core, parallel
from ..algorithms._workspace import chunks
from ..algorithms.status import OK, at_sample
from .admm import SCRATCH_ROWS, admm_solve
from .pgs import pgs_solve

ADMM, PGS = 0, 1
"""The solvers, by code."""


@core
def solve_one(solver, G, g, mu, bounds, R, settings, lam, info, C, w):
    """``admm_solve`` or ``pgs_solve`` by code, with the caller's scratch (``C`` m x m, ``w``
    ``SCRATCH_ROWS`` x ``max(m, 6)``); the blocks: the cones of ``mu`` (nc,), then the
    intervals of ``bounds`` (nb, 2) (``ncp.py``). A status."""
    if solver == PGS:
        return pgs_solve(G, g, mu, bounds, R, settings, lam, info, C, w)
    return admm_solve(G, g, mu, bounds, R, settings, lam, info, C, w)


@parallel
def solve_batch(solver, G, g, mu, bounds, R, settings, lam, info, threads):
    """(B, ...) problems of ``solve_one`` in parallel chunks, each chunk's scratch made once;
    a status naming the first sample that failed."""
    batch, m = g.shape
    starts, stops = chunks(batch, threads)
    status = np.zeros(starts.shape[0], dtype=np.int64)
    for c in prange(starts.shape[0]):
        C = np.empty((m, m))
        w = np.empty((SCRATCH_ROWS, max(m, 6)))
        for b in range(starts[c], stops[c]):
            s = solve_one(solver, G[b], g[b], mu[b], bounds[b], R[b], settings, lam[b], info[b],
                          C, w)
            if s != OK:
                status[c] = at_sample(s, b)
                break
    for c in range(starts.shape[0]):
        if status[c] != OK:
            return status[c]
    return OK
