"""``cgadyn ik``: inverse kinematics of one link to a position, or to a full pose.

    cgadyn ik ROBOT LINK --position X Y Z [--orientation W X Y Z] [--json]

Without ``--orientation`` the link frame's origin is brought onto the point (a point task);
with it, onto the pose (the quaternion ``w x y z``, normalised). Prints the configuration,
whether it converged, the residual and the iterations; exits with 1 when the target was not
reached (the best configuration is printed all the same), 2 on bad input.
"""

from __future__ import annotations

import argparse
import math

from .common import (
    ROBOT_HELP,
    add_base_options,
    floating_base,
    non_negative_int,
    positive_float,
    print_json,
)

__all__ = ["add_parser", "run"]


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def add_parser(sub) -> None:
    p = sub.add_parser("ik", help="inverse kinematics: a link to a position or a pose")
    p.add_argument("robot", metavar="ROBOT", help=ROBOT_HELP)
    p.add_argument("link", metavar="LINK", help="the link to move (see `cgadyn info ROBOT`)")
    p.add_argument("--position", type=_finite, nargs=3, required=True, metavar=("X", "Y", "Z"),
                   help="target position of the link frame's origin, in the world (m)")
    p.add_argument("--orientation", type=_finite, nargs=4, metavar=("W", "X", "Y", "Z"),
                   help="target orientation as a quaternion (default: position only)")
    p.add_argument("--tol", type=positive_float, default=1e-10,
                   help="the residual norm to reach (default 1e-10)")
    p.add_argument("--restarts", type=non_negative_int, default=20,
                   help="random restarts within the joint limits (default 20)")
    p.add_argument("--seed", type=non_negative_int, default=0, help="seed of the restarts")
    p.add_argument("--json", action="store_true", help="print as JSON")
    add_base_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..cga.conventions import motor_from_quaternion
    from ..cga.objects import Motor, Point
    from ..multibody import registry
    from ..tasks import inverse_kinematics

    model = registry.load(args.robot, floating_base=floating_base(args))
    if args.orientation is None:
        target, kind = Point(args.position), "position"
    else:
        quat = np.asarray(args.orientation)
        if not np.linalg.norm(quat) > 0.0:
            raise ValueError("--orientation: the quaternion is zero")
        target, kind = Motor(motor_from_quaternion(quat, args.position)), "pose"
    res = inverse_kinematics(model, args.link, target, tol=args.tol, restarts=args.restarts,
                             seed=args.seed)
    out = {"robot": model.name, "link": args.link, "target": kind,
           "position": list(args.position), "orientation": args.orientation,
           "converged": res.converged, "error": res.error,
           "residual": [float(x) for x in res.residual], "iterations": res.iterations,
           "restarts": res.restarts, "q": [float(x) for x in res.q],
           "joints": list(model.joint_names)}
    if args.json:
        print_json(out)
    else:
        state = "converged" if res.converged else "NOT converged (best configuration found)"
        print(f"{model.name} {args.link} to the {kind} {args.position}"
              f"{'' if args.orientation is None else f' {args.orientation}'}: {state}, "
              f"|residual| = {res.error:.3g}, {res.iterations} iterations, "
              f"{res.restarts} restarts")
        for name, x in zip(model.joint_names, res.q, strict=False):
            print(f"  {name:<28s} {x: .10f}")
    return 0 if res.converged else 1
