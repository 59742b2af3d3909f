"""The ``cgadyn`` command: ``validate``, ``info``, ``robots``, ``simulate-body`` (and ``bench``).

    cgadyn validate [ROBOT] [--samples N] [--seed S] [--tolerance T] [--json] [--all]
    cgadyn info [ROBOT] [--json]
    cgadyn robots
    cgadyn simulate-body [...]
    cgadyn --version

Heavy modules (numba, Pinocchio, the kernels) are imported inside the handlers, so that
``cgadyn --help`` stays fast. Exit status: 0 success, 1 validation failed, 2 bad usage.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import math
import sys
from collections.abc import Sequence

import cgadyn

DEFAULT_ROBOT = "panda"

__all__ = ["build_parser", "main"]


# --- parser ------------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    parser = argparse.ArgumentParser(
        prog="cgadyn",
        description="Robot dynamics in conformal geometric algebra G(4,1), checked against "
        "Pinocchio.")
    parser.add_argument("--version", action="version", version=f"cgadyn {cgadyn.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    _add_validate(sub)
    _add_info(sub)
    _add_robots(sub)
    _add_simulate_body(sub)
    _add_bench(sub)
    return parser


def _positive_int(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def _add_validate(sub) -> None:
    p = sub.add_parser(
        "validate", help="compare every algorithm with Pinocchio (the paper's Table 1)",
        description="Run rnea, aba, crba, gravity torques, Jacobians (world and local, at the "
        "leaf links) and forward kinematics (all links) on random states in cgadyn (batched) "
        "and Pinocchio, and print the errors. q is uniform within the joint limits ([-pi, pi] "
        "for continuous joints); v, a, tau are standard normal. The paper averaged over 1000 "
        "samples. Exit status 1 if a relative error exceeds the tolerance.")
    p.add_argument("robot", nargs="?", metavar="ROBOT",
                   help=f"robot name (see `cgadyn robots`) or URDF path; default {DEFAULT_ROBOT}")
    p.add_argument("--samples", type=_positive_int, default=100,
                   help="random states per robot (default 100; the paper used 1000)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--tolerance", type=float, default=1e-10,
                   help="largest relative error that passes (default 1e-10)")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--all", action="store_true", help="validate every robot of `cgadyn robots`")
    p.set_defaults(func=_run_validate)


def _add_info(sub) -> None:
    p = sub.add_parser("info", help="joints, limits, links and mass of a robot")
    p.add_argument("robot", nargs="?", default=DEFAULT_ROBOT, metavar="ROBOT",
                   help=f"robot name or URDF path (default {DEFAULT_ROBOT})")
    p.add_argument("--json", action="store_true", help="print as JSON")
    p.set_defaults(func=_run_info)


def _add_robots(sub) -> None:
    p = sub.add_parser("robots", help="list the robot names that load by name")
    p.set_defaults(func=_run_robots)


def _add_simulate_body(sub) -> None:
    from cgadyn.pga import cli as pga_cli

    pga_cli.add_parser(sub)


def _add_bench(sub) -> None:
    """``bench`` lives in ``cgadyn.bench`` (``add_parser``, ``run``); registered if present."""
    # --- bench: src/cgadyn/bench.py, written separately --------------------------------
    if importlib.util.find_spec("cgadyn.bench") is None:
        return
    try:
        bench = importlib.import_module("cgadyn.bench")
    except ImportError:
        return
    bench.add_parser(sub)


# --- helpers -----------------------------------------------------------------------------


def _known_robots() -> list[str]:
    from cgadyn.multibody import robots

    return robots()


def _resolve(robot: str) -> str | None:
    """``robot`` if it names a known robot or a URDF file; else print why and return None."""
    from pathlib import Path

    known = _known_robots()
    if robot in known or (Path(robot).is_file() and robot.endswith(".urdf")):
        return robot
    print(f"cgadyn: error: unknown robot {robot!r}; known robots: {', '.join(known)} "
          f"(or give a .urdf path)", file=sys.stderr)
    return None


def _fmt(x: float) -> str:
    return "nan" if math.isnan(x) else f"{x:.2e}"


def _progress(done: int, total: int, label: str, width: int = 24) -> None:
    """A one-line progress bar on stderr: ``[####    ] 5/24 ur5``."""
    filled = round(width * done / total) if total else width
    bar = "#" * filled + " " * (width - filled)
    end = "\n" if done == total else ""
    print(f"\r[{bar}] {done}/{total} {label:<30}", end=end, file=sys.stderr, flush=True)


# --- validate ----------------------------------------------------------------------------


def _run_validate(args: argparse.Namespace) -> int:
    if args.all and args.robot:
        print("cgadyn validate: error: give a ROBOT or --all, not both", file=sys.stderr)
        return 2
    if args.all:
        return _validate_all(args)
    robot = _resolve(args.robot or DEFAULT_ROBOT)
    if robot is None:
        return 2
    from cgadyn.validate import validate_robot

    result = validate_robot(robot, args.samples, args.seed, args.tolerance)
    print(json.dumps(result, indent=2) if args.json else format_result(result))
    return 0 if result["pass"] else 1


def _header(result: dict) -> list[str]:
    v = result["versions"]
    return [
        f"cgadyn validate: {result['robot']}, {result['dof']} dof, {result['samples']} samples, "
        f"seed {result['seed']} | cgadyn {v['cgadyn']}, pinocchio {v['pinocchio']}, "
        f"numpy {v['numpy']}, numba {v['numba']}",
        "cgadyn (batched) against Pinocchio; q uniform in the joint limits, v, a, tau ~ N(0, 1) "
        "(the paper's Table 1: 1000 samples)",
        f"{result['relative_error']}; tolerance {result['tolerance']:.0e}",
        f"Jacobians at: {', '.join(result['jacobian_links'])}",
    ]


def format_result(result: dict) -> str:
    """The Table-1-style text table of one :func:`~cgadyn.validate.validate_robot` result."""
    from cgadyn.validate import ALGORITHMS

    lines = _header(result) + [""]
    lines.append(f"{'algorithm':<32}{'mean norm':>12}{'max |diff|':>12}{'max rel':>12}  result")
    lines.append("-" * 76)
    for key, label in ALGORITHMS.items():
        row = result["algorithms"][key]
        lines.append(f"{label:<32}{_fmt(row['mean_norm']):>12}{_fmt(row['max_abs']):>12}"
                     f"{_fmt(row['max_rel']):>12}  {'pass' if row['pass'] else 'FAIL'}")
        if "error" in row:
            lines.append(f"    error: {row['error']}")
    lines.append("-" * 76)
    verdict = "PASS" if result["pass"] else "FAIL"
    lines.append(f"{verdict}: worst relative error {_fmt(worst(result))} "
                 f"(tolerance {result['tolerance']:.0e}), {result['seconds']:.1f} s")
    return "\n".join(lines)


def worst(result: dict) -> float:
    """The largest relative error over every algorithm of a result (nan if any is nan)."""
    values = [row["max_rel"] for row in result["algorithms"].values()]
    return math.nan if any(math.isnan(x) for x in values) else max(values)


def _validate_one(name: str, args: argparse.Namespace) -> dict:
    """validate_robot, with a failure to run turned into a failed result."""
    from cgadyn.validate import validate_robot

    try:
        return validate_robot(name, args.samples, args.seed, args.tolerance)
    except Exception as exc:  # one robot must not stop --all
        return {"robot": name, "dof": None, "samples": args.samples, "seed": args.seed,
                "tolerance": args.tolerance, "algorithms": {}, "pass": False,
                "error": f"{type(exc).__name__}: {exc}"}


def _validate_all(args: argparse.Namespace) -> int:
    names = _known_robots()
    results = []
    for i, name in enumerate(names):
        _progress(i, len(names), name)
        results.append(_validate_one(name, args))
    _progress(len(names), len(names), "done")
    ok = all(r["pass"] for r in results)
    if args.json:
        print(json.dumps({"pass": ok, "results": results}, indent=2))
    else:
        print(format_summary(results, args))
    return 0 if ok else 1


def format_summary(results: list[dict], args: argparse.Namespace) -> str:
    """One row per robot: dof, the worst relative error per algorithm, pass/fail."""
    from cgadyn.validate import ALGORITHMS, REL_DEFINITION, versions

    v = versions()
    short = {"rnea": "rnea", "aba": "aba", "crba": "crba", "gravity": "g(q)",
             "jacobian_world": "J world", "jacobian_local": "J local", "fk": "fk"}
    lines = [f"cgadyn validate --all: {len(results)} robots, {args.samples} samples each, seed "
             f"{args.seed} | cgadyn {v['cgadyn']}, pinocchio {v['pinocchio']}",
             f"worst relative error per algorithm; {REL_DEFINITION}; "
             f"tolerance {args.tolerance:.0e}", ""]
    head = f"{'robot':<28}{'dof':>4}" + "".join(f"{short[k]:>10}" for k in ALGORITHMS)
    lines += [head + "  result", "-" * (len(head) + 8)]
    for r in results:
        rows = r["algorithms"]
        cells = "".join(f"{_fmt(rows[k]['max_rel']) if k in rows else '-':>10}" for k in ALGORITHMS)
        dof = "?" if r["dof"] is None else str(r["dof"])
        lines.append(f"{r['robot']:<28}{dof:>4}{cells}  {'pass' if r['pass'] else 'FAIL'}")
        if "error" in r:
            lines.append(f"    error: {r['error']}")
    passed = sum(r["pass"] for r in results)
    lines += ["-" * (len(head) + 8), f"{passed}/{len(results)} robots pass"]
    return "\n".join(lines)


# --- info, robots ------------------------------------------------------------------------


def _joint_info(model, j: int) -> dict:
    return {"name": model.joint_names[j], "kind": model.joint_kinds[j],
            "parent": _joint_name(model, int(model.parents[j])),
            "lower": float(model.lower[j]), "upper": float(model.upper[j]),
            "velocity_limit": float(model.velocity_limit[j]),
            "effort_limit": float(model.effort_limit[j]),
            "body_mass": float(model.body_mass[j])}


def _model_info(model) -> dict:
    """Joints (kind, parent, limits, body mass), links (with their joint), total mass."""
    return {
        "robot": model.name, "dof": model.nv, "root_link": model.root_link,
        "total_mass": model.total_mass,
        "joints": [_joint_info(model, j) for j in range(model.nv)],
        "links": [{"name": n, "joint": _joint_name(model, int(model.link_joint[i]))}
                  for i, n in enumerate(model.link_names)],
    }


def _joint_name(model, j: int) -> str | None:
    return None if j < 0 else model.joint_names[j]


def format_info(info: dict) -> str:
    """A readable listing of :func:`_model_info`."""
    lines = [f"{info['robot']}: {info['dof']} dof, {len(info['links'])} links, "
             f"root link {info['root_link']}, moving mass {info['total_mass']:.4g} kg", "",
             f"{'#':>3}  {'joint':<28}{'kind':<12}{'lower':>10}{'upper':>10}{'mass':>9}  parent"]
    for j, jt in enumerate(info["joints"]):
        lines.append(f"{j:>3}  {jt['name']:<28}{jt['kind']:<12}{jt['lower']:>10.4g}"
                     f"{jt['upper']:>10.4g}{jt['body_mass']:>9.4g}  {jt['parent'] or 'world'}")
    lines += ["", f"{'link':<36}moves with joint"]
    lines += [f"{lk['name']:<36}{lk['joint'] or '(fixed to world)'}" for lk in info["links"]]
    return "\n".join(lines)


def _run_info(args: argparse.Namespace) -> int:
    robot = _resolve(args.robot)
    if robot is None:
        return 2
    from cgadyn.multibody import load

    info = _model_info(load(robot))
    print(json.dumps(info, indent=2) if args.json else format_info(info))
    return 0


def _run_robots(args: argparse.Namespace) -> int:
    print("\n".join(_known_robots()))
    return 0


# --- entry point -------------------------------------------------------------------------


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``cgadyn`` command; returns the exit status (argparse errors give 2)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return exc.code if isinstance(exc.code, int) else 2
    if getattr(args, "func", None) is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return int(args.func(args))
    except BrokenPipeError:  # `cgadyn info panda | head`: stop quietly, like other tools
        _silence_stdout()
        return 141


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail."""
    import os

    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):
        pass


if __name__ == "__main__":
    sys.exit(main())
