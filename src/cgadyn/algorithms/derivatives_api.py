"""Analytic derivatives of the dynamics, with Pinocchio's meanings (``computeRNEADerivatives``,
``computeABADerivatives``, ``computeMinverse``).

Derivatives are taken in the tangent space of the configuration manifold: column l of a
derivative with respect to q is the derivative along ``integrate(model, q, ε e_l)``, so a
free flyer has six columns (its body twist), not seven. Each function takes one sample or a
batch ``(B, ...)`` and returns ``(nv, nv)`` or ``(B, nv, nv)`` arrays. The derivation is in
``docs/derivatives.md``.
"""

from __future__ import annotations

import numpy as np

from . import _inputs
from .calls import SLOTS, fast, run

G = _inputs.DEFAULT_GRAVITY
_RNEA_D, _ABA_D, _MINV = SLOTS["rnea_derivatives"], SLOTS["aba_derivatives"], SLOTS["minverse"]


def rnea_derivatives(model, q, v, a, gravity=G, f_ext=None):
    """``(∂τ/∂q, ∂τ/∂v, ∂τ/∂a)`` of inverse dynamics at (q, v, a), the last being M(q).

    ``f_ext``: external forces per joint as for ``rnea``.
    """
    if gravity is G and f_ext is None:
        out = fast(_RNEA_D, model.packed, q, v, a, None)
        if out.__class__ is tuple:
            return out
    return run("rnea_derivatives", model, (q, v, a), gravity, f_ext)


def aba_derivatives(model, q, v, tau, gravity=G, f_ext=None):
    """``(∂q̈/∂q, ∂q̈/∂v, ∂q̈/∂τ)`` of forward dynamics at (q, v, τ), the last being
    ``M(q)⁻¹``; ``∂q̈/∂q = -M⁻¹ ∂τ/∂q`` at ``q̈ = aba(q, v, τ)``."""
    if gravity is G and f_ext is None:
        out = fast(_ABA_D, model.packed, q, v, tau, None)
        if out.__class__ is tuple:
            return out
    return run("aba_derivatives", model, (q, v, tau), gravity, f_ext)


def minverse(model, q) -> np.ndarray:
    """``M(q)⁻¹``, full and symmetric, from the articulated-body recursion in O(n nv),
    without forming M (``docs/derivatives.md``, M1-M5)."""
    out = fast(_MINV, model.packed, q)
    if out.__class__ is np.ndarray:
        return out
    return run("minverse", model, (q,))
