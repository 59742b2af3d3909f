"""Standard JSON for every ``--json`` output and results file: a number that is not finite
(``nan``, ``inf``) becomes ``null``, numpy scalars and arrays become numbers and lists, so
that any JSON parser reads the output (Python's ``json`` would write ``NaN``/``Infinity``)."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

__all__ = ["clean", "dumps"]


def clean(obj: Any) -> Any:
    """``obj`` with non-finite floats as ``None`` and numpy values as Python ones."""
    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs) -> str:
    """``json.dumps`` of :func:`clean` ``(obj)``; never writes ``NaN`` or ``Infinity``."""
    return json.dumps(clean(obj), allow_nan=False, **kwargs)
