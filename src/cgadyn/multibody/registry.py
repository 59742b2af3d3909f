"""Robots by name: the project's own URDFs and MJCF files, Gymnasium's and dm_control's
MuJoCo models (``gymnasium:ant``), and the robots of example-robot-data.

``load("panda")`` returns a cached, immutable :class:`~cgadyn.multibody.model.Model`;
``load`` also takes a URDF path or URDF text. ``robots()`` lists the names.
"""

from __future__ import annotations

import functools
import os
import site
import sys
from pathlib import Path

from cgadyn.multibody import mujoco_model
from cgadyn.multibody.mjcf import file_is_mjcf, is_mjcf, load_mjcf
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

FIXED, FREE = "fixed", "free"
"""A robot's natural base: fixed to the world, or a free-flyer root."""

# name -> (path under example-robot-data's robots/ directory, natural base). The names are
# those of example-robot-data's own loader (``example_robot_data.load(name)``) where it has
# one; arms, hands and benches stand on a fixed base, legged, humanoid and flying robots
# float, as that loader builds them.
EXAMPLE_ROBOT_DATA = {
    "a1": ("a1_description/urdf/a1.urdf", FREE),
    "alex": ("alex_description/urdf/alex_nub_hands.urdf", FREE),
    "alex_psyonic_hands": ("alex_description/urdf/alex_psyonic_hands.urdf", FREE),
    "alex_sake_hands": ("alex_description/urdf/alex_sake_hands.urdf", FREE),
    "alexander": ("alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf", FREE),
    "allegro_left_hand": ("allegro_hand_description/urdf/allegro_left_hand.urdf", FIXED),
    "allegro_right_hand": ("allegro_hand_description/urdf/allegro_right_hand.urdf", FIXED),
    "anymal": ("anymal_b_simple_description/robots/anymal.urdf", FREE),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", FREE),
    "anymal_kinova": ("anymal_b_simple_description/robots/anymal-kinova.urdf", FREE),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", FIXED),
    "b1": ("b1_description/urdf/b1.urdf", FREE),
    "b1_z1": ("b1_description/urdf/b1-z1.urdf", FREE),
    "baxter": ("baxter_description/urdf/baxter.urdf", FIXED),
    "bolt": ("bolt_description/robots/bolt.urdf", FREE),
    "borinot": ("borinot_description/urdf/borinot_flying_arm_2.urdf", FREE),
    "centauro": ("centauro_description/urdf/centauro.urdf", FREE),
    "double_pendulum": ("double_pendulum_description/urdf/double_pendulum.urdf", FIXED),
    "double_pendulum_continuous":
        ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", FIXED),
    "double_pendulum_simple":
        ("double_pendulum_description/urdf/double_pendulum_simple.urdf", FIXED),
    "finger_edu": ("finger_edu_description/robots/finger_edu.urdf", FIXED),
    "g1": ("g1_description/urdf/g1_29dof_rev_1_0.urdf", FREE),
    "g1_with_hands": ("g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf", FREE),
    "go1": ("go1_description/urdf/go1.urdf", FREE),
    "go2": ("go2_description/urdf/go2.urdf", FREE),
    "hector": ("hector_description/robots/quadrotor_base.urdf", FREE),
    "hextilt": ("hextilt_description/urdf/hextilt_flying_arm_5.urdf", FREE),
    "human": ("human_description/robots/human.urdf", FREE),
    "hyq": ("hyq_description/robots/hyq_no_sensors.urdf", FREE),
    "icub": ("icub_description/robots/icub.urdf", FREE),
    "icub_reduced": ("icub_description/robots/icub_reduced.urdf", FREE),
    "iris": ("iris_description/robots/iris_simple.urdf", FREE),
    "iris_full": ("iris_description/robots/iris.urdf", FREE),
    "kinova": ("kinova_description/robots/kinova.urdf", FIXED),
    "laikago": ("laikago_description/urdf/laikago.urdf", FREE),
    "panda": ("panda_description/urdf/panda.urdf", FIXED),
    "panda_collision": ("panda_description/urdf/panda_collision.urdf", FIXED),
    "pr2": ("pr2_description/urdf/pr2.urdf", FIXED),
    "quadruped": ("quadruped_description/urdf/quadruped.urdf", FREE),
    "romeo": ("romeo_description/urdf/romeo.urdf", FREE),
    "romeo_laas_small": ("romeo_description/urdf/romeo_laas_small.urdf", FREE),
    "romeo_small": ("romeo_description/urdf/romeo_small.urdf", FREE),
    "simple_humanoid": ("simple_humanoid_description/urdf/simple_humanoid.urdf", FREE),
    "simple_humanoid_classical":
        ("simple_humanoid_description/urdf/simple_humanoid_classical.urdf", FREE),
    "so100": ("so_arm_description/urdf/so100.urdf", FIXED),
    "so101": ("so_arm_description/urdf/so101.urdf", FIXED),
    "solo": ("solo_description/robots/solo.urdf", FREE),
    "solo12": ("solo_description/robots/solo12.urdf", FREE),
    "talos": ("talos_data/robots/talos_reduced.urdf", FREE),
    "talos_box": ("talos_data/robots/talos_reduced_box.urdf", FREE),
    "talos_corrected": ("talos_data/robots/talos_reduced_corrected.urdf", FREE),
    "talos_full": ("talos_data/robots/talos_full_v2.urdf", FREE),
    "talos_full_box": ("talos_data/robots/talos_full_v2_box.urdf", FREE),
    "talos_left_arm": ("talos_data/robots/talos_left_arm.urdf", FIXED),
    "tiago": ("tiago_description/robots/tiago.urdf", FIXED),
    "tiago_dual": ("tiago_description/robots/tiago_dual.urdf", FIXED),
    "tiago_no_hand": ("tiago_description/robots/tiago_no_hand.urdf", FIXED),
    "tiago_pro": ("tiago_pro_description/robots/tiago_pro.urdf", FIXED),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", FIXED),
    "ur10_limited": ("ur_description/urdf/ur10_joint_limited_robot.urdf", FIXED),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", FIXED),
    "ur3_gripper": ("ur_description/urdf/ur3_gripper.urdf", FIXED),
    "ur3_limited": ("ur_description/urdf/ur3_joint_limited_robot.urdf", FIXED),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", FIXED),
    "ur5_gripper": ("ur_description/urdf/ur5_gripper.urdf", FIXED),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", FIXED),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", FIXED),
    "z1": ("z1_description/urdf/z1.urdf", FIXED),
}
ALIASES = {"talos_reduced": "talos", "solo8": "solo"}
"""Other names of the same robots."""

