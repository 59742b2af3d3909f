"""What the subcommands share: argument types that refuse bad values with a clear message,
the robot argument (``registry.resolve``'s rule: a name, or a URDF or MJCF file of any
extension), output paths (``--plot``, ``--html``, ``bench --output``) checked for a
writable place before any work starts (``_paths``, which the library's own plots use too),
and output as text or standard JSON."""

from __future__ import annotations

import argparse
import math
import sys

from .._json import dumps
from .._paths import UsageError, check_output_dir, check_output_file, check_plot_path

DEFAULT_ROBOT = "panda"

ROBOT_HELP = "robot name (see `cgadyn robots`), or a URDF or MJCF file"
"""What the ROBOT argument of every subcommand accepts."""

__all__ = ["DEFAULT_ROBOT", "ROBOT_HELP", "UsageError", "add_base_options", "check_output_dir",
           "check_output_file", "check_plot_path", "floating_base", "non_negative_int",
           "positive_float", "positive_int", "print_json"]


def positive_int(text: str) -> int:
    """An integer >= 1."""
    value = _parse(int, text, "an integer >= 1")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return value


def non_negative_int(text: str) -> int:
    """An integer >= 0 (a random seed)."""
    value = _parse(int, text, "an integer >= 0")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}")
    return value


def positive_float(text: str) -> float:
    """A positive finite number."""
    value = _parse(float, text, "a positive finite number")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text!r}")
    return value


def _parse(kind, text: str, expected: str):
    try:
        return kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be {expected}, got {text!r}") from None


def add_base_options(p: argparse.ArgumentParser) -> None:
    """``--floating-base`` / ``--fixed-base``: override the robot's natural base."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("--floating-base", dest="base", action="store_const", const=True,
                   help="give the robot a free-flyer root (default: its natural base)")
    g.add_argument("--fixed-base", dest="base", action="store_const", const=False,
                   help="fix the robot's root link to the world")
    p.set_defaults(base=None)


def floating_base(args: argparse.Namespace) -> bool | None:
    """The base the user asked for (None: the robot's natural base)."""
    return getattr(args, "base", None)


def print_json(obj) -> None:
    """Standard JSON on stdout: non-finite numbers as ``null``."""
    print(dumps(obj, indent=2))


def warn(message: str) -> None:
    """A note on stderr that does not stop the command."""
    print(f"cgadyn: {message}", file=sys.stderr)
