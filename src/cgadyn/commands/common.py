"""What the subcommands share: argument types that refuse bad values with a clear message,
the robot argument (``registry.resolve``'s rule: a name, or a URDF or MJCF file of any
extension), output paths (``--plot``, ``--html``, ``bench --output``) checked for a
writable place before any work starts, and output as text or standard JSON."""

from __future__ import annotations

import argparse
import errno
import math
import sys
import tempfile
from pathlib import Path

from .._json import dumps

DEFAULT_ROBOT = "panda"

ROBOT_HELP = "robot name (see `cgadyn robots`), or a URDF or MJCF file"
"""What the ROBOT argument of every subcommand accepts."""

__all__ = ["DEFAULT_ROBOT", "ROBOT_HELP", "UsageError", "add_base_options", "check_output_dir",
           "check_output_file", "check_plot_path", "floating_base", "non_negative_int",
           "positive_float", "positive_int", "print_json"]


class UsageError(Exception):
    """A user error: ``cgadyn`` prints ``cgadyn: error: <message>`` and exits with status 2."""


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


def _writable(directory: Path, subject: str) -> None:
    """A ``UsageError`` ("cannot write ``subject``: ...") unless a file can be created in
    ``directory``, tried for real: as root, or on /proc or a read-only mount, the
    permission bits do not tell."""
    try:
        with tempfile.NamedTemporaryFile(dir=directory, prefix=".cgadyn-check-"):
            pass
    except OSError as exc:
        reason = f" ({exc.strerror})" if exc.strerror and exc.errno != errno.ENOENT else ""
        raise UsageError(f"cannot write {subject}: directory {str(directory)!r} is not "
                         f"writable{reason}") from None


def check_output_file(path: str, what: str) -> Path:
    """``path`` if a file can be written there (its directory exists and is writable, and
    it is not a directory or a read-only file), checked before any work starts; else a
    ``UsageError`` naming the path. ``what``: "the plot", "the animation", ..."""
    p = Path(path)
    if not p.parent.is_dir():
        raise UsageError(f"cannot write {what} {path!r}: directory {str(p.parent)!r} does "
                         f"not exist")
    if p.is_dir():
        raise UsageError(f"cannot write {what} {path!r}: it is a directory")
    _writable(p.parent, f"{what} {path!r}")
    if p.exists():
        try:
            with open(p, "ab"):
                pass
        except OSError as exc:
            raise UsageError(f"cannot write {what} {path!r}: {exc.strerror}") from None
    return p


def check_output_dir(path: str, what: str) -> Path:
    """``path`` if it is, or can be made, a writable directory: an existing directory, or
    a new one under the nearest existing ancestor, which must be a writable directory."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise UsageError(f"cannot write {what} into {path!r}: it exists and is not a "
                         f"directory")
    ancestor = p
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise UsageError(f"cannot write {what} into {path!r}: {str(ancestor)!r} is not a "
                         f"directory")
    _writable(ancestor, f"{what} into {path!r}")
    return p


def check_plot_path(path: str | None) -> Path | None:
    """``path`` if matplotlib can write a figure there: its directory exists and is
    writable and its extension is a format matplotlib writes; else a ``UsageError``
    saying which."""
    if path is None:
        return None
    p = check_output_file(path, "the plot")
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    ext = p.suffix.lstrip(".").lower()
    if ext not in formats:
        raise UsageError(f"cannot write the plot {path!r}: extension {p.suffix or '(none)'!r} "
                         f"is not a format matplotlib writes; expected one of "
                         f"{', '.join('.' + f for f in sorted(formats))}")
    return p


def print_json(obj) -> None:
    """Standard JSON on stdout: non-finite numbers as ``null``."""
    print(dumps(obj, indent=2))


def warn(message: str) -> None:
    """A note on stderr that does not stop the command."""
    print(f"cgadyn: {message}", file=sys.stderr)
