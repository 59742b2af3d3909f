"""Arrays of libraries other than numpy, handed to the layer that serves them.

The checked paths (``algorithms.calls.run``, ``sim.simulate.simulate``) compute on numpy
arrays. An input from another array library (a dask array of samples, chunked along B) is
handed whole to the module that serves that library, which cuts it into numpy chunks and
calls the checked path again on each. That module lies above the call layer and imports
it; the call layer must not import it back (``tests/test_layers.py``). So serving modules
are declared by name, by the package itself (``cgadyn/__init__.py``, the top of every
layer: ``dask`` is served by ``cgadyn.distributed``), and imported when the first such
array arrives: without one, neither the module nor its library is imported.

A serving module has ``run(name, model, arrays, gravity, f_ext, options)``, the algorithm
``name`` of ``algorithms/table.py`` on its arrays, and ``simulate(model, q0, v0, dt, steps,
tau, kwargs)``, ``cgadyn.simulate`` on them (``kwargs``: simulate's other arguments).
"""

from __future__ import annotations

import importlib
from types import ModuleType

SERVERS: dict[str, str] = {}
"""The top-level package of an array type -> the module that serves arrays of that type."""


def serve(package: str, module: str) -> None:
    """Let ``module`` (a dotted name) serve the arrays whose type comes from ``package``."""
    SERVERS[package] = module


def server(arrays) -> ModuleType | None:
    """The module serving the first of ``arrays`` whose type comes from a package of
    ``SERVERS``, imported on first use; None when no array is such (numpy arrays, lists,
    numbers, None)."""
    for a in arrays:
        module = SERVERS.get(type(a).__module__.partition(".")[0])
        if module is not None:
            return importlib.import_module(module)
    return None
