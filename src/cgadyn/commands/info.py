"""``cgadyn info``: a robot's joints (kind, coordinates, limits, body mass), links and mass,
its base and the sizes nq and nv, its actuators and tendons, an MJCF's static world, and
whether the C extension of fast single calls is there, as text or JSON."""

from __future__ import annotations

import argparse

import numpy as np

from .common import DEFAULT_ROBOT, ROBOT_HELP, add_base_options, floating_base, print_json

__all__ = ["add_parser", "format_info", "model_info", "native_extension", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("info", help="joints, limits, links, base and mass of a robot")
    p.add_argument("robot", nargs="?", default=DEFAULT_ROBOT, metavar="ROBOT",
                   help=f"{ROBOT_HELP} (default {DEFAULT_ROBOT})")
    p.add_argument("--json", action="store_true", help="print as JSON")
    add_base_options(p)
    p.set_defaults(func=run)


def _limits(values, j: int, idx) -> list[float]:
    return [float(x) for x in values[idx[j]:idx[j + 1]]]


def model_info(model) -> dict:
    """Base, sizes, joints (kind, parent, coordinates, limits, armature, damping,
    stiffness, body mass), links (with the joint they move with), actuators, fixed tendons'
    springs and dampers, couplings (``Σ coef q = offset``), ropes, total mass and
    home configuration (``Model.home``; ``home_is_neutral`` where it is the neutral one) of
    a model."""
    from ..algorithms import neutral

    def joint(j: int) -> dict:
        parent = int(model.parents[j])
        return {"name": model.joint_names[j], "kind": model.joint_kinds[j],
                "parent": None if parent < 0 else model.joint_names[parent],
                "q": [int(model.idx_q[j]), int(model.idx_q[j + 1])],
                "v": [int(model.idx_v[j]), int(model.idx_v[j + 1])],
                "lower": _limits(model.lower, j, model.idx_q),
                "upper": _limits(model.upper, j, model.idx_q),
                "velocity_limit": _limits(model.velocity_limit, j, model.idx_v),
                "effort_limit": _limits(model.effort_limit, j, model.idx_v),
                "armature": _limits(model.armature, j, model.idx_v),
                "damping": _limits(model.damping, j, model.idx_v),
                "stiffness": _limits(model.stiffness, j, model.idx_v),
                "body_mass": float(model.body_mass[j])}

    return {"robot": model.name, "base": "free flyer" if model.floating_base else "fixed",
            "nq": model.nq, "nv": model.nv, "njoints": model.njoints,
            "root_link": model.root_link, "total_mass": model.total_mass,
            "joints": [joint(j) for j in range(model.njoints)],
            "links": [{"name": n, "joint": None if model.link_joint[i] < 0
                       else model.joint_names[model.link_joint[i]]}
                      for i, n in enumerate(model.link_names)],
            "actuators": model.actuators, "tendons": [
                {"name": name, "joints": {model.joint_names[model.dof_joint[k]]: float(c[k])
                                          for k in np.flatnonzero(c)},
                 "stiffness": float(k_t), "damping": float(b_t),
                 "spring_length": [float(x) for x in length]}
                for name, c, k_t, b_t, length in zip(
                    model.tendon_names, model.tendon_coefficients, model.tendon_stiffness,
                    model.tendon_damping, model.tendon_spring_length, strict=True)],
            "couplings": [
                {"name": name, "joints": {model.joint_names[model.dof_joint[k]]: float(a[k])
                                          for k in np.flatnonzero(a)}, "offset": float(b)}
                for name, a, b in zip(model.coupling_names, model.coupling_coefficients,
                                      model.coupling_offset, strict=True)],
            "ropes": [
                {"name": name, "links": [model.link_names[k] if k >= 0 else "world"
                                         for k in links],
                 "points": [[float(x) for x in p] for p in points],
                 "range": [float(x) for x in bounds]}
                for name, links, points, bounds in zip(model.rope_names, model.rope_links,
                                                        model.rope_points, model.rope_range,
                                                        strict=True)],
            "home": [float(x) for x in model.home],
            "home_is_neutral": bool(np.array_equal(model.home, neutral(model)))}


def native_extension() -> dict:
    """Whether one-sample calls take the C extension ``cgadyn._native`` (``status``:
    loaded, missing or disabled) and, where not, what that costs and how to get it."""
    from ..algorithms import calls

    info = {"status": calls.NATIVE_STATUS, "fast_single_calls": calls.NATIVE_STATUS == "loaded"}
    if calls.NATIVE_STATUS != "loaded":
        info["note"] = calls.NATIVE_MISSING_ADVICE
    return info


def _range(lo: list[float], hi: list[float]) -> str:
    if len(lo) != 1:
        return f"{len(lo)} coordinates"
    return f"[{lo[0]:.4g}, {hi[0]:.4g}]"


def _most(values: list[float]) -> str:
    """A joint's armature, damping or stiffness in one column: its largest coordinate's."""
    return f"{max(values, default=0.0):.3g}"


def format_info(info: dict) -> str:
    """A readable listing of :func:`model_info`."""
    lines = [f"{info['robot']}: {info['base']} base, nq = {info['nq']}, nv = {info['nv']}, "
             f"{info['njoints']} joints, {len(info['links'])} links, root link "
             f"{info['root_link']}, moving mass {info['total_mass']:.4g} kg", "",
             f"{'#':>3}  {'joint':<28}{'kind':<12}{'q':>8}{'v':>8}  {'limits':<22}"
             f"{'mass':>9}{'armature':>10}{'damping':>9}{'spring':>8}  parent"]
    for j, jt in enumerate(info["joints"]):
        q = f"{jt['q'][0]}:{jt['q'][1]}"
        v = f"{jt['v'][0]}:{jt['v'][1]}"
        lines.append(f"{j:>3}  {jt['name']:<28}{jt['kind']:<12}{q:>8}{v:>8}  "
                     f"{_range(jt['lower'], jt['upper']):<22}{jt['body_mass']:>9.4g}"
                     f"{_most(jt['armature']):>10}{_most(jt['damping']):>9}"
                     f"{_most(jt['stiffness']):>8}  {jt['parent'] or 'world'}")
    if not info.get("home_is_neutral", True):
        lines += ["", "home configuration (the file's qpos0; cgadyn simulate starts there): "
                  "[" + ", ".join(f"{x:.4g}" for x in info["home"]) + "]"]
    lines += ["", f"{'link':<36}moves with joint"]
    lines += [f"{lk['name']:<36}{lk['joint'] or '(fixed to world)'}" for lk in info["links"]]
    if info.get("actuators"):
        lines += ["", f"{'actuator':<28}{'joint or tendon':<28}{'gear':>9}  {'kind':<36}"
                  f"control range"]
        lines += [f"{a['name']:<28}{a['joint'] or 'tendon ' + a['tendon']:<28}"
                  f"{a['gear']:>9.4g}  {_kind(a):<36}"
                  f"{_range([a['ctrlrange'][0]], [a['ctrlrange'][1]])}"
                  for a in info["actuators"]]
    if info.get("tendons"):
        lines += ["", f"{'tendon (fixed)':<28}{'stiffness':>10}{'damping':>9}  relaxed length"
                  f"  length = Σ coef q"]
        lines += [f"{t['name']:<28}{t['stiffness']:>10.4g}{t['damping']:>9.4g}  "
                  f"{_range([t['spring_length'][0]], [t['spring_length'][1]]):<16}"
                  + " + ".join(f"{c:.4g} {j}" for j, c in t["joints"].items())
                  for t in info["tendons"]]
    if info.get("couplings"):
        lines += ["", f"{'coupling':<28}Σ coef q = offset (held by the contact step)"]
        lines += [f"{c['name']:<28}"
                  + " + ".join(f"{x:.4g} {j}" for j, x in c["joints"].items())
                  + f" = {c['offset']:.6g}" for c in info["couplings"]]
    if info.get("ropes"):
        lines += ["", f"{'rope':<28}{'between':<36}length (held by the contact step)"]
        lines += [f"{r['name']:<28}{' and '.join(r['links']):<36}"
                  f"{_range([r['range'][0]], [r['range'][1]])}" for r in info["ropes"]]
    world = info.get("world")
    if world is not None:
        ground = world["ground"]
        lines += ["", "world (the MJCF's static geoms; a cgadyn.World given to simulate "
                  "replaces it):",
                  "  ground: " + ("none" if ground is None else
                                  f"height {ground['height']:.4g} m, normal "
                                  f"{_vector(ground['normal'])}, friction "
                                  f"{ground['friction']:.4g}")]
        lines += [f"  {o['name']:<26}{o['shape']:<44}at {_vector(o['position'])}"
                  for o in world["obstacles"]]
    native = info.get("native_extension")
    if native is not None:
        lines += ["", f"C extension (fast single calls): {native['status']}"]
        if "note" in native:
            lines.append(f"  {native['note']}")
    return "\n".join(lines)


def world_info(model, robot) -> dict | None:
    """The static world of an MJCF ``robot`` (``contact.static_world``, K44): its ground
    (height, normal, friction) and its obstacles (name, shape, position; a plane a wall);
    None for a URDF, or where its MJCF has no world (contacts off: warned on reading)."""
    from ..contact.model import collision_model
    from ..contact.static_world import default_world
    from ..multibody import registry

    if registry.resolve(robot)[0] != "mjcf":
        return None
    world = default_world(collision_model(model, robot))
    if world is None:
        return None
    return {"ground": {"height": world.ground_height, "normal": list(world.ground_normal),
                       "friction": world.friction} if world.ground else None,
            "obstacles": [{"name": o.name, "shape": _shape(o), "position": list(o.position)}
                          for o in world.obstacles]}


def _shape(obstacle) -> str:
    """An obstacle's shape; a plane as a wall with its normal in the world."""
    from ..contact.shapes import PLANE

    shape = obstacle.shape
    if shape.kind != PLANE:
        return repr(shape)
    n = obstacle.pose[:3, :3] @ shape.placement[:3, :3] @ shape.normal
    return f"wall, facing {_vector(n.tolist())}"


def run(args: argparse.Namespace) -> int:
    from ..multibody import registry

    model = registry.load(args.robot, floating_base=floating_base(args))
    info = model_info(model)
    info["world"] = world_info(model, args.robot)
    info["native_extension"] = native_extension()
    print_json(info) if args.json else print(format_info(info))
    return 0


def _kind(actuator: dict) -> str:
    """An actuator's kind by its gain and bias (A1): a motor, a position servo ``kp`` (and
    ``kv``), a velocity servo ``kv``, or its force law; then its activation dynamics (A2),
    a filter with its time constant."""
    return _law(actuator) + {"none": "", "integrator": ", integrator"}.get(
        actuator["dynamics"], f", {actuator['dynamics']} {actuator['time_constant']:.4g} s")


def _law(actuator: dict) -> str:
    gain, (b0, b1, b2) = actuator["gain"], actuator["bias"]
    if (gain, b0, b1, b2) == (1.0, 0.0, 0.0, 0.0):
        return "motor"
    if b0 == 0.0 and b1 == -gain and b1 != 0.0:
        return f"position kp {gain:.4g}" + (f" kv {-b2:.4g}" if b2 else "")
    if b0 == 0.0 and b1 == 0.0 and b2 == -gain and b2 != 0.0:
        return f"velocity kv {gain:.4g}"
    return f"{gain:.4g} u{b0:+.4g}{b1:+.4g} L{b2:+.4g} L'"


def _vector(x: list[float]) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in x) + ")"
