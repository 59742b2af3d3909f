"""Multibody models: the immutable :class:`Model`, URDF loading and the robot registry.

``load("panda")`` loads a robot by name (see ``robots()``), a URDF path or URDF text;
``load_urdf(source)`` loads a URDF file or text.
"""

from cgadyn.multibody.joints import (
    FREE_FLYER,
    HELICAL,
    PLANAR,
    PRISMATIC,
    REVOLUTE,
    REVOLUTE_UNBOUNDED,
    SPHERICAL,
    TRANSLATION,
)
from cgadyn.multibody.model import Model, build_model, merge_inertias
from cgadyn.multibody.registry import load, robot_path, robots
from cgadyn.multibody.urdf import load_urdf

__all__ = [
    "FREE_FLYER",
    "HELICAL",
    "Model",
    "PLANAR",
    "PRISMATIC",
    "REVOLUTE",
    "REVOLUTE_UNBOUNDED",
    "SPHERICAL",
    "TRANSLATION",
    "build_model",
    "load",
    "load_urdf",
    "merge_inertias",
    "robot_path",
    "robots",
]
