"""``cgadyn simulate-body``: the hypercube on a spring of figs. 2.4/2.5 in d = 1..4.

``cgadyn.cli`` registers ``add_parser``/``run`` with the other subcommands.
"""

from __future__ import annotations

import argparse

from .._json import dumps
from .._paths import check_plot_path

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register the ``simulate-body`` subcommand on an ``add_subparsers()`` object."""
    p = subparsers.add_parser(
        "simulate-body",
        help="simulate a PGA hypercube on a spring (Dorst & De Keninck, figs. 2.4/2.5)",
        description="A free rigid hypercube in d-dimensional PGA under gravity, hanging from "
        "a spring, with damping and floor contact; prints the final state and energy.",
    )
    _add_arguments(p)
    p.set_defaults(func=run)
    return p


def _add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--dim", type=int, default=3, help="space dimension d in 1..4 (default 3)")
    p.add_argument("--steps", type=int, default=1200, help="number of steps (default 1200)")
    p.add_argument("--dt", type=float, default=1 / 600, help="step size in s (default 1/600)")
    p.add_argument("--integrator", default="rk4", help="rk4 (default) or euler")
    p.add_argument("--no-contact", action="store_true", help="no floor")
    p.add_argument("--no-damping", action="store_true", help="no damping forque")
    p.add_argument("--plot", metavar="FILE.png", help="write trajectory and energy plot")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args: argparse.Namespace) -> int:
    """Run the simulation; returns the exit code. Bad arguments raise ``ValueError`` or
    ``UsageError``, which ``cgadyn.cli.main`` reports (exit status 2)."""
    from ..pga.simulate import hypercube_on_spring

    check_plot_path(args.plot)  # before the work: a bad path is a usage error
    result = hypercube_on_spring(
        d=args.dim,
        steps=args.steps,
        dt=args.dt,
        integrator=args.integrator,
        contact=not args.no_contact,
        damping=not args.no_damping,
    )
    summary = result["summary"]
    if args.plot:
        _plot(result, args.plot)
        summary["plot"] = args.plot
    if args.json:
        print(dumps(summary, indent=2))
    else:
        _print_summary(summary)
    return 0


def _print_summary(s: dict) -> None:
    print(f"hypercube on a spring in {s['dim']}D PGA: {s['steps']} {s['integrator']} steps of "
          f"{s['dt']:.4g} s ({s['duration']:.3g} s), contact={s['contact']}, "
          f"damping={s['damping']}")
    print(f"  final centroid     {[round(x, 6) for x in s['final_centroid']]}")
    print("  final motor M      " + _terms(s["final_motor"]))
    print("  final rate B       " + _terms(s["final_rate"]))
    print(f"  energy             {s['energy_initial']:.9g} -> {s['energy_final']:.9g} J")
    print(f"  energy drift       {s['energy_drift']:.3e} J "
          f"(max deviation {s['energy_max_deviation']:.3e} J)")
    print(f"  contacts           {s['contacts']}")
    print(f"  |M M~ - 1|         {s['motor_norm_error']:.2e}")
    if "plot" in s:
        print(f"  plot               {s['plot']}")


def _terms(coeffs: dict) -> str:
    return " ".join(f"{v:+.6g}{'' if k == '1' else ' ' + k}" for k, v in coeffs.items()) or "0"


def _plot(result: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s, tr = result["summary"], result["trajectory"]
    up = tr["up_axis"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    if s["dim"] == 1:
        ax1.plot(tr["t"], tr["centroid"][:, 0], label="centroid")
        ax1.plot(tr["t"], tr["vertex"][:, 0], label="spring vertex")
        ax1.set_xlabel("t [s]")
        ax1.set_ylabel("x")
    else:
        ax1.plot(tr["centroid"][:, 0], tr["centroid"][:, up], label="centroid")
        ax1.plot(tr["vertex"][:, 0], tr["vertex"][:, up], label="spring vertex")
        ax1.set_xlabel("x")
        ax1.set_ylabel("y (up)")
        if s["floor_height"] is not None:
            ax1.axhline(s["floor_height"], color="k", lw=1, label="floor")
        ax1.set_aspect("equal", adjustable="datalim")
    ax1.legend()
    ax1.set_title(f"{s['dim']}D hypercube trajectory")
    ax2.plot(tr["t"], tr["energy"], label="T + V")
    ax2.plot(tr["t"], tr["kinetic"], label="T = ½ B ∨ I[B]")
    ax2.plot(tr["t"], tr["potential"], label="V")
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("energy [J]")
    ax2.legend()
    ax2.set_title(f"energy ({s['integrator']}, dt={s['dt']:.3g})")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
