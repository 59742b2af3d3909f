"""Output paths checked before any work starts, and the user error that refuses one.

A figure, an animation or a directory of results is written after minutes of work; a path
where it cannot be written is refused first, with the reason, by the command line
(``commands``) and by the library's own plots (``sim.plot``, the ``simulate-body`` command
of ``pga``) alike.
"""

from __future__ import annotations

import errno
import tempfile
from pathlib import Path

__all__ = ["UsageError", "check_output_dir", "check_output_file", "check_plot_path"]


class UsageError(Exception):
    """A user error (a bad argument, a path where an output cannot be written): the
    ``cgadyn`` command prints ``cgadyn: error: <message>`` and exits with status 2."""


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
