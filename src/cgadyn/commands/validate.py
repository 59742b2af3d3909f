"""``cgadyn validate``: every check of ``cgadyn.oracle`` against Pinocchio, on one robot or
on every robot of ``cgadyn robots`` (``--all``), as a table in the style of the paper's
Table 1 or as JSON. Exit status 1 when a check ran and failed."""

from __future__ import annotations

import argparse
import math
import sys

from .. import mujoco_oracle, oracle
from .common import (
    DEFAULT_ROBOT,
    ROBOT_HELP,
    UsageError,
    add_base_options,
    floating_base,
    non_negative_int,
    positive_float,
    positive_int,
    print_json,
)

__all__ = ["add_parser", "format_result", "format_summary", "run"]


def add_parser(sub) -> None:
    from ..validate import DEFAULT_SAMPLES, DEFAULT_SEED, DEFAULT_TOLERANCE

    p = sub.add_parser(
        "validate", help="compare every algorithm with Pinocchio (the paper's Table 1)",
        description="Run every algorithm (dynamics, Jacobians, kinematics, derivatives, "
        "centroidal quantities, the configuration manifold) on random states in cgadyn "
        "(one sample at a time; the tests check that batches repeat it) and Pinocchio and "
        "print the relative errors. q: joints uniform within "
        "their limits, a free-flyer base in the unit box with a uniformly random rotation; "
        "v, a, tau standard normal. Exit status 1 if a check fails.")
    p.add_argument("robot", nargs="?", metavar="ROBOT",
                   help=f"{ROBOT_HELP} (default {DEFAULT_ROBOT})")
    p.add_argument("--samples", type=positive_int, default=DEFAULT_SAMPLES,
                   help=f"random states per robot (default {DEFAULT_SAMPLES}; the paper used "
                   "1000)")
    p.add_argument("--seed", type=non_negative_int, default=DEFAULT_SEED,
                   help=f"random seed, an integer >= 0 (default {DEFAULT_SEED})")
    p.add_argument("--tolerance", type=positive_float, default=DEFAULT_TOLERANCE,
                   help=f"largest relative error that passes (default {DEFAULT_TOLERANCE:g}); "
                   "forward dynamics and M⁻¹ are judged against it times cond(M)")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.add_argument("--all", action="store_true",
                   help="validate every robot of `cgadyn robots` (refused ones are listed)")
    add_base_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.all and args.robot:
        raise UsageError("give a ROBOT or --all, not both")
    if args.all:
        return _validate_all(args)
    from ..validate import validate_robot

    result = validate_robot(args.robot or DEFAULT_ROBOT, args.samples, args.seed,
                            args.tolerance, floating_base(args))
    print_json(result) if args.json else print(format_result(result))
    return 0 if result["pass"] else 1


def _fmt(x: float | None) -> str:
    return "-" if x is None else "nan" if math.isnan(x) else f"{x:.2e}"


def _verdict(row: dict) -> str:
    return "n/a" if "not_applicable" in row else "pass" if row["pass"] else "FAIL"


def format_result(result: dict) -> str:
    """The Table-1-style text table of one ``validate_robot`` result."""
    v = result["versions"]
    lines = [
        f"cgadyn validate: {result['robot']}, {result['base']} base, nq {result['nq']}, nv "
        f"{result['nv']}, {result['samples']} samples, seed {result['seed']} | cgadyn "
        f"{v['cgadyn']}, pinocchio {v['pinocchio']}, numpy {v['numpy']}, numba {v['numba']}",
        f"cgadyn (one sample at a time) against Pinocchio"
        f"{' and MuJoCo' if any(k in result['checks'] for k in mujoco_oracle.CHECKS) else ''}"
        f"; the paper's Table 1 used 1000 samples",
        f"{result['relative_error']}; tolerance {result['tolerance']:.0e}",
        f"{result['scaled']}; largest cond(M) {result['conditioning']:.2e}",
        f"Jacobians at: {', '.join(result['jacobian_links'])}", "",
        f"{'check':<42}{'mean norm':>11}{'max |diff|':>11}{'max rel':>11}{'limit':>10}  result",
        "-" * 93]
    labels = [(c.key, c.label) for c in oracle.CHECKS] + list(result.get("labels", {}).items()) \
        + [(key, label) for key, label in mujoco_oracle.CHECKS.items()
           if key in result["checks"]]
    for key, label in labels:
        row = result["checks"][key]
        lines.append(f"{label:<42}{_fmt(row['mean_norm']):>11}{_fmt(row['max_abs']):>11}"
                     f"{_fmt(row['max_rel']):>11}{_fmt(row['tolerance']):>10}  {_verdict(row)}")
        if "error" in row:
            lines.append(f"    why: {row['error']}")
        if "not_applicable" in row:
            lines.append(f"    n/a: {row['not_applicable']}")
    lines.append("-" * 93)
    verdict = "PASS" if result["pass"] else "FAIL"
    failed = [k for k, row in result["checks"].items() if not row["pass"]]
    undefined = [k for k, row in result["checks"].items() if "not_applicable" in row]
    within = len(result["checks"]) - len(failed) - len(undefined)
    lines.append(f"{verdict}: {within}/{len(result['checks'])} checks within their limits"
                 f"{'; failed: ' + ', '.join(failed) if failed else ''}"
                 f"{'; undefined for this robot: ' + ', '.join(undefined) if undefined else ''}"
                 f" ({result['seconds']:.1f} s)")
    return "\n".join(lines)


