"""Robots by name: the project's own URDFs and the fixed-base arms and hands of
example-robot-data.

``load("panda")`` returns a cached, immutable :class:`~cgadyn.multibody.model.Model`;
``load`` also takes a URDF path or URDF text. ``robots()`` lists the names.
"""

from __future__ import annotations

import functools
import os
import site
import sys
from pathlib import Path

from cgadyn.multibody.model import Model
from cgadyn.multibody.urdf import load_urdf


def _own_robots_dir() -> Path:
    """The project's own URDFs: ``robots/`` at the top of a source checkout (an editable
    install), or ``cgadyn/robots/`` inside an installed wheel (``setup.py`` copies them)."""
    package = Path(__file__).resolve().parent.parent
    checkout = package.parent.parent / "robots"
    return checkout if (checkout / "cart_pole.urdf").is_file() else package / "robots"


OWN_ROBOTS_DIR = _own_robots_dir()

_ERD_SUBDIR = Path("cmeel.prefix") / "share" / "example-robot-data" / "robots"

# name -> path relative to example-robot-data's robots/ directory. Fixed-base arms, hands
# and benches only: mobile and legged robots (whose base should float) are left out.
EXAMPLE_ROBOT_DATA = {
    "panda": "panda_description/urdf/panda.urdf",
    "ur3": "ur_description/urdf/ur3_robot.urdf",
    "ur3_gripper": "ur_description/urdf/ur3_gripper.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "ur5_gripper": "ur_description/urdf/ur5_gripper.urdf",
    "ur10": "ur_description/urdf/ur10_robot.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",
    "z1": "z1_description/urdf/z1.urdf",
    "xarm7": "xarm_description/urdf/xarm7.urdf",
    "so100": "so_arm_description/urdf/so100.urdf",
    "so101": "so_arm_description/urdf/so101.urdf",
    "talos_left_arm": "talos_data/robots/talos_left_arm.urdf",
    "baxter": "baxter_description/urdf/baxter.urdf",
    "allegro_left_hand": "allegro_hand_description/urdf/allegro_left_hand.urdf",
    "allegro_right_hand": "allegro_hand_description/urdf/allegro_right_hand.urdf",
    "finger_edu": "finger_edu_description/robots/finger_edu.urdf",
    "double_pendulum": "double_pendulum_description/urdf/double_pendulum.urdf",
    "double_pendulum_continuous":
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
    "double_pendulum_simple": "double_pendulum_description/urdf/double_pendulum_simple.urdf",
    "asr_twodof": "asr_twodof_description/urdf/TwoDofs.urdf",
}

DEFAULT_ROBOT = "panda"


def _candidate_prefixes():
    seen = []
    try:
        seen.extend(site.getsitepackages())
    except AttributeError:  # some virtualenvs lack it
        pass
    try:
        seen.append(site.getusersitepackages())
    except AttributeError:
        pass
    seen.extend(p for p in sys.path if p)
    for prefix in (sys.prefix, sys.base_prefix):
        seen.append(prefix)
        seen.extend(str(p) for p in Path(prefix).glob("lib*/python*/site-packages"))
    return seen


@functools.lru_cache(maxsize=1)
def example_robot_data_dir() -> Path | None:
    """The ``robots/`` directory of example-robot-data, or ``None`` if it is not installed."""
    env = os.environ.get("EXAMPLE_ROBOT_DATA_DIR")
    if env and Path(env).is_dir():
        return Path(env)
    for base in _candidate_prefixes():
        for cand in (Path(base) / _ERD_SUBDIR, Path(base) / "share" / "example-robot-data"
                     / "robots"):
            if cand.is_dir():
                return cand
    return None


def _own_robots() -> dict:
    return {p.stem: p for p in sorted(OWN_ROBOTS_DIR.glob("*.urdf"))}


@functools.lru_cache(maxsize=1)
def _table() -> dict:
    table = {}
    erd = example_robot_data_dir()
    if erd is not None:
        for name, rel in EXAMPLE_ROBOT_DATA.items():
            path = erd / rel
            if path.is_file():
                table[name] = path
    table.update(_own_robots())
    return table


def robots() -> list[str]:
    """Names that :func:`load` accepts: the project's own robots and example-robot-data's
    fixed-base arms and hands (those installed)."""
    return sorted(_table())


def robot_path(name: str) -> Path:
    """The URDF file of the robot called ``name``."""
    table = _table()
    if name not in table:
        raise ValueError(f"unknown robot {name!r}; known robots: {', '.join(sorted(table))} "
                         f"(or give a URDF path or URDF text)")
    return table[name]


@functools.cache
def _load_named(name: str) -> Model:
    return load_urdf(robot_path(name), name=name)


def load(robot: str | os.PathLike = DEFAULT_ROBOT) -> Model:
    """Load a robot: a name from :func:`robots`, a URDF file path, or URDF XML text.

    Models loaded by name are cached (models are immutable).
    """
    if isinstance(robot, Model):
        return robot
    if isinstance(robot, str) and "<" not in robot:
        if robot in _table():
            return _load_named(robot)
        if not (os.sep in robot or robot.endswith(".urdf") or Path(robot).is_file()):
            robot_path(robot)  # raises the "unknown robot" ValueError
    return load_urdf(robot)
