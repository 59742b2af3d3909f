"""cgadyn: robot dynamics in conformal geometric algebra G(4,1), checked against Pinocchio.

    >>> import cgadyn
    >>> model = cgadyn.load("panda")
    >>> tau = cgadyn.rnea(model, q, v, a)

The algorithms (``rnea``, ``aba``, ``crba``, ``jacobian``, ...) are imported on first use,
so that ``import cgadyn`` stays fast: numba and the compiled kernels load only when needed.
"""

from __future__ import annotations

import importlib

from . import _arrays

__version__ = "0.1.0"

_LAZY = {
    "load": "cgadyn.multibody",
    "load_urdf": "cgadyn.multibody",
    "robots": "cgadyn.multibody",
    "Model": "cgadyn.multibody",
    "from_pinocchio": "cgadyn.multibody.pinocchio_model",
    "from_mujoco": "cgadyn.multibody.mujoco_model",
    "from_mujoco_state": "cgadyn.multibody.mujoco_model",
    "to_mujoco_state": "cgadyn.multibody.mujoco_model",
    "from_mujoco_acceleration": "cgadyn.multibody.mujoco_model",
    "to_mujoco_acceleration": "cgadyn.multibody.mujoco_model",
    "passive_torques": "cgadyn.algorithms.passive",
    "actuator_torques": "cgadyn.algorithms.actuators",
    "activations": "cgadyn.algorithms.actuators",
    "rnea": "cgadyn.algorithms",
    "aba": "cgadyn.algorithms",
    "crba": "cgadyn.algorithms",
    "gravity_torques": "cgadyn.algorithms",
    "nonlinear_effects": "cgadyn.algorithms",
    "forward_kinematics": "cgadyn.algorithms",
    "link_placements": "cgadyn.algorithms",
    "jacobian": "cgadyn.algorithms",
    "energy": "cgadyn.algorithms",
    "kinetic_energy": "cgadyn.algorithms",
    "potential_energy": "cgadyn.algorithms",
    "rnea_derivatives": "cgadyn.algorithms",
    "aba_derivatives": "cgadyn.algorithms",
    "minverse": "cgadyn.algorithms",
    "integrate": "cgadyn.algorithms",
    "difference": "cgadyn.algorithms",
    "interpolate": "cgadyn.algorithms",
    "neutral": "cgadyn.algorithms",
    "random_configuration": "cgadyn.algorithms",
    "normalize": "cgadyn.algorithms",
    "total_mass": "cgadyn.algorithms",
    "center_of_mass": "cgadyn.algorithms",
    "com_jacobian": "cgadyn.algorithms",
    "centroidal_momentum_matrix": "cgadyn.algorithms",
    "centroidal_momentum": "cgadyn.algorithms",
    "twist_from_motion": "cgadyn.cga.conventions",
    "motion_from_twist": "cgadyn.cga.conventions",
    "wrench_from_force": "cgadyn.cga.conventions",
    "force_from_wrench": "cgadyn.cga.conventions",
    "motor_from_matrix": "cgadyn.cga.conventions",
    "matrix_from_motor": "cgadyn.cga.conventions",
    "inverse_kinematics": "cgadyn.tasks",
    "IKResult": "cgadyn.tasks",
    "Task": "cgadyn.tasks",
    "solve_tasks": "cgadyn.tasks",
    "evaluate_tasks": "cgadyn.tasks",
    "motor_jacobian": "cgadyn.tasks",
    "object_jacobian": "cgadyn.tasks",
    "jacobian_time_variation": "cgadyn.tasks",
    "CooperativeTask": "cgadyn.tasks",
    "cooperative_space": "cgadyn.tasks",
    "Constraint": "cgadyn.constraints",
    "SolveInfo": "cgadyn.constraints",
    "constraint_jacobian": "cgadyn.constraints",
    "constraint_drift": "cgadyn.constraints",
    "delassus": "cgadyn.constraints",
    "constrained_dynamics": "cgadyn.constraints",
    "impulse_dynamics": "cgadyn.constraints",
    "contact_inverse_dynamics": "cgadyn.constraints",
    "mujoco_constraints": "cgadyn.constraints",
    "Sphere": "cgadyn.contact",
    "Capsule": "cgadyn.contact",
    "Box": "cgadyn.contact",
    "Cylinder": "cgadyn.contact",
    "Ellipsoid": "cgadyn.contact",
    "Plane": "cgadyn.contact",
    "ConvexMesh": "cgadyn.contact",
    "MeshSimplified": "cgadyn.contact",
    "shape_distance": "cgadyn.contact",
    "Collision": "cgadyn.contact",
    "CollisionModel": "cgadyn.contact",
    "collision_model": "cgadyn.contact",
    "collision_poses": "cgadyn.contact",
    "collision_distances": "cgadyn.contact",
    "World": "cgadyn.contact",
    "Body": "cgadyn.contact",
    "Obstacle": "cgadyn.contact",
    "static_world": "cgadyn.contact",
    "with_bodies": "cgadyn.contact",
    "Contacts": "cgadyn.contact",
    "ground_contacts": "cgadyn.contact",
    "contact_step": "cgadyn.contact",
    "ContactStep": "cgadyn.contact",
    "ContactSettings": "cgadyn.contact",
    "contact_problem": "cgadyn.contact",
    "solve_contacts": "cgadyn.contact",
    "ContactSolveInfo": "cgadyn.contact",
    "ContactCriteria": "cgadyn.contact",
    "step_criteria": "cgadyn.contact",
    "simulate": "cgadyn.sim",
    "Trajectory": "cgadyn.sim",
    "PD": "cgadyn.sim",
    "GravityCompensation": "cgadyn.sim",
    "SimulationDiverged": "cgadyn.sim",
}

__all__ = sorted([*_LAZY, "NativeExtensionMissing"])

# dask arrays of samples run chunk by chunk, each chunk one compiled batch call; declared
# here, at the top of the layers, so that the call layer below never imports the module.
_arrays.serve("dask", "cgadyn.distributed")


class NativeExtensionMissing(RuntimeWarning):
    """Issued once, when the compiled algorithms are first imported, where the C extension
    ``cgadyn._native`` was not built (no C compiler at install time; ``setup.py`` makes it
    optional): one-sample calls then take numba's dispatcher, several times slower. Defined here,
    outside the modules that warn, so that it can be filtered before they load."""


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'cgadyn' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