def _validate_all(args: argparse.Namespace) -> int:
    from ..multibody import registry
    from ..validate import validate_robot

    names = registry.robots()
    refused = registry.refused()
    results = []
    for i, name in enumerate(names):
        _progress(i, len(names), name)
        if name in refused:
            results.append({"robot": name, "pass": None, "refused": refused[name]})
            continue
        try:
            results.append(validate_robot(name, args.samples, args.seed, args.tolerance,
                                          floating_base(args)))
        except (ValueError, OSError) as exc:  # one robot must not stop --all
            results.append({"robot": name, "pass": False, "error": str(exc)})
    _progress(len(names), len(names), "done")
    ok = all(r["pass"] is not False for r in results)
    if args.json:
        print_json({"pass": ok, "results": results})
    else:
        print(format_summary(results, args))
    return 0 if ok else 1


SHORT = {"rnea": "rnea", "aba": "aba", "crba": "crba", "gravity": "g(q)",
         "jacobian_world": "J world", "jacobian_local": "J local", "fk": "fk",
         "rnea_derivatives": "d rnea", "aba_derivatives": "d aba", "minverse": "M⁻¹",
         "centroidal": "Ag", "com": "com", "manifold": "q ⊕ v", "constrained": "held"}
"""Column titles of the ``--all`` table, one per check of ``oracle.CHECKS`` and the
constrained check (``validate.CONSTRAINED``: empty for a robot without constraints)."""
MUJOCO_SHORT = {"mj_placements": "mj x", "mj_mass_matrix": "mj M", "mj_rnea": "mj rnea",
                "mj_aba": "mj aba", "mj_passive": "mj pas"}
"""Column titles of the ``--all`` table for the checks against MuJoCo
(``mujoco_oracle.CHECKS``): shown when a robot of the run is an MJCF model, empty for the
others."""


def _cell(row: dict) -> str:
    return "n/a" if "not_applicable" in row else _fmt(row["max_rel"])


def format_summary(results: list[dict], args: argparse.Namespace) -> str:
    """One row per robot: nv, base, the worst relative error per check, pass/fail."""
    from ..validate import versions

    v = versions()
    titles = dict(SHORT)
    mujoco = [k for k in mujoco_oracle.CHECKS
              if any(k in r.get("checks", {}) for r in results)]
    titles.update((k, MUJOCO_SHORT[k]) for k in mujoco)
    keys = [c.key for c in oracle.CHECKS] + ["constrained"] + mujoco
    width = max([27] + [len(r["robot"]) + 1 for r in results])
    lines = [f"cgadyn validate --all: {len(results)} robots, {args.samples} samples each, seed "
             f"{args.seed} | cgadyn {v['cgadyn']}, pinocchio {v['pinocchio']}"
             f"{', mujoco ' + _mujoco_version() if mujoco else ''}",
             f"worst relative error per check; {oracle.RELATIVE}; tolerance "
             f"{args.tolerance:.0e} (× cond(M) for aba, d aba, M⁻¹, held"
             f"{', mj aba' if mujoco else ''}); held: constrained dynamics, a floating "
             f"robot's feet or an MJCF model's equalities held"]
    if mujoco:
        lines.append("mj: an MJCF model against MuJoCo (rel as above, MuJoCo in place of "
                     "Pinocchio): x body placements (xpos, xmat), M mj_fullM, rnea "
                     "mj_inverse, aba mj_forward's qacc, pas qfrc_passive")
    lines.append("")
    head = f"{'robot':<{width}}{'nv':>4} {'base':<6}" + "".join(f"{titles[k]:>9}"
                                                               for k in keys)
    lines += [head + "  result", "-" * (len(head) + 8)]
    for r in results:
        if "checks" not in r:
            status = "refused" if r["pass"] is None else "FAIL"
            lines.append(f"{r['robot']:<{width}}{'':>4} {'':<6}  {status}: "
                         f"{r.get('refused') or r.get('error')}")
            continue
        cells = "".join(f"{_cell(r['checks'][k]) if k in r['checks'] else '':>9}"
                        for k in keys)
        base = "free" if r["base"] == "free flyer" else "fixed"
        lines.append(f"{r['robot']:<{width}}{r['nv']:>4} {base:<6}{cells}  "
                     f"{'pass' if r['pass'] else 'FAIL'}")
        for key, row in r["checks"].items():
            if "error" in row:
                lines.append(f"    {key} ({_verdict(row)}): {row['error']}")
    passed = sum(r["pass"] is True for r in results)
    refused = sum(r["pass"] is None for r in results)
    lines += ["-" * (len(head) + 8),
              f"{passed}/{len(results) - refused} robots pass; {refused} refused"]
    return "\n".join(lines)


def _mujoco_version() -> str:
    import mujoco

    return mujoco.__version__


def _progress(done: int, total: int, label: str, width: int = 24) -> None:
    """A one-line progress bar on stderr (only on a terminal): ``[####    ] 5/24 ur5``."""
    if not sys.stderr.isatty():
        return
    filled = round(width * done / total) if total else width
    end = "\n" if done == total else ""
    print(f"\r[{'#' * filled}{' ' * (width - filled)}] {done}/{total} {label:<30}", end=end,
          file=sys.stderr, flush=True)
