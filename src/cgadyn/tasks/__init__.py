"""Geometric tasks in CGA: Jacobians of motors and carried objects, task residuals, inverse
kinematics and the cooperative dual-arm task space (gafro's manipulation toolbox).

- ``jacobians``: ``∂M/∂q`` of a link motor, ``X(q) = M X ~M`` and ``∂X/∂q`` of any carried
  object, ``J̇`` (Pinocchio's ``getFrameJacobianTimeVariation``);
- ``task``: ``Task`` (a carried object onto a target object, weighted) and ``evaluate``;
- ``ik``: ``inverse_kinematics`` (Levenberg-Marquardt in compiled code, batches in parallel);
- ``dual_arm``: absolute and relative motors of two end-effectors and their Jacobians, and
  tasks on them (compiled, stacked with the others).
"""

from .dual_arm import CooperativeTask, cooperative_space
from .ik import IKResult, inverse_kinematics, solve
from .jacobians import jacobian_time_variation, motor_jacobian, object_jacobian
from .task import Task, evaluate

solve_tasks = solve
evaluate_tasks = evaluate

__all__ = [
    "CooperativeTask", "cooperative_space",
    "IKResult", "Task", "evaluate", "inverse_kinematics", "jacobian_time_variation",
    "motor_jacobian", "object_jacobian", "solve", "solve_tasks", "evaluate_tasks",
]
