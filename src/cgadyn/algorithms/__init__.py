"""Recursive dynamics on CGA: RNEA, ABA, CRBA, kinematics, Jacobians, energy, the
configuration manifold and centroidal quantities.

Each compiled algorithm is one core in its own file (``rnea.py``, ``aba.py``, ...), listed in
``table.py``; ``calls.py`` is the path of a call from the public functions (``api.py``,
``configuration.py``, ``centroidal_api.py``) to the core, described in
``docs/architecture.md``.
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
from .centroidal_api import (
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    com_jacobian,
    total_mass,
)
from .configuration import (
    difference,
    integrate,
    interpolate,
    neutral,
    normalize,
    random_configuration,
)
from .derivatives_api import aba_derivatives, minverse, rnea_derivatives

__all__ = [
    "aba",
    "aba_derivatives",
    "minverse",
    "rnea_derivatives",
    "center_of_mass",
    "centroidal_momentum",
    "centroidal_momentum_matrix",
    "com_jacobian",
    "difference",
    "integrate",
    "interpolate",
    "neutral",
    "normalize",
    "random_configuration",
    "total_mass",
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
