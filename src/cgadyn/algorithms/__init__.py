"""Recursive dynamics on CGA: kinematics, RNEA, ABA, CRBA, Jacobians, energy."""

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
