"""The configuration manifold, with Pinocchio's names and meanings.

A configuration ``q`` has ``model.nq`` entries and a velocity ``v`` ``model.nv``: they differ
on a free flyer, whose configuration is a position and a unit quaternion (a motor) and whose
velocity is a body twist, and on a spherical joint (a unit quaternion, an angular velocity).
``integrate`` and ``difference`` are the exponential and logarithm maps joint by joint
(``multibody.joints``); each takes one sample or a batch. What each joint type adds (its
neutral and random configurations, its quaternion) comes from its record.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints import table
from . import _inputs
from .calls import run


def integrate(model, q, v) -> np.ndarray:
    """``q ⊕ v``: the configuration reached from q by moving with the velocity v for unit
    time (for a free flyer ``M exp(V / 2)``, V the body twist); (nq,) or (B, nq)."""
    return run("integrate", model, (q, v))


def difference(model, q0, q1) -> np.ndarray:
    """``q1 ⊖ q0``: the velocity that moves q0 to q1 in unit time, so that
    ``integrate(q0, difference(q0, q1)) == q1`` (for a free flyer the logarithm of the
    relative motor ``~M0 M1``, the rotation at most π; an unbounded revolute joint's angle
    wrapped to (-π, π]); (nv,) or (B, nv)."""
    return run("difference", model, (q0, q1))


def interpolate(model, q0, q1, t) -> np.ndarray:
    """``q0 ⊕ t (q1 ⊖ q0)``: the configuration a fraction ``t`` of the way from q0 to q1
    along the manifold's geodesic (t in [0, 1], or beyond to extrapolate); ``t`` a number or
    one per sample (B,)."""
    d = difference(model, q0, q1)
    t = np.asarray(t, dtype=float)
    if t.ndim > 1 or (t.ndim == 1 and t.shape != d.shape[:1]) or not np.all(np.isfinite(t)):
        raise ValueError(f"t must be a finite number, or one per sample {d.shape[:1]}, got "
                         f"shape {t.shape}")
    return integrate(model, q0, d * (t[:, None] if t.ndim == 1 else t))


def neutral(model) -> np.ndarray:
    """The neutral configuration (Pinocchio's ``neutral``): every joint's own
    (``multibody.joints``: one-dof joints at 0, a free flyer at the origin with the
    identity rotation ``(0, 0, 0, 0, 0, 0, 1)``)."""
    return table.neutral(model)


def random_configuration(model, rng=None, box: float = 1.0) -> np.ndarray:
    """A random configuration: one-dof joints uniform within their limits (unbounded ones in
    [-π, π]), free flyers at a uniform position in the box ``[-box, box]³`` with a uniformly
    random rotation. ``rng``: a ``numpy.random.Generator``, a seed or None."""
    return table.random_configuration(model, np.random.default_rng(rng), box)


def normalize(model, q) -> np.ndarray:
    """``q`` with every unit quaternion (free flyers', spherical joints') scaled to unit
    length (a zero one is an error); (nq,) or (B, nq)."""
    return table.normalize(model, _inputs.state(model, q, "q", model.nq).copy())
