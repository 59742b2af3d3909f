"""Kinetic and potential energy of a robot.

Kinetic: ``T = ½ Σ_j p(V_j, I_j[V_j]) = -½ Σ_j V_j · I_j[V_j]`` (eqs. 9 and 15), with the
body twists ``V_j`` of the forward pass of Algorithm 2. Potential: ``U = -Σ_j m_j g · c_j``
with ``c_j`` the world position of body j's centre of mass, the translation of the motor
``M^w_j T(c_j)``.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .._jit import parallel, serial
from ..kernels import (
    dot,
    inertia_apply,
    joint_motor,
    motor_mul,
    motor_translation,
    translator_rotor,
    twist_sandwich_rev,
)
from ..multibody.packed import unpack
from . import _workspace as ws


@serial
def energy_core(parents, types, placements, axes, inertias, masses, coms, q, qd, gravity,
                M, Mw, V, tmp, joint, local):
    """(kinetic, potential) of one sample; ``gravity`` is the 3-vector g."""
    n = parents.shape[0]
    kinetic = 0.0
    potential = 0.0
    for j in range(n):
        p = parents[j]
        joint_motor(axes[j], types[j] == 1, q[j], joint)
        motor_mul(placements[j], joint, M[j])
        if p < 0:
            V[j, :] = 0.0
            Mw[j] = M[j]
        else:
            twist_sandwich_rev(M[j], V[p], V[j])
            motor_mul(Mw[p], M[j], Mw[j])
        for k in range(6):
            V[j, k] += qd[j] * axes[j, k]
        inertia_apply(inertias[j], V[j], tmp)
        kinetic -= 0.5 * dot(V[j], tmp)
        translator_rotor(coms[j, 0], coms[j, 1], coms[j, 2], 1.0, 0.0, 0.0, 0.0, joint)
        motor_mul(Mw[j], joint, local)
        c1, c2, c3 = motor_translation(local)
        potential -= masses[j] * (gravity[0] * c1 + gravity[1] * c2 + gravity[2] * c3)
    return kinetic, potential


@parallel
def energy_batch(packed, masses, coms, q, qd, gravity, threads):
    parents, types, placements, axes, inertias, _ = unpack(packed)
    n = parents.shape[0]
    batch = q.shape[0]
    out = np.empty((batch, 2))
    starts, stops = ws.chunks(batch, threads)
    for c in prange(starts.shape[0]):
        M, Mw, V = ws.motors(n), ws.motors(n), ws.bivectors(n)
        tmp, joint, local = np.empty(6), np.empty(8), np.empty(8)
        for b in range(starts[c], stops[c]):
            out[b, 0], out[b, 1] = energy_core(parents, types, placements, axes, inertias, masses,
                                               coms, q[b], qd[b], gravity, M, Mw, V, tmp, joint,
                                               local)
    return out
