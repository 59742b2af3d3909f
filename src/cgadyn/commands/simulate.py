"""``cgadyn simulate``: integrate a robot's motion (``cgadyn.simulate``), print a summary
(the energy drift of passive runs), and optionally the trajectory as JSON, a figure
(``--plot``) and a self-contained browser animation with the robot's meshes (``--html``).

    cgadyn simulate [ROBOT] [--seconds S] [--dt DT] [--integrator NAME]
                    [--controller none|gravity|pd] [--wn W | --kp KP --kd KD] [--q0 Q ...]
                    [--v0 V ...] [--ground] [--drop H] [--soft K] [--controls none|random]
                    [--seed N] [--json] [--plot F.png]
                    [--html F.html] [--no-progress]

``--ground`` puts a level ground at z = 0 under the robot (an MJCF's own floor and static
geoms where it has them, ``cgadyn.static_world``), touched by the collision shapes of its
URDF or MJCF (``cgadyn.collision_model``; meshes as their convex hulls): the run is
then the contact step of ``docs/contact.md`` (semi-implicit Euler with frictional contact
impulses). A floating robot starts resting on it, its lowest shape at the ground, or
``--drop H`` metres above it. ``--soft K`` makes the links it stands on touch the ground
through springs and dampers (``CollisionModel.compliant``, K41).

The run is integrated in chunks of steps, each one ``cgadyn.simulate`` call continuing from
the last state (RK4 and the Euler methods are one-step methods, so the states are those of
one call), to draw a progress bar on stderr when the run takes more than a second.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np

from .common import (
    DEFAULT_ROBOT,
    ROBOT_HELP,
    UsageError,
    add_base_options,
    check_output_file,
    check_plot_path,
    floating_base,
    positive_float,
    print_json,
    warn,
)

__all__ = ["add_parser", "check_html_path", "parse_vector", "pd_gains", "run",
           "simulate_chunked"]

INTEGRATORS = ("rk4", "semi_implicit_euler", "euler")
CONTACT_INTEGRATOR = "semi_implicit_euler"
"""The integrator of a run with ``--ground``: the contact step is a velocity-level step."""
CONTROLLERS = ("none", "gravity", "pd")
WN = 10.0
"""rad/s: the default natural frequency of the ``pd`` controller's joints."""
PROGRESS_AFTER = 1.0
"""Seconds: a run expected to take longer than this draws a progress bar."""
PENETRATION = 1e-3
"""Metres: how deep in the ground a run with ``--ground`` may start."""
MAX_KEPT = 100_001
"""The states a run keeps unless ``--record-every`` says otherwise: a longer run keeps every
k-th (the first k that fits), so that its memory and its JSON stay bounded."""


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def _height(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"expected a height in metres >= 0, got {text!r}")
    return value


