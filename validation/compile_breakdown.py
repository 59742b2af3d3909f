"""Where a cold run's compilation goes: numba's compile events, per function, in CPU seconds.

Run as a script in a fresh ``NUMBA_CACHE_DIR`` (``startup.py --breakdown`` does), it listens
to numba's ``numba:compile`` events (raised only where no cached machine code was found),
runs one workload and prints one JSON line per compiled specialisation as it ends (the
function, its depth (0: compiled from Python; deeper: compiled while typing a caller), its
argument types, its CPU seconds inclusive (with the functions compiled inside it) and
exclusive, and the CPU seconds of the process so far), then one JSON line with them all.
CPU time of the process, not wall time, so that other jobs on the machine change the
numbers little. Workloads:

- ``aba``: a first ``cgadyn.aba`` on the panda;
- ``validate``: ``cgadyn.validate.validate_robot("panda")``, what ``cgadyn validate`` does;
- ``simulate``: three semi-implicit Euler steps of solo12 (a rollout without a world);
- ``contact``: the same with ``World()`` and solo12's collision model (a rollout with
  contact).

    python validation/compile_breakdown.py aba|validate|simulate|contact
"""

from __future__ import annotations

import json
import resource
import sys
from contextlib import contextmanager


def cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main(workload: str) -> int:
    from numba.core import event

    records: list[dict] = []
    stack: list[list[float]] = []  # [start, seconds of the compilations nested inside]

    def end(fn, args) -> None:
        began, nested = stack.pop()
        inclusive = cpu() - began
        if stack:
            stack[-1][1] += inclusive
        name = f"{fn.__module__}.{fn.__qualname__}" if fn else "?"
        records.append({"function": name, "depth": len(stack), "args": str(args),
                        "inclusive": inclusive, "exclusive": inclusive - nested,
                        "at": cpu() - start})
        print(json.dumps(records[-1]), flush=True)

    class Recorder(event.Listener):
        def on_start(self, ev) -> None:
            stack.append([cpu(), 0.0])

        def on_end(self, ev) -> None:
            data = ev.data or {}
            end(getattr(data.get("dispatcher"), "py_func", None), data.get("args"))

    start = cpu()
    event.register("numba:compile", Recorder())
    import numpy as np

    import cgadyn
    from cgadyn import _progress

    frame = _progress.frame

    @contextmanager
    def native(fn):  # a C entry point compiles without an event of its own
        stack.append([cpu(), 0.0])
        try:
            with frame(fn):
                yield
        finally:
            end(fn, "C entry point")

    _progress.frame = native
    if workload == "aba":
        m = cgadyn.load("panda")
        q = np.full(m.nq, 0.3)
        cgadyn.aba(m, q, q, q)
    elif workload == "validate":
        from cgadyn.validate import validate_robot

        validate_robot("panda")
    elif workload == "simulate":
        m = cgadyn.load("solo12")
        cgadyn.simulate(m, cgadyn.neutral(m), np.zeros(m.nv), 1e-3, 3,
                        integrator="semi_implicit_euler")
    elif workload == "contact":
        m = cgadyn.load("solo12")
        q = cgadyn.neutral(m)
        q[2] = 0.3
        cgadyn.simulate(m, q, np.zeros(m.nv), 1e-3, 3, integrator="semi_implicit_euler",
                        world=cgadyn.World(), collisions=cgadyn.collision_model(m))
    else:
        raise SystemExit(f"unknown workload {workload!r}: expected aba, validate, simulate "
                         "or contact")
    print(json.dumps({"workload": workload, "cpu": cpu() - start, "records": records}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1]))