REFUSED = {
    "cassie": ("cassie_description/robots/cassie.sdf",
               "SDF only, with closed kinematic loops (the legs' four-bar linkages); cgadyn "
               "models URDF kinematic trees"),
    "romeo_laas_small": ("romeo_description/urdf/romeo_laas_small.urdf",
                         "link 'body' has an inertia that is not positive semi-definite; "
                         "loads with check_inertia=False, as Pinocchio does"),
}
"""Robots of example-robot-data that do not load by default: name -> (file, why)."""

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


MUJOCO_SUITES = {"gymnasium": "Gymnasium's MuJoCo environments",
                 "dm_control": "dm_control's suite"}
"""The MJCF model collections shipped under ``robots/mujoco/<suite>/`` (copies, with their
licence), named ``<suite>:<model>`` (``gymnasium:ant``, ``dm_control:cheetah``)."""


def _own_robots() -> dict:
    """name -> file of the project's own robots: its URDFs and MJCF files (``*.xml``), and
    the MJCF models of ``MUJOCO_SUITES`` as ``<suite>:<model>``."""
    files = [*OWN_ROBOTS_DIR.glob("*.urdf"), *OWN_ROBOTS_DIR.glob("*.xml")]
    table = {p.stem: p for p in sorted(files)}
    for suite in MUJOCO_SUITES:
        table.update({f"{suite}:{p.stem}": p
                      for p in sorted((OWN_ROBOTS_DIR / "mujoco" / suite).glob("*.xml"))})
    return table


@functools.lru_cache(maxsize=1)
def _table() -> dict:
    """name -> (URDF path, natural base) of every installed robot."""
    table = {}
    erd = example_robot_data_dir()
    if erd is not None:
        for name, (rel, base) in EXAMPLE_ROBOT_DATA.items():
            if (erd / rel).is_file():
                table[name] = (erd / rel, base)
    table.update({name: (path, FIXED) for name, path in _own_robots().items()})
    return table


def robots() -> list[str]:
    """Names that :func:`load` accepts: the project's own robots and every robot of
    example-robot-data (those installed), whatever their base (``natural_base``)."""
    return sorted(_table())


def refused() -> dict[str, str]:
    """name -> why, for the installed robots of example-robot-data that cgadyn refuses by
    default (``REFUSED``); those that load with an option stay in :func:`robots`."""
    erd = example_robot_data_dir()
    if erd is None:
        return {}
    return {name: why for name, (rel, why) in REFUSED.items() if (erd / rel).is_file()}


def source(name: str) -> str:
    """Where robot ``name`` comes from: ``"cgadyn"`` (the project's robots/), a suite of
    ``MUJOCO_SUITES`` (``"gymnasium"``, ``"dm_control"``: their MJCF files, shipped in
    robots/mujoco/) or ``"example-robot-data"``."""
    suite = name.split(":", 1)[0]
    if suite in MUJOCO_SUITES and name in _own_robots():
        return suite
    return "cgadyn" if name in _own_robots() else "example-robot-data"


def _known(name: str) -> str:
    name = ALIASES.get(name, name)
    if name not in _table():
        raise ValueError(f"unknown robot {name!r}; known robots: {', '.join(robots())} "
                         f"(or give a URDF file path or URDF text)")
    return name


