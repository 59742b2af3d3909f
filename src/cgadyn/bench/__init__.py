"""Timing cgadyn against Pinocchio: ``measure`` runs the cases, ``report`` writes tables and
plots; ``cgadyn bench`` (``cgadyn.commands.bench``) is the command."""

from .measure import OPS, TARGETS, benchmark, machine_info
from .report import format_tables, plot, write_report

__all__ = ["OPS", "TARGETS", "benchmark", "format_tables", "machine_info", "plot",
           "write_report"]
