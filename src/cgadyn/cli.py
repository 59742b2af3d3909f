"""The ``cgadyn`` command: ``validate``, ``info``, ``robots``, ``bench``, ``simulate-body``,
``ik``, ``simulate``.

    cgadyn validate [ROBOT | --all] [--samples N] [--seed S] [--tolerance T] [--json]
    cgadyn info [ROBOT] [--json]
    cgadyn robots [--json | --names]
    cgadyn bench [ROBOT] [--batch B ...] [--output DIR]
    cgadyn simulate-body [...]
    cgadyn ik ROBOT LINK --position X Y Z [--orientation W X Y Z] [--json]
    cgadyn simulate [ROBOT] [--seconds S] [--dt DT] [--controller C] [--plot F] [--html F]
    cgadyn --version

Each subcommand is a module of ``cgadyn.commands`` (``add_parser``, ``run``), registered
here in one loop; heavy modules (numba, Pinocchio, the kernels) are imported inside ``run``
so that ``cgadyn --help`` stays fast. Every error ends here, once: a user error (bad
arguments, an unknown robot, a missing file, a URDF that ``load`` refuses, a value the
library rejects) prints ``cgadyn: error: ...`` and exits with status 2; a validation that
ran and failed exits with 1; nothing prints a traceback (``CGADYN_DEBUG=1`` shows it).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import warnings
from collections.abc import Sequence

import cgadyn

from .commands.common import UsageError

__all__ = ["COMMANDS", "build_parser", "main"]

COMMANDS = ("cgadyn.commands.validate", "cgadyn.commands.info", "cgadyn.commands.robots",
            "cgadyn.commands.bench", "cgadyn.commands.simulate_body",
            "cgadyn.commands.ik", "cgadyn.commands.simulate")
"""The modules that register a subcommand, in the order ``--help`` lists them."""


class _Parser(argparse.ArgumentParser):
    """argparse, with its usage errors in the one form of every ``cgadyn`` error."""

    def error(self, message: str):
        self.print_usage(sys.stderr)
        self.exit(2, f"cgadyn: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    parser = _Parser(prog="cgadyn", description="Robot dynamics in conformal geometric "
                     "algebra G(4,1), checked against Pinocchio.")
    parser.add_argument("--version", action="version", version=f"cgadyn {cgadyn.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(name).add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``cgadyn`` command; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return exc.code if isinstance(exc.code, int) else 2
    if getattr(args, "func", None) is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        with warnings.catch_warnings():  # restores showwarning when the command returns
            warnings.showwarning = _show_warning
            status = int(args.func(args))
        _compiled_total()
        return status
    except BrokenPipeError:  # `cgadyn info panda | head`: stop quietly, like other tools
        _silence_stdout()
        return 141
    except KeyboardInterrupt:
        print("cgadyn: interrupted", file=sys.stderr)
        return 130
    except (UsageError, ValueError, OSError) as exc:
        return _error(exc, 2)
    except Exception as exc:  # a bug of ours: still one line, and a way to see more
        return _error(exc, 3, f"internal error ({type(exc).__name__}), please report: ")


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one ``cgadyn: warning: ...`` line on stderr, as errors are printed
    (a user of the command needs what it says, not the line of source that raised it)."""
    print(f"cgadyn: warning: {message}", file=sys.stderr if file is None else file)


def _compiled_total() -> None:
    """After a command that compiled (a first run), the total on stderr (``_progress``)."""
    progress = sys.modules.get("cgadyn._progress")
    if progress is None or not progress.ENABLED:
        return
    count, seconds = progress.compiled()
    if count:
        print(f"cgadyn: compiled {count} functions in {seconds:.0f} s on this first run; "
              f"later runs load them from numba's cache", file=sys.stderr)


def _error(exc: Exception, status: int, prefix: str = "") -> int:
    if os.environ.get("CGADYN_DEBUG"):
        import traceback

        traceback.print_exc()
    message = str(exc) or type(exc).__name__
    if isinstance(exc, FileNotFoundError) and "file not found" not in message:
        message = f"file not found: {exc.filename or message}"
    print(f"cgadyn: error: {prefix}{message}", file=sys.stderr)
    return status


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):
        pass


if __name__ == "__main__":
    sys.exit(main())
