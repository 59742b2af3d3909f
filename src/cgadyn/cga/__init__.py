"""The conformal model G(4,1): null basis, typed subspaces, conventions, inertia.

The typed objects are imported on first use, so that importing ``cgadyn.cga.basis`` (as the
kernel generator does) never pulls in the compiled kernels.
"""

from __future__ import annotations

import importlib

__all__ = ["Circle", "Inertia", "Line", "Motor", "Plane", "Point", "Sphere", "Twist", "Wrench"]


def __getattr__(name: str):
    if name in __all__:
        return getattr(importlib.import_module("cgadyn.cga.objects"), name)
    raise AttributeError(f"module 'cgadyn.cga' has no attribute {name!r}")
