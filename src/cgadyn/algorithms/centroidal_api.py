"""Centroidal quantities with Pinocchio's names and meanings (``centroidal.py`` computes them).

They work on fixed-base models too: bodies fixed to the world count for nothing, as in
Pinocchio.
"""

from __future__ import annotations

import numpy as np

from . import _inputs
from .calls import run


def total_mass(model) -> float:
    """The mass of every moving body (Pinocchio's ``computeTotalMass``)."""
    return model.total_mass


def center_of_mass(model, q, v=None, a=None):
    """The centre of mass in the world frame, (3,) or (B, 3); with ``v`` also its velocity,
    and with ``a`` its (classical) acceleration: ``c``, ``(c, ċ)`` or ``(c, ċ, c̈)``
    (Pinocchio's ``centerOfMass``: ``data.com[0], data.vcom[0], data.acom[0]``)."""
    if a is not None and v is None:
        raise ValueError("center_of_mass: an acceleration a needs a velocity v")
    q = _inputs.state(model, q, "q", model.nq)
    zeros = np.zeros(q.shape[:-1] + (model.nv,))
    out = run("com", model, (q, zeros if v is None else v, zeros if a is None else a))
    if v is None:
        return out[..., 0, :]
    if a is None:
        return out[..., 0, :], out[..., 1, :]
    return out[..., 0, :], out[..., 1, :], out[..., 2, :]


def centroidal_momentum_matrix(model, q) -> np.ndarray:
    """``A_g`` (6, nv) or (B, 6, nv): ``A_g v`` is the robot's momentum, linear then angular
    about its centre of mass, in world axes (Pinocchio's ``ccrba``)."""
    return run("centroidal", model, (q,))[0]


def centroidal_momentum(model, q, v) -> np.ndarray:
    """``h_g = A_g v``: linear momentum and angular momentum about the centre of mass, world
    axes, (6,) or (B, 6) (Pinocchio's ``computeCentroidalMomentum``)."""
    Ag = centroidal_momentum_matrix(model, q)
    v = _inputs.state(model, v, "v", model.nv)
    if v.shape[:-1] != Ag.shape[:-2]:
        raise ValueError(f"q and v must be one sample each or batches of the same size, got "
                         f"{Ag.shape[:-2]} and {v.shape[:-1]}")
    return np.einsum("...ij,...j->...i", Ag, v)


def com_jacobian(model, q) -> np.ndarray:
    """The Jacobian of the centre of mass, (3, nv) or (B, 3, nv): ``ċ = J_c v``, world frame
    (Pinocchio's ``jacobianCenterOfMass``)."""
    return centroidal_momentum_matrix(model, q)[..., :3, :] / model.total_mass