def robot_path(name: str) -> Path:
    """The URDF file of the robot called ``name``."""
    return _table()[_known(name)][0]


def natural_base(name: str) -> str:
    """``FIXED`` or ``FREE``: how example-robot-data's loader builds robot ``name``."""
    return _table()[_known(name)][1]


def resolve(robot) -> tuple[str, object, str | None]:
    """What ``robot`` names, by one rule for ``load`` and every command:
    ``("name", name, base)`` for a registered robot, ``("path", Path, None)`` for an existing
    file (any extension), ``("text", str, None)`` for URDF text, and ``("mjcf", Path or str,
    None)`` for an MJCF file or MJCF text, decided by content: an XML document whose root
    element is ``<mujoco>`` (``mjcf.is_mjcf``); a registered name whose file is MJCF
    (``robots/slide_arm.xml``) resolves to ``("mjcf", its path, None)``. A path that does
    not exist raises ``FileNotFoundError`` ("file not found"); anything else ``ValueError``."""
    kind, value, base = _resolve(robot)
    if kind == "name" and file_is_mjcf(robot_path(value)):
        return "mjcf", robot_path(value), None
    if kind == "path" and file_is_mjcf(value) or kind == "text" and is_mjcf(value.encode()):
        return "mjcf", value, None
    return kind, value, base


def _resolve(robot) -> tuple[str, object, str | None]:
    if isinstance(robot, os.PathLike):
        path = Path(robot)
        if not path.is_file():
            raise FileNotFoundError(f"file not found: {str(path)!r}")
        return "path", path, None
    if not isinstance(robot, str):
        raise ValueError(f"a robot is a name, a file path or URDF text, got "
                         f"{type(robot).__name__}")
    if "<" in robot:
        return "text", robot, None
    if ALIASES.get(robot, robot) in _table():
        name = _known(robot)
        return "name", name, natural_base(name)
    path = Path(robot)
    if path.is_file():
        return "path", path, None
    if os.sep in robot or "/" in robot or path.suffix:
        raise FileNotFoundError(f"file not found: {robot!r} (no such file; expected a robot "
                                f"name, a URDF file path or URDF text)")
    _known(robot)  # raises the "unknown robot" ValueError
    raise AssertionError


@functools.cache
def _load_named(name: str, floating: bool, check_inertia: bool) -> Model:
    return load_urdf(robot_path(name), name=name, floating_base=floating,
                     check_inertia=check_inertia)


def _base_option(floating_base) -> bool | None:
    """``floating_base`` as ``True``, ``False`` or ``None``: a ``bool`` (numpy's too) or
    ``None``; anything else (``"False"``, ``0``, ...) is refused, not taken for its
    truth value."""
    import numpy as np

    if floating_base is None or isinstance(floating_base, bool | np.bool_):
        return None if floating_base is None else bool(floating_base)
    raise ValueError(f"floating_base must be True, False or None (the robot's natural "
                     f"base), got {floating_base!r} ({type(floating_base).__name__})")


def load(robot: str | os.PathLike = DEFAULT_ROBOT, floating_base: bool | None = None,
         check_inertia: bool = True) -> Model:
    """Load a robot: a name from :func:`robots` (the project's MJCF ``slide_arm`` among
    them), a URDF file path, or URDF XML text; or an MJCF file or text (root element
    ``<mujoco>``), compiled by MuJoCo and converted by ``from_mujoco`` when ``mujoco`` is
    installed, else parsed by Pinocchio and converted by ``from_pinocchio``
    (``multibody.mjcf``: what that parser reads differently).

    ``floating_base`` (``True``, ``False`` or ``None``; anything else is refused):
    ``None`` gives the robot its natural base (a free-flyer root
    ``root_joint`` for example-robot-data's legged, humanoid and flying robots; fixed for
    arms, hands, and any URDF path or text; for MJCF, the file's own: a free joint on the
    root body floats it); ``True`` or ``False`` overrides it.
    ``check_inertia=False`` accepts inertias that are not physically valid, as Pinocchio
    does. Models loaded by name are cached (models are immutable).
    """
    floating_base = _base_option(floating_base)
    if isinstance(robot, Model):
        return robot
    kind, value, base = resolve(robot)
    if kind == "name":
        floating = base == FREE if floating_base is None else bool(floating_base)
        return _load_named(value, floating, bool(check_inertia))
    if kind == "mjcf":
        name = robot if isinstance(robot, str) and robot in _table() else None
        if mujoco_model.available():  # MuJoCo's compiler: the reference for MJCF
            return mujoco_model.load_mujoco(value, name=name, floating_base=floating_base,
                                            check_inertia=check_inertia)
        return load_mjcf(value, floating_base=floating_base, check_inertia=check_inertia)
    return load_urdf(value, floating_base=bool(floating_base), check_inertia=check_inertia)
