"""``cgadyn robots``: every robot that loads by name (example-robot-data's, the project's
own, Gymnasium's and dm_control's MuJoCo models), with its base, nq and nv, and the robots
that cgadyn refuses, with the reason."""

from __future__ import annotations

import argparse

from .common import print_json

__all__ = ["add_parser", "listing", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("robots", help="list the robots that load by name, with base and dof",
                       description="Every robot name `cgadyn.load` accepts (the project's own "
                       "robots, example-robot-data's, Gymnasium's and dm_control's MuJoCo models), "
                       "with its natural base, nq and nv, "
                       "and the robots cgadyn refuses with the reason. Loads every model "
                       "(cached after the first run).")
    p.add_argument("--names", action="store_true", help="print the names only, one per line")
    p.add_argument("--json", action="store_true", help="print as JSON")
    p.set_defaults(func=run)


def listing() -> list[dict]:
    """One entry per robot: ``name, source, base, nq, nv`` or ``refused`` (the reason)."""
    from ..multibody import registry

    refused = registry.refused()
    rows = []
    for name in sorted(set(registry.robots()) | set(refused)):
        row = {"name": name, "source": registry.source(name)}
        if name in refused:
            row["refused"] = refused[name]
        else:
            model = registry.load(name)
            row.update(base="free flyer" if model.floating_base else "fixed", nq=model.nq,
                       nv=model.nv)
        rows.append(row)
    return rows


def run(args: argparse.Namespace) -> int:
    if args.names:
        from ..multibody import registry

        print("\n".join(registry.robots()))
        return 0
    rows = listing()
    if args.json:
        print_json(rows)
        return 0
    width = max([28] + [len(r["name"]) + 1 for r in rows])
    lines = [f"{'robot':<{width}}{'base':<12}{'nq':>4}{'nv':>4}  source"]
    for r in rows:
        if "refused" in r:
            lines.append(f"{r['name']:<{width}}{'refused':<12}{'':>4}{'':>4}  {r['source']}: "
                         f"{r['refused']}")
        else:
            lines.append(f"{r['name']:<{width}}{r['base']:<12}{r['nq']:>4}{r['nv']:>4}  "
                         f"{r['source']}")
    loaded = sum("refused" not in r for r in rows)
    lines.append(f"{loaded} robots load by name; {len(rows) - loaded} refused")
    print("\n".join(lines))
    return 0
