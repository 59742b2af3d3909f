"""Compiled kernels for the typed subspaces of CGA: motors, twists, wrenches, inertias.

``_generated`` holds the explicit formulas produced by ``tools/generate_kernels.py``;
``motors`` the closed forms (exp, log, normalisation) built on them; ``halfangle`` the
half-angle sine and cosine of the joint motors; ``layout`` the signs and index maps of the
coefficients; ``rigid`` rigid inertias as ten parameters;
``batch`` the ``(B, k)`` forms that run in parallel over samples.
"""

from ._generated import (
    adjoint_apply,
    adjoint_apply_transpose,
    dot,
    inertia_apply,
    inertia_congruence,
    inertia_congruence_add,
    inertia_congruence_downdate_add,
    inertia_transform,
    motor_mul,
    motor_mul_rotor,
    motor_mul_translator,
    motor_reverse,
    motor_translation,
    translator_rotor,
    twist_cross,
    twist_cross_wrench,
    twist_sandwich,
    twist_sandwich_rev,
    wrench_adjoint,
    wrench_sandwich,
    wrench_sandwich_rev,
)
from .motors import motor_log, motor_normalize, twist_exp

__all__ = [
    "adjoint_apply",
    "adjoint_apply_transpose",
    "dot",
    "inertia_apply",
    "inertia_congruence",
    "inertia_congruence_add",
    "inertia_congruence_downdate_add",
    "inertia_transform",
    "motor_log",
    "motor_mul",
    "motor_mul_rotor",
    "motor_mul_translator",
    "motor_normalize",
    "motor_reverse",
    "motor_translation",
    "translator_rotor",
    "twist_cross",
    "twist_cross_wrench",
    "twist_exp",
    "twist_sandwich",
    "twist_sandwich_rev",
    "wrench_adjoint",
    "wrench_sandwich",
    "wrench_sandwich_rev",
]
