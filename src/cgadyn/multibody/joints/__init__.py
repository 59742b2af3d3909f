"""Every joint type in one place: its motor, its motion subspace, its configuration space.

As in Featherstone's ``jcalc``, adding a joint type means adding a case here, and nowhere
else but its tests and the converters (``docs/joints.md``). A joint type is

- a file of its own (``revolute``, ``prismatic``, ``free_flyer``, ``spherical``,
  ``planar``, ``translation``, ``helical``): its
  code, its compiled joint motor ``M_J(q)`` and manifold maps ⊕/⊖, and its record
  (``record.JointType``: sizes, motion subspace, limits, neutral and random configurations,
  quaternion, actuation, speeds, Pinocchio's and MuJoCo's layouts);
- a case in each compiled function of ``dispatch`` that branches on the type code;
- an entry in ``table.TYPES``, which the other layers ask.

======================  ====  ====  ====================================================
type                    nq_j  nv_j  M_J(q_j) and S_j
======================  ====  ====  ====================================================
``REVOLUTE``            1     1     ``exp(q B / 2) = cos(q/2) + sin(q/2) B``: B a unit line
``REVOLUTE_UNBOUNDED``  1     1     the same, for an angle without limits
``PRISMATIC``           1     1     ``exp(q B / 2) = 1 + (q/2) B``: B a unit direction
``FREE_FLYER``          7     6     the motor ``T(p) R(x, y, z, w)`` of
                                    ``q_j = (p1, p2, p3, x, y, z, w)``; ``S_j`` the six
                                    unit twists, so ``S_j v_j`` is the body twist ``(v, ω)``
``SPHERICAL``           4     3     the rotor ``R(x, y, z, w)`` of ``q_j = (x, y, z, w)``;
                                    ``S_j`` the three unit rotation twists, so ``v_j`` is
                                    ``ω`` in the child's frame (the free flyer's rotation)
``PLANAR``              4     3     ``T(x, y, 0) R_z(θ)`` of ``(x, y, cos θ, sin θ)``;
                                    ``S_j`` the unit twists of vx, vy, ωz (SE(2))
``TRANSLATION``         3     3     ``T(q)``; ``S_j`` the three unit translations
``HELICAL``             1     1     ``exp(q B / 2)``, B the screw ``L + h d`` (pitch h)
======================  ====  ====  ====================================================
"""

from .dispatch import (
    ADDITIVE,
    QUATERNION_AT,
    QUATERNION_TOLERANCE,
    free_root,
    is_additive,
    joint_difference,
    joint_frame_rate,
    joint_integrate,
    joint_motors,
    joint_power,
    joint_scalars,
    joint_step,
    joint_transport,
    joint_twist,
    quaternion_error,
    unit_axes,
)
from .free_flyer import FREE_FLYER
from .helical import HELICAL
from .planar import PLANAR
from .prismatic import PRISMATIC
from .record import JointType
from .revolute import REVOLUTE, REVOLUTE_UNBOUNDED
from .spherical import SPHERICAL
from .table import (
    ACTUATED,
    JOINT_KINDS,
    KIND_TYPE,
    NQ,
    NV,
    SPEEDS,
    TYPE_NAMES,
    TYPES,
    of_kind,
)
from .translation import TRANSLATION

__all__ = [
    "ACTUATED", "ADDITIVE", "FREE_FLYER", "HELICAL", "JOINT_KINDS", "KIND_TYPE", "NQ", "NV",
    "PLANAR", "PRISMATIC", "QUATERNION_AT", "QUATERNION_TOLERANCE", "REVOLUTE",
    "REVOLUTE_UNBOUNDED", "SPEEDS", "SPHERICAL", "TRANSLATION", "TYPES", "TYPE_NAMES",
    "JointType", "free_root", "is_additive",
    "joint_difference", "joint_frame_rate", "joint_integrate", "joint_motors", "joint_power",
    "joint_scalars", "joint_step", "joint_transport", "joint_twist", "of_kind", "quaternion_error",
    "unit_axes",
]
