"""The words of a fault: the ``ValueError`` for a status returned by compiled code.

Compiled code says only what went wrong and where (``status.py``); this module looks at
the inputs and the model to say it in terms of the call: which array holds NaN, which
joint's subtree has no mass, what overflowed.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints import QUATERNION_TOLERANCE, TYPES, table
from . import status as S

TINY_MASS = 1e-300
"""A subtree lighter than this (kg) cannot be accelerated in double precision."""


def explain(code: int, model, algorithm, arrays: dict) -> ValueError:
    """The error for the status ``code`` of ``algorithm`` (a ``table.Algorithm``) run on
    ``arrays`` (name -> the converted input, one sample or a batch)."""
    fault, joint, sample = S.decode(code)
    batch = next(iter(arrays.values())).ndim == 2 if arrays else False
    where = f"sample {sample}: " if batch else ""
    if fault == S.NONFINITE_INPUT or not all(np.isfinite(a).all() for a in arrays.values()):
        return _nonfinite_input(model, arrays)  # NaN and inf propagate: look at inputs first
    if fault == S.QUATERNION:
        return _quaternion(model, arrays, joint, sample if batch else None)
    if fault == S.SINGULAR:
        return ValueError(f"{where}singular articulated-body inertia at joint "
                          f"{model.joint_names[joint]!r}: {_subtree(model, joint)}; "
                          f"{algorithm.name} cannot solve for its acceleration")
    if fault == S.NONFINITE_RESULT:
        return ValueError(f"{where}{algorithm.name} produced NaN or inf from finite inputs: "
                          f"{algorithm.nonfinite}. {_magnitudes(arrays, sample, batch)}"
                          f"{_light_subtrees(model)}")
    if fault == S.WRONG_SHAPE:
        shapes = ", ".join(f"{k} {v.shape}" for k, v in arrays.items())
        return ValueError(f"{algorithm.name}: arrays of the wrong shape: {shapes}")
    return ValueError(f"{algorithm.name} failed with status {code}")


def _nonfinite_input(model, arrays: dict) -> ValueError:
    for name, a in arrays.items():
        bad = np.argwhere(~np.isfinite(a))
        if bad.size:
            index = tuple(int(i) for i in bad[0])
            return ValueError(f"{name} contains NaN or inf at index {index} "
                              f"({_coordinate(model, name, index[-1])})")
    return ValueError("an input contains NaN or inf")


def _coordinate(model, name: str, k: int) -> str:
    """Which joint (and which of its coordinates) entry k of a state is."""
    return table.describe(model, not name.startswith("q"), k)


def _quaternion(model, arrays: dict, joint: int, sample) -> ValueError:
    """The first configuration among ``arrays`` whose quaternion of ``joint`` is off."""
    record = TYPES[int(model.joint_types[joint])]
    o, n = record.quaternion, record.unit_length
    i = int(model.idx_q[joint]) + o
    for name, q in arrays.items():
        x = q[sample] if sample is not None else q
        norm = float(np.linalg.norm(x[i:i + n])) if name.startswith("q") else 1.0
        if not abs(norm - 1.0) <= QUATERNION_TOLERANCE:
            break
    where = f"{name}[{sample}, {i}:{i + n}]" if sample is not None else f"{name}[{i}:{i + n}]"
    what = "quaternion" if n == 4 else "unit vector"
    return ValueError(f"{where}, the {what} ({', '.join(record.q_names[o:o + n])}) of "
                      f"{record.label} joint "
                      f"{model.joint_names[joint]!r}, has norm {norm:.6g}; expected a unit "
                      f"{what} (cgadyn.normalize(model, q) normalises q)")


def _subtree(model, joint: int) -> str:
    mass = float(sum(model.body_mass[k] for k in model.subtree(joint)))
    if mass <= 0.0:
        return "the subtree it moves has no mass"
    if mass < TINY_MASS:
        return f"the subtree it moves has a mass of {mass:.3g} kg, too small to accelerate"
    return (f"the subtree it moves ({mass:.4g} kg) has no inertia along the joint's motion "
            f"(a point mass on a revolute axis, or a singular inertia)")


def _magnitudes(arrays: dict, sample: int, batch: bool) -> str:
    parts = []
    for name, a in arrays.items():
        x = a[sample] if batch else a
        if x.size:
            parts.append(f"max |{name}| = {np.abs(x).max():.3g}")
    return ("Inputs: " + ", ".join(parts) + ".") if parts else ""


def _light_subtrees(model) -> str:
    light = [model.joint_names[j] for j in range(model.njoints)
             if 0.0 < sum(model.body_mass[k] for k in model.subtree(j)) < 1e-100]
    return (f" Nearly massless subtrees at joints {', '.join(light)}." if light else "")
