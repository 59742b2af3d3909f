"""Free rigid bodies in plane-based GA G(d,0,1), d = 1..4 (Dorst & De Keninck, "May the
Forque be with You: Dynamics in PGA", chapter 2 and appendix B).

One code path for every d: ``pga(d)`` gives the model, ``Inertia`` the inertia duality,
``RigidBody`` + ``state_derivative`` the law of motion (Table 2.1), ``Gravity``/``Hooke``/
``Damping``/``Wrench``/``Forques`` the forques, ``step`` with ``'euler'``/``'rk4'`` the
integrators, ``kinetic_energy``/``power`` section 2.7, ``contact_impulse`` section 2.6,
``simulate``/``hypercube_on_spring`` figs. 2.4/2.5, ``free_tops`` the closed forms of
Appendix B.
"""

from .body import RigidBody, check_state, dynamics, hypercube, kinematics, state_derivative
from .contact import contact_impulse, normal_velocity, penetrations, signed_distance
from .energy import kinetic_energy, potential_energy, power, total_energy
from .forques import Damping, Forques, Gravity, Hooke, Wrench, forque_at
from .inertia import Inertia
from .integrators import INTEGRATORS, euler_step, normalize_motor, rk4_step, step
from .model import PGA, pga
from .simulate import hypercube_on_spring, simulate

__all__ = [
    "INTEGRATORS",
    "PGA",
    "Damping",
    "Forques",
    "Gravity",
    "Hooke",
    "Inertia",
    "RigidBody",
    "Wrench",
    "check_state",
    "contact_impulse",
    "dynamics",
    "euler_step",
    "forque_at",
    "hypercube",
    "hypercube_on_spring",
    "kinematics",
    "kinetic_energy",
    "normal_velocity",
    "normalize_motor",
    "penetrations",
    "pga",
    "potential_energy",
    "power",
    "rk4_step",
    "signed_distance",
    "simulate",
    "state_derivative",
    "step",
    "total_energy",
]