def record_every(steps: int, given: int | None) -> int:
    """``--record-every``, or the smallest k that keeps at most ``MAX_KEPT`` states."""
    return given if given is not None else max(1, -(-steps // (MAX_KEPT - 1)))


def add_parser(sub) -> None:
    p = sub.add_parser(
        "simulate", help="integrate a robot's motion; plot it or animate it in a browser",
        description="Integrate q'' = ABA(q, v, tau) from q0, v0 and print a summary: the "
        "final state, and for a passive run (no controller) the drift of the total energy, "
        "max |E(t) - E(0)| / |E(0)|.")
    p.add_argument("robot", nargs="?", default=DEFAULT_ROBOT, metavar="ROBOT",
                   help=f"{ROBOT_HELP} (default {DEFAULT_ROBOT})")
    p.add_argument("--seconds", type=positive_float, default=2.0,
                   help="simulated time in seconds (default 2)")
    p.add_argument("--dt", type=positive_float, default=1e-3,
                   help="time step in seconds (default 0.001)")
    p.add_argument("--integrator", choices=INTEGRATORS, default=None,
                   help=f"integration method (default rk4; {CONTACT_INTEGRATOR} with "
                        f"--ground, the only one contact allows)")
    p.add_argument("--controller", choices=CONTROLLERS, default="none",
                   help="none: passive; gravity: gravity compensation; pd: joint PD to the "
                        "start configuration (the model's home, within the joints' limits) "
                        "plus gravity compensation (default none)")
    p.add_argument("--wn", type=positive_float, default=None,
                   help=f"PD natural frequency in rad/s: K_p = diag(M(q_ref)) wn^2, "
                        f"K_d = 2 diag(M(q_ref)) wn, critically damped per joint, so that "
                        f"light joints get light gains (default {WN:g}; with --controller "
                        f"pd only)")
    p.add_argument("--kp", nargs="+", metavar="KP",
                   help="PD stiffness instead: one number for every joint or nv numbers "
                        "(with --controller pd only)")
    p.add_argument("--kd", nargs="+", metavar="KD",
                   help="PD damping instead: one number for every joint or nv numbers "
                        "(with --controller pd only)")
    p.add_argument("--q0", nargs="+", metavar="Q",
                   help="initial configuration, nq numbers separated by spaces or commas "
                        "(default: the model's home configuration (an MJCF model's qpos0, a "
                        "URDF's neutral one), each coordinate moved into its joint's limits)")
    p.add_argument("--v0", nargs="+", metavar="V",
                   help="initial velocity, nv numbers (default zero)")
    p.add_argument("--ground", action="store_true",
                   help="a level ground at z = 0 touched by the robot's collision shapes, "
                        "with Coulomb friction 1 (an MJCF's own floor and static geoms, "
                        "where it has them); a floating robot starts resting on it")
    p.add_argument("--drop", type=_height, default=None, metavar="H",
                   help="start a floating robot with its lowest shape H metres above the "
                        "ground (implies --ground)")
    p.add_argument("--soft", type=positive_float, default=None, metavar="K",
                   help="with --ground: the links it stands on (within 1 cm of its lowest "
                        "shape) touch the ground through a spring of K N/m and a damper of "
                        "2 sqrt(K m) N s/m at each contact point (m its mass): soft soles "
                        "(default rigid)")
    p.add_argument("--controls", choices=("none", "random"), default="none",
                   help="random: each step's controls of the model's MJCF motors drawn "
                        "uniformly in their control ranges (the random actions of a "
                        "Gymnasium agent), added to the controller's torques (default none)")
    p.add_argument("--seed", type=int, default=0,
                   help="the seed of --controls random (default 0)")
    p.add_argument("--json", action="store_true",
                   help="print the summary and the whole trajectory as JSON")
    p.add_argument("--plot", metavar="FILE", help="write joint trajectories and energy to "
                   "FILE (its extension picks the format, e.g. .png, .pdf, .svg)")
    p.add_argument("--html", metavar="FILE", help="write a self-contained animation of the "
                   "robot with its meshes, for a browser, to FILE.html (needs meshcat: pip "
                   "install 'cgadyn[viewer]')")
    p.add_argument("--record-every", type=_positive_int, metavar="K",
                   help=f"keep every K-th state and the last (default 1, or as many as keep "
                        f"at most {MAX_KEPT} states of a long run)")
    p.add_argument("--no-progress", dest="progress", action="store_false",
                   help="never draw the progress bar")
    add_base_options(p)
    p.set_defaults(func=run)


def parse_vector(tokens: list[str] | None, size: int, name: str) -> np.ndarray | None:
    """``--q0 1 -0.5`` or ``--q0 1,-0.5`` as ``size`` finite numbers; a ``UsageError``
    naming the option otherwise."""
    if tokens is None:
        return None
    parts = [p for tok in tokens for p in re.split(r"[,\s]+", tok.strip()) if p]
    try:
        values = np.array([float(p) for p in parts])
    except ValueError:
        raise UsageError(f"{name} must be numbers separated by spaces or commas, got "
                         f"{' '.join(tokens)!r}") from None
    if values.shape != (size,):
        raise UsageError(f"{name} needs {size} numbers for this robot, got {len(values)}")
    if not np.all(np.isfinite(values)):
        raise UsageError(f"{name} must be finite numbers, got {' '.join(tokens)!r}")
    return values


def check_html_path(path: str | None) -> Path | None:
    """``path`` if the animation can be written there (``.html``/``.htm`` in an existing
    directory) and meshcat is installed; else a ``UsageError`` saying which."""
    if path is None:
        return None
    p = Path(path)
    if p.suffix.lower() not in (".html", ".htm"):
        raise UsageError(f"cannot write the animation {path!r}: expected a file ending in "
                         f".html, got {p.suffix or '(no extension)'!r}")
    check_output_file(path, "the animation")
    from ..sim.html import MissingViewer, require_viewer

    try:
        require_viewer()
    except MissingViewer as exc:
        raise UsageError(f"--html: {exc}") from None
    return p


class _Progress:
    """A one-line progress bar on stderr: ``simulate |#####     | 52% 5200/10000 steps``."""

    def __init__(self, total: int, width: int = 30):
        self.total, self.width, self.last = total, width, -1.0

    def update(self, done: int, final: bool = False) -> None:
        now = time.perf_counter()
        if not final and now - self.last < 0.2:
            return
        self.last = now
        frac = done / self.total
        bar = "#" * int(round(frac * self.width))
        sys.stderr.write(f"\rsimulate |{bar:<{self.width}}| {100 * frac:3.0f}% "
                         f"{done}/{self.total} steps")
        if final:
            sys.stderr.write("\n")
        sys.stderr.flush()


def simulate_chunked(model, q0, v0, dt: float, steps: int, integrator: str, controller,
                     progress: bool = True, every: int = 1, world=None, collisions=None,
                     ctrl=None):
    """``cgadyn.simulate(model, q0, v0, dt, steps, ..., record_every=every, world=world,
    collisions=collisions, ctrl=ctrl)`` as a sequence of calls, each continuing from the
    last state (and the actuators' last activations, A2) and each a whole number of
    ``every`` steps (so that the states kept are
    those of one call;
    with contact, each call's first step starts its solver cold instead of from the last
    step's forces, which changes the forces within the solver's tolerance), with a progress
    bar when the whole is expected to take longer than :data:`PROGRESS_AFTER` seconds.
    Returns one ``Trajectory`` (its message gives the step and time of the whole run)."""
    from ..sim import Trajectory, simulate

    keys = ("i", "q", "v", "a", "kinetic", "potential")
    if world is not None:
        keys += ("contact_count", "contact_forces")
    parts: dict[str, list] = {k: [] for k in keys}
    q, v, act, done, message, bar = q0, v0, None, 0, "", None
    chunk = every  # the first call compiles: one kept row, then a measured chunk sets the pace
    while done < steps:
        n = min(chunk, steps - done)
        start = time.perf_counter()
        notice = threading.Timer(PROGRESS_AFTER, _compiling) if progress and done == 0 \
            else None
        if notice is not None:
            notice.daemon = True
            notice.start()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the message is reported once, below
                traj = simulate(model, q, v, dt, n, integrator=integrator,
                                controller=controller, record_every=every, world=world,
                                collisions=collisions,
                                ctrl=None if ctrl is None else ctrl[done:done + n],
                                act=act)
        finally:
            if notice is not None:
                notice.cancel()
        took = time.perf_counter() - start
        first = 0 if done == 0 else 1
        for k in parts:  # "i": the step of each state kept
            x = np.rint(traj.t / dt).astype(np.int64) + done if k == "i" else getattr(traj, k)
            parts[k].append(np.asarray(x)[first:])
        done += int(traj.completed)
        if traj.diverged:
            message = _stopped(traj.message, done, steps, dt, done - int(traj.completed))
            break
        q, v = traj.q[-1], traj.v[-1]
        act = None if traj.activation is None else traj.activation[-1]
        if done == n:
            chunk = max(1, min(1000, steps) // every) * every
        else:
            rate = n / max(took, 1e-9)  # steps per second
            if bar is None and progress and (steps - done) / rate > PROGRESS_AFTER:
                bar = _Progress(steps)
            chunk = max(1, int(rate * 0.25) // every) * every  # four updates a second
        if bar is not None and done < steps:
            bar.update(done)
    if bar is not None:
        bar.update(done, final=True)
    out = {k: np.concatenate(v) for k, v in parts.items()}
    i = out.pop("i")  # the times as one call gives them (sim.simulate._times)
    t = np.where(i % every == 0, (dt * every) * (i // every), dt * i)
    return Trajectory(t=t, **out, completed=done, diverged=bool(message), dt=dt,
                      integrator=integrator, message=message,
                      scene=traj.scene)  # the same for every call: its contacts' at a state


def _stopped(message: str, done: int, steps: int, dt: float, offset: int = 0) -> str:
    """The divergence message of one call, with the step and time of the whole run (the
    call began after ``offset`` steps)."""
    found = re.search(r"\): (.*?)(; the trajectory|$)", message or "")
    reason = found.group(1) if found else (message or "the state stopped being finite")
    reason = re.sub(r"step (\d+)", lambda m: f"step {int(m.group(1)) + offset}", reason)
    return (f"stopped after {done} of {steps} steps (t = {done * dt:g} s): {reason}; the "
            f"results hold the states up to there")


def _compiling() -> None:
    sys.stderr.write("simulate: compiling the simulation loop (once; numba caches it)...\n")
    sys.stderr.flush()


def pd_gains(model, q_ref: np.ndarray, wn: float, support=()) -> tuple[np.ndarray, np.ndarray]:
    """``K_p = I wn²``, ``K_d = 2 I wn``: each joint alone, with the inertia ``I`` it moves
    at ``q_ref``, a critically damped oscillator of frequency ``wn``; zero on the
    coordinates no actuator drives (a free flyer's). ``I`` is ``diag(M(q_ref))``, the
    joint's subtree. A floating robot standing on the links ``support`` (those touching
    the ground) turns, at each joint between its base and a support link (a leg's), the
    rest of the robot about that joint: ``I`` adds the whole mass at the distance from the
    joint to the centre of mass, ``m |p_j - c|²``. Such a leg also swings in the air, where
    the same gains meet its subtree alone: stable at any step, because a step with a world
    takes the gains at its end (K40)."""
    from ..algorithms import center_of_mass, crba, forward_kinematics
    from ..cga.conventions import matrix_from_motor

    M = np.asarray(crba(model, q_ref))
    inertia = np.diag(M).copy()
    if model.floating_base and len(support):
        joints = set()
        for link in support:  # every joint from the support link up to the base
            j = int(model.link_joint[link])
            while j >= 0:
                joints.add(j)
                j = int(model.parents[j])
        legs = np.array([int(model.dof_joint[k]) in joints for k in range(model.nv)])
        legs &= np.asarray(model.actuated)
        c = np.asarray(center_of_mass(model, q_ref))
        joints_at = np.asarray(matrix_from_motor(forward_kinematics(model, q_ref)[0]))
        mass = float(np.sum(model.body_mass))
        for k in np.flatnonzero(legs):  # from the joint frame's origin (one may carry no
            p = joints_at[int(model.dof_joint[k]), :3, 3]  # link: an MJCF body's chain)
            inertia[k] += mass * float(np.sum((p - c) ** 2))
    m = np.where(model.actuated, inertia, 0.0)
    return m * wn**2, 2.0 * m * wn


def _gains(tokens, model, name: str) -> np.ndarray | None:
    if tokens is None:
        return None
    size = 1 if len(tokens) == 1 and not re.search(r"[,\s]", tokens[0].strip()) else model.nv
    gains = parse_vector(tokens, size, name)
    if np.any(gains < 0):
        raise UsageError(f"{name} must be >= 0, got {' '.join(tokens)!r}")
    return gains[0] if size == 1 else gains


def check_gains(args: argparse.Namespace) -> None:
    """Gains are the PD controller's: ``--kp``, ``--kd`` or ``--wn`` with another
    controller would be ignored, so they are refused, saying what to add."""
    given = [name for name, value in (("--kp", args.kp), ("--kd", args.kd),
                                      ("--wn", args.wn)) if value is not None]
    if given and args.controller != "pd":
        raise UsageError(f"{', '.join(given)} {'sets' if len(given) == 1 else 'set'} the gains "
                         f"of the PD controller, but the controller is {args.controller!r}: "
                         f"add --controller pd")


def start_configuration(model) -> np.ndarray:
    """The model's home configuration (``Model.home``: MuJoCo's ``qpos0``, where the
    hopper stands 1.25 m up its ``rootz`` slide, not sunk 1.2 m into the floor at q = 0; a
    URDF's neutral one) with each coordinate of a joint whose coordinates add (revolute,
    prismatic, ...) moved into its limits: the command's default start and PD target.
    Gymnasium's Ant has every ankle's range away from 0 (30 to 70 degrees): started outside,
    a step takes it back (K26a), but a start should be a state the model allows."""
    from ..multibody.joints import TYPES

    q = np.array(model.home, dtype=float)
    for j, t in enumerate(model.joint_types):
        if TYPES[int(t)].additive:
            i = slice(int(model.idx_q[j]), int(model.idx_q[j + 1]))
            q[i] = np.clip(q[i], model.lower[i], model.upper[i])
    return q


def _controller(args, model, support=()):
    from ..sim import PD, GravityCompensation

    if args.controller == "gravity":
        return GravityCompensation()
    if args.controller == "pd":
        q_ref = start_configuration(model)
        kp, kd = pd_gains(model, q_ref, WN if args.wn is None else args.wn, support)
        kp_user, kd_user = _gains(args.kp, model, "--kp"), _gains(args.kd, model, "--kd")
        kp = kp if kp_user is None else kp_user
        kd = kd if kd_user is None else kd_user
        return PD(kp, kd, q_ref=q_ref)
    return None


def run(args: argparse.Namespace) -> int:
    from ..multibody import registry

    steps = int(round(args.seconds / args.dt))
    if steps < 1:
        raise UsageError(f"--seconds {args.seconds:g} is shorter than one step of --dt "
                         f"{args.dt:g}")
    check_gains(args)
    ground = args.ground or args.drop is not None
    if args.soft is not None and not ground:
        raise UsageError("--soft makes the soles on the ground compliant: add --ground (or "
                         "--drop)")
    integrator = _integrator(args.integrator, ground)
    plot = check_plot_path(args.plot)
    html = check_html_path(args.html)
    model = registry.load(args.robot, floating_base=floating_base(args))
    if model.coupling_names and not ground:
        raise UsageError(f"{model.name!r} couples its joints "
                         f"({', '.join(map(repr, model.coupling_names))}), which the contact "
                         f"step holds: add --ground")
    if args.drop is not None and not model.floating_base:
        raise UsageError(f"--drop lifts a floating base, but {model.name!r} has a fixed base "
                         f"(add --floating-base to give it one)")
    q0 = parse_vector(args.q0, model.nq, "--q0")
    given = q0 is not None
    q0 = start_configuration(model) if q0 is None else q0
    v0 = parse_vector(args.v0, model.nv, "--v0")
    v0 = np.zeros(model.nv) if v0 is None else v0
    ctrl = _controls(model, args, steps)
    world = collisions = None
    support: tuple = ()
    if ground:
        world, collisions, q0, support = _ground(model, args, q0, given, registry)
    controller = _controller(args, model, support)
    if html is not None:  # find the meshes before the run, not after it
        from ..sim.html import visuals

        visuals(model, _urdf(args.robot, registry))

    every = record_every(steps, args.record_every)
    start = time.perf_counter()
    traj = simulate_chunked(model, q0, v0, args.dt, steps, integrator, controller,
                            progress=args.progress, every=every, world=world,
                            collisions=collisions, ctrl=ctrl)
    wall = time.perf_counter() - start
    passive = controller is None and ctrl is None
    drift = traj.energy_drift() if passive else None
    summary = {"robot": model.name, "base": "free flyer" if model.floating_base else "fixed",
               "nq": model.nq, "nv": model.nv, "integrator": integrator,
               "dt": args.dt, "steps": steps, "seconds": steps * args.dt,
               "record_every": every, "states_kept": len(traj.t),
               "controller": args.controller, "controls": args.controls,
               "seed": args.seed if ctrl is not None else None, "actuated": model.actuated,
               "gains": {"kp": controller.kp, "kd": controller.kd}
               if args.controller == "pd" else None,
               "completed": traj.completed, "diverged": traj.diverged,
               "message": traj.message, "wall_seconds": wall,
               "energy_initial": traj.energy[0], "energy_final": traj.energy[-1],
               "energy_drift": drift, "q0": q0, "v0": v0, "q_final": traj.q[-1],
               "v_final": traj.v[-1], "ground": ground, "drop": args.drop,
               "soft": args.soft,
               **(_contact_summary(model, traj) if ground else {})}
    if plot is not None:
        from ..sim.plot import plot_trajectory

        plot_trajectory(model, traj, plot)
    if html is not None:
        from ..sim.html import write_html

        write_html(model, traj.q, args.dt * every, html, urdf=_urdf(args.robot, registry),
                   contacts=traj.contacts if ground else None, world=world)
    if args.json:
        arrays = {k: getattr(traj, k) for k in ("t", "q", "v", "a", "kinetic", "potential",
                                                "energy")}
        if ground:
            arrays["contact_count"] = traj.contact_count
            arrays["contact_force"] = np.nansum(traj.contact_forces, axis=-2)
        print_json({**summary, **arrays, "plot": str(plot) if plot else None,
                    "html": str(html) if html else None})
    else:
        print(_summary_text(summary, plot, html))
    if traj.diverged:
        warn(f"simulation stopped early: {traj.message}")
        return 1
    return 0


def _controls(model, args, steps: int) -> np.ndarray | None:
    """``--controls random``: (steps, na) controls uniform in the motors' control ranges
    from ``--seed``; None for ``--controls none``."""
    if args.controls == "none":
        return None
    if not model.actuator_names:
        raise UsageError(f"--controls random drives the motors of an MJCF model, but "
                         f"{model.name!r} has none (give a controller instead)")
    low, high = np.asarray(model.actuator_ctrlrange, float).T
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
        raise UsageError(f"--controls random draws within the motors' control ranges, but "
                         f"{model.name!r} has motors without one")
    return np.random.default_rng(args.seed).uniform(low, high, (steps, low.size))


def _integrator(given: str | None, ground: bool) -> str:
    """``--integrator``, or its default: RK4, or the contact step's with ``--ground``, which
    refuses the others."""
    if not ground:
        return given or "rk4"
    if given not in (None, CONTACT_INTEGRATOR):
        raise UsageError(f"--integrator {given} cannot take contact: with --ground the run "
                         f"is the contact step, a velocity-level {CONTACT_INTEGRATOR} step "
                         f"(leave --integrator out or give {CONTACT_INTEGRATOR})")
    return CONTACT_INTEGRATOR


def _ground(model, args, q0: np.ndarray, given: bool, registry):
    """The world of ``--ground``/``--drop``, the robot's collision shapes, ``q0`` with a
    floating base moved up or down so that its lowest shape is ``--drop`` metres (default
    0) above the ground (a ``q0`` given by ``--q0`` is moved only by ``--drop``), and the
    links it will stand on (``pd_gains``' support)."""
    from ..contact import MeshSimplified, World, collision_model, ground_contacts
    from ..contact.static_world import default_world

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshSimplified)  # hulls of at most 64 vertices
        try:
            collisions = collision_model(model, _urdf(args.robot, registry))
        except (ValueError, FileNotFoundError) as exc:
            raise UsageError(f"--ground needs the robot's collision shapes: {exc}") from None
    if len(collisions) == 0:
        raise UsageError(f"--ground: {model.name!r} has no collision shapes in its file, so "
                         f"nothing of it can touch the ground")
    own = default_world(collisions)  # an MJCF's floor and geoms (K44)
    world = own if own is not None and own.ground else World(
        obstacles=() if own is None else own.obstacles)
    q0 = q0.copy()
    found = ground_contacts(model, collisions, q0, world, margin=1e9)
    if len(found) == 0:
        raise UsageError(f"--ground: none of {model.name!r}'s collision shapes may touch "
                         f"the ground (their contype/conaffinity exclude it)")
    distance = found.distance.copy()
    if model.floating_base and (args.drop is not None or not given):
        lift = (args.drop or 0.0) if given else (args.drop or 0.0) - distance.min()
        q0[2] += lift  # the base's z: every shape rises by lift above the level ground
        distance += lift
    k = int(np.argmin(distance))
    if distance[k] < -PENETRATION:
        shape = collisions[int(found.collision[k])].name
        where = "the given --q0" if given else "its start (its home configuration)"
        raise UsageError(f"--ground: at {where} {model.name!r} starts "
                         f"{-distance[k]:.3g} m inside the ground (its shape "
                         f"{shape!r}); start it above the ground"
                         + ("" if model.floating_base else
                            " (a fixed base stays where its file puts it: z = 0 is the "
                            "ground, so a robot hanging below its base cannot stand on it)"))
    # the links it will stand on: those within 1 cm of the lowest shape
    support = tuple(sorted({int(link) for link, d in zip(found.link, distance, strict=True)
                            if d <= distance[k] + 0.01}))
    if args.soft is not None:  # soft soles (K41)
        mass = float(np.sum(model.body_mass))
        collisions = collisions.compliant(args.soft, 2.0 * math.sqrt(args.soft * mass),
                                          links=support)
    return world, collisions, q0, support


def _contact_summary(model, traj) -> dict:
    """The contacts of the last state and their total force next to the robot's weight."""
    from ..algorithms import center_of_mass

    force = np.nansum(traj.contact_forces[-1], axis=0)
    weight = float(np.sum(model.body_mass)) * 9.81
    com = np.asarray(center_of_mass(model, traj.q[-1]))
    return {"contacts_final": int(traj.contact_count[-1]), "contact_force_final": force,
            "weight": weight, "com_final": com}


def _urdf(robot: str, registry):
    kind, value, _ = registry.resolve(robot)
    return registry.robot_path(value) if kind == "name" else value


def _vec(x) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in x) + "]"


def _summary_text(s: dict, plot, html) -> str:
    rate = s["completed"] / s["wall_seconds"] if s["wall_seconds"] > 0 else math.inf
    lines = [f"cgadyn simulate: {s['robot']}, {s['base']} base, nq {s['nq']}, nv {s['nv']}, "
             f"{s['integrator']}, dt {s['dt']:g} s, {s['seconds']:g} s ({s['steps']} steps), "
             f"controller {s['controller']}"
             + (f", random controls (seed {s['seed']})" if s["seed"] is not None else ""),
             f"  simulated {s['completed']} steps in {s['wall_seconds']:.3g} s "
             f"({rate:.3g} steps/s), kept {s['states_kept']} states"
             + (f" (every {s['record_every']}th and the last)" if s["record_every"] > 1
                else ""),
             f"  q(end) = {_vec(s['q_final'])}",
             f"  v(end) = {_vec(s['v_final'])}",
             f"  energy E(0) = {s['energy_initial']:.10g} J, E(end) = "
             f"{s['energy_final']:.10g} J"]
    if s["ground"]:
        f = s["contact_force_final"]
        soles = "" if s["soft"] is None else f" (soft soles, {s['soft']:g} N/m a point)"
        lines.append(f"  ground{soles}: {s['contacts_final']} contacts at the end, their "
                     f"force {_vec(f)} N against the weight {s['weight']:.6g} N; centre of "
                     f"mass at {_vec(s['com_final'])} m")
    if s["energy_drift"] is not None:
        lines.append(f"  energy drift (passive run): max |E(t) - E(0)| / |E(0)| = "
                     f"{s['energy_drift']:.3e}")
    if plot is not None:
        lines.append(f"  plot: {plot}")
    if html is not None:
        lines.append(f"  animation: {html} (open it in a browser; it plays offline)")
    return "\n".join(lines)
