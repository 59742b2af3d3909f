"""The lock held by every call from Python into numba's parallel code.

numba's workqueue threading layer (its fallback where neither OpenMP nor TBB is installed)
aborts the process when two threads enter parallel code at once. A parallel call already
uses every thread numba has, so calls taking turns lose nothing. The batch kernels of the
CGA objects (``cga.objects``, ``cga.conventions``), the batch entries of the algorithms
(``algorithms.calls``), batch inverse kinematics (``tasks.ik``), the rollouts and their
energies (``sim.simulate``) run under ``PARALLEL_LOCK``. Compiled code holding it calls no
Python, so it is never taken twice by one thread.
"""

from __future__ import annotations

import threading

PARALLEL_LOCK = threading.Lock()
"""Held for the whole of each parallel compiled call."""
