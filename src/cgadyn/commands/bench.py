"""``cgadyn bench``: time the algorithms against Pinocchio (``cgadyn.bench.measure``) and
print or write the tables (``cgadyn.bench.report``)."""

from __future__ import annotations

import argparse

from .common import (
    DEFAULT_ROBOT,
    ROBOT_HELP,
    add_base_options,
    check_output_dir,
    floating_base,
    positive_int,
    print_json,
)

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser(
        "bench", help="time the algorithms against Pinocchio (and pygafro)",
        description="Time single calls and batches of rnea, aba, crba, their derivatives and "
        "M⁻¹ in cgadyn and Pinocchio (and pygafro's Franka for the panda), alternating "
        "libraries, medians over repeats. Ratios are cgadyn / other: below 1 means cgadyn is "
        "faster.")
    p.add_argument("robot", nargs="?", default=DEFAULT_ROBOT, metavar="ROBOT",
                   help=f"{ROBOT_HELP} (default {DEFAULT_ROBOT})")
    p.add_argument("--batch", type=positive_int, nargs="+", default=[1, 64, 4096],
                   metavar="B", help="batch sizes (default 1 64 4096)")
    p.add_argument("--threads", type=positive_int, default=None,
                   help="threads for batches (default numba.get_num_threads())")
    p.add_argument("--repeats", type=positive_int, default=None,
                   help="timed repeats (default 11)")
    p.add_argument("--quick", action="store_true", help="short repeats, for a smoke run")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--output", metavar="DIR",
                   help="write benchmark.md, benchmark.json and benchmark.png into DIR")
    add_base_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..bench import benchmark, format_tables, write_report

    if args.output:  # before minutes of timing, not after
        check_output_dir(args.output, "the benchmark report")
    res = benchmark(args.robot, args.batch, args.threads, args.repeats, args.quick,
                    floating_base(args))
    if args.output:
        res["files"] = [str(p) for p in write_report(res, args.output)]
    if args.json:
        print_json(res)
    else:
        print(format_tables(res))
        if args.output:
            print("wrote " + ", ".join(res["files"]))
    return 0
