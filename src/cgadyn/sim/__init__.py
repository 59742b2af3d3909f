"""Simulation: rollouts of a robot's motion, one compiled call parallel over rollouts.

``simulate`` (``simulate.py``) checks the arguments and calls the compiled loop of
``rollout.py`` (the closed-loop dynamics, the integrators on the configuration manifold);
``controllers.py`` holds the feedback laws evaluated inside it, ``trajectory.py`` the result.
"""

from .controllers import PD, GravityCompensation
from .simulate import INTEGRATORS, SimulationDiverged, simulate
from .trajectory import Trajectory

__all__ = ["INTEGRATORS", "PD", "GravityCompensation", "SimulationDiverged", "Trajectory",
           "simulate"]
