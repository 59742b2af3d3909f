"""Parallel calls: the lock held by every call from Python into numba's parallel code, and
the Python threads that run long serial compiled calls side by side.

numba's workqueue threading layer (its fallback where neither OpenMP nor TBB is installed)
aborts the process when two threads enter parallel code at once. A parallel call already
uses every thread numba has, so calls taking turns lose nothing. The batch kernels of the
CGA objects (``cga.objects``, ``cga.conventions``), the batch entries of the algorithms
(``algorithms.calls``), batch inverse kinematics (``tasks.ik``), the rollouts and their
energies (``sim.simulate``) run under ``PARALLEL_LOCK``. Compiled code holding it calls no
Python, so it is never taken twice by one thread.

``in_chunks`` runs a compiled function that releases the GIL (``nogil``) over contiguous
chunks of a batch on Python threads, as a ``prange`` loop over chunks would on numba's.
It is for calls whose chunks run for milliseconds or more (the rollouts): starting a thread
costs tens of microseconds, where numba's pool wakes its threads in a few. What it saves is
compile time: numba compiles a ``prange`` loop's body as a function of its own and links
into it every function it calls, so that LLVM optimises and emits all of that code once
more (``docs/architecture.md``, "Compiling and caching").
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import numba

PARALLEL_LOCK = threading.Lock()
"""Held for the whole of each parallel compiled call."""


def in_chunks(run: Callable[[int, int], object], batch: int) -> None:
    """``run(b0, b1)`` over contiguous chunks ``[b0, b1)`` of ``range(batch)``, one per
    thread of numba's (``numba.get_num_threads()``, at most ``batch``), the first on the
    calling thread and the others on Python threads; returns when all are done. ``run``
    must release the GIL (a ``nogil`` compiled function) for the chunks to overlap. An
    exception of any chunk is raised again here, the first chunk's first."""
    threads = max(1, min(numba.get_num_threads(), batch))
    bounds = [(batch * c // threads, batch * (c + 1) // threads) for c in range(threads)]
    errors: list[BaseException | None] = [None] * threads

    def chunk(c: int) -> None:
        try:
            run(*bounds[c])
        except BaseException as error:  # raised again on the calling thread
            errors[c] = error

    others = [threading.Thread(target=chunk, args=(c,)) for c in range(1, threads)]
    for thread in others:
        thread.start()
    chunk(0)
    for thread in others:
        thread.join()
    for error in errors:
        if error is not None:
            raise error
