"""Bilateral constraints in CGA: point and frame contacts, loop closures, their Jacobian,
drift and Delassus matrix, constrained forward, impulse and contact inverse dynamics
(``docs/constraints.md``, C1-C11; Pinocchio's ``RigidConstraintModel`` family).

- ``model``: ``Constraint``, a point (conformal point) or frame (motor) of a link held to
  another link or to the world;
- ``kinematics``: the rows of one constraint (C1, C2) and its drift (C3-C5);
- ``operators``: ``constraint_jacobian``, ``constraint_drift``, ``delassus`` (C7);
- ``solve``: the forces through the Delassus matrix, directly or by proximal iterations
  (C8), and the errors naming a constraint;
- ``dynamics``: ``constrained_dynamics`` (C6), ``impulse_dynamics`` (C9),
  ``contact_inverse_dynamics`` (C10).
"""

from .dynamics import constrained_dynamics, contact_inverse_dynamics, impulse_dynamics
from .model import Constraint
from .mujoco_equality import mujoco_constraints
from .operators import constraint_drift, constraint_jacobian, delassus
from .solve import SolveInfo

__all__ = ["Constraint", "SolveInfo", "constrained_dynamics", "constraint_drift",
           "constraint_jacobian", "contact_inverse_dynamics", "delassus", "impulse_dynamics",
           "mujoco_constraints"]
