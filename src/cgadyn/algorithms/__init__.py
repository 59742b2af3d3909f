"""Recursive dynamics on CGA: kinematics, RNEA, ABA, CRBA, Jacobians, energy.

The cores of rnea, aba and crba compile with ``fastmath={"contract"}``: the only liberty
taken is fusing a multiply and an add into one FMA instruction (GCC does so by default),
about 5 % faster; every other IEEE rule is kept, so NaN checks and the results against
Pinocchio (1e-15 relative) are unchanged.
"""

from .api import (
    aba,
    crba,
    energy,
    forward_kinematics,
    gravity_torques,
    jacobian,
    kinetic_energy,
    link_placements,
    nonlinear_effects,
    potential_energy,
    rnea,
)

__all__ = [
    "aba",
    "crba",
    "energy",
    "forward_kinematics",
    "gravity_torques",
    "jacobian",
    "kinetic_energy",
    "link_placements",
    "nonlinear_effects",
    "potential_energy",
    "rnea",
]
