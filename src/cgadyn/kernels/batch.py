"""Batch forms of every kernel over ``(B, k)`` arrays, run in parallel over samples.

The polynomial kernels are generated (``_generated_batch.py``, same formulas as
``_generated.py``, direct ``a[n, i]`` indexing), for the kernels that numpy-level code calls;
the closed forms of ``motors.py`` (exp, log, normalisation) are wrapped here, one row per
sample.

Contract (as for the single kernels): every argument has the sample axis first, ``out`` is
given and written, and is also returned. Nothing checks shapes, so callers from Python
should go through ``cgadyn.cga.objects`` (which does) or pass arrays of matching ``B``.
"""

from __future__ import annotations

from numba import prange

from .._jit import parallel
from ._generated_batch import (
    dot_batch,
    inertia_apply_batch,
    inertia_transform_batch,
    motor_mul_batch,
    motor_reverse_batch,
    motor_translation_batch,
    twist_cross_batch,
    twist_cross_wrench_batch,
    twist_sandwich_batch,
    wrench_sandwich_batch,
)
from .motors import motor_log, motor_normalize, twist_exp


@parallel
def twist_exp_batch(v, out):
    """Motors ``out[n] = exp(V[n] / 2)`` of twists ``v`` (B, 6) (eq. 6)."""
    for n in prange(v.shape[0]):
        twist_exp(v[n], out[n])
    return out


@parallel
def motor_log_batch(m, out):
    """Twists ``out[n]`` with ``exp(out[n] / 2) = M[n]`` of normalised motors ``m`` (B, 8)."""
    for n in prange(m.shape[0]):
        motor_log(m[n], out[n])
    return out


@parallel
def motor_normalize_batch(m, out):
    """Motors ``m`` (B, 8) projected back onto ``M ~M = 1``."""
    for n in prange(m.shape[0]):
        motor_normalize(m[n], out[n])
    return out


__all__ = [
    "dot_batch",
    "inertia_apply_batch",
    "inertia_transform_batch",
    "motor_log_batch",
    "motor_mul_batch",
    "motor_normalize_batch",
    "motor_reverse_batch",
    "motor_translation_batch",
    "twist_cross_batch",
    "twist_cross_wrench_batch",
    "twist_exp_batch",
    "twist_sandwich_batch",
    "wrench_sandwich_batch",
]
