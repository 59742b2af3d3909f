"""Time stepping with contact, and the paper's demo: a hypercube on a spring under gravity,
with damping and floor contact (figs. 2.4 and 2.5, sections 2.5.7 and 2.6.1), in any d.
"""

from __future__ import annotations

import numpy as np

from .body import RigidBody, check_state, hypercube
from .contact import contact_impulse, normal_velocity, penetrations
from .energy import kinetic_energy, potential_energy
from .forques import Damping, Forques, Gravity, Hooke
from .integrators import get_integrator, step
from .model import check_dimension

__all__ = ["hypercube_on_spring", "simulate"]


def simulate(
    body: RigidBody,
    forque,
    m0,
    b0,
    h: float,
    steps: int,
    integrator: str = "rk4",
    floor=None,
    restitution: float = 0.5,
) -> dict:
    """Integrate ``steps`` steps of size h; returns arrays t, M, B, kinetic, potential.

    With a ``floor`` hyperplane (world frame), each step that leaves a vertex below the floor
    is undone, the impulse eqs. (2.32)-(2.33) is applied at the deepest vertex still moving
    into the floor, and the step is taken again (section 2.6.1), at most 2^d times a step.
    """
    get_integrator(integrator)
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
        raise ValueError(f"steps must be an integer >= 0, got {steps!r}")
    model = body.model
    m, b = check_state(model, m0, b0)
    ms, bs, contacts = [m], [b], 0
    for i in range(int(steps)):
        t = i * h
        m1, b1 = step(body, forque, m, b, h, t, integrator)
        if floor is not None:
            for _ in range(2**model.d):
                idx, _ = penetrations(body, m1, floor)
                hit = next((k for k in idx if normal_velocity(
                    model, m, b, model.point(body.vertices[k]), floor) < 0), None)
                if hit is None:
                    break
                b, _ = contact_impulse(body, m, b, body.vertices[hit], floor, restitution)
                contacts += 1
                m1, b1 = step(body, forque, m, b, h, t, integrator)
        m, b = m1, b1
        if not (np.all(np.isfinite(m)) and np.all(np.isfinite(b))):
            raise ValueError(f"simulation diverged at step {i + 1} (h={h} too large?)")
        ms.append(m)
        bs.append(b)
    ms, bs = np.array(ms), np.array(bs)
    return {
        "t": h * np.arange(len(ms)),
        "M": ms,
        "B": bs,
        "kinetic": kinetic_energy(body.inertia, bs),
        "potential": np.array([potential_energy(forque, mm) for mm in ms]),
        "contacts": contacts,
    }


def hypercube_on_spring(
    d: int = 3,
    steps: int = 600,
    dt: float = 1 / 600,
    integrator: str = "rk4",
    contact: bool = True,
    damping: bool = True,
    k: float = 12.0,
    alpha: float = 0.25,
    floor_height: float = -0.6,
    restitution: float = 0.5,
) -> dict:
    """The unit hypercube of figs. 2.4/2.5: mass 1, edges 1, its vertex (½, ..., ½) on a
    spring (k = 12) to the world point one unit above it, gravity 9.81 down, damping
    F_d = *(-0.25 B), initial rate 1 e12 + 1.3 e13 + 0.5 e24 (the blades that exist in d),
    and a floor at ``floor_height``. 'Up' is e2 as in the paper's demos (e1 for d = 1).

    Returns a dict: 'summary' (JSON-ready scalars and the final state) and 'trajectory'
    (t, centroid, spring vertex, height of the lowest vertex, kinetic/potential/total
    energy arrays).
    """
    d = check_dimension(d)
    get_integrator(integrator)
    if not np.isfinite(dt) or dt <= 0:
        raise ValueError(f"time step dt must be finite and > 0, got {dt}")
    body = hypercube(d)
    model = body.model
    up = np.eye(d)[min(d, 2) - 1]
    corner = np.full(d, 0.5)
    parts = [Gravity(body.inertia, -9.81 * up), Hooke(model, corner, corner + up, k)]
    if damping:
        parts.append(Damping(model, alpha))
    forque = Forques(*parts)
    b0 = model.zeros()
    for name, value in (("e12", 1.0), ("e13", 1.3), ("e24", 0.5)):
        if name in model.algebra.blade_names:
            b0[model.algebra.blade(name)] = value
    floor = model.hyperplane(up, floor_height) if contact else None
    run = simulate(body, forque, model.scalar(), b0, dt, steps, integrator, floor, restitution)
    ms = run["M"]
    centroid = model.coords(model.sandwich(ms, model.origin))
    vertex = model.coords(model.sandwich(ms, model.point(corner)))
    lowest = model.coords(model.sandwich(ms[:, None, :], model.point(body.vertices)))
    lowest = lowest[..., int(np.argmax(up))].min(axis=1)
    energy = run["kinetic"] + run["potential"]
    norm_err = np.abs(model.gp(ms, model.reverse(ms)) - model.scalar()).max()
    summary = {
        "dim": d,
        "steps": int(steps),
        "dt": float(dt),
        "duration": float(steps * dt),
        "integrator": integrator,
        "contact": bool(contact),
        "damping": bool(damping),
        "contacts": int(run["contacts"]),
        "floor_height": float(floor_height) if contact else None,
        "lowest_height": float(lowest.min()),
        "final_centroid": centroid[-1].tolist(),
        "final_motor": {n: float(c) for n, c in zip(model.algebra.blade_names, ms[-1],
                                                     strict=True) if c != 0.0},
        "final_rate": {n: float(c) for n, c in zip(model.algebra.blade_names, run["B"][-1],
                                                    strict=True) if c != 0.0},
        "energy_initial": float(energy[0]),
        "energy_final": float(energy[-1]),
        "energy_drift": float(energy[-1] - energy[0]),
        "energy_max_deviation": float(np.abs(energy - energy[0]).max()),
        "motor_norm_error": float(norm_err),
    }
    trajectory = {
        "t": run["t"],
        "centroid": centroid,
        "vertex": vertex,
        "lowest": lowest,
        "kinetic": run["kinetic"],
        "potential": run["potential"],
        "energy": energy,
        "up_axis": int(np.argmax(up)),
    }
    return {"summary": summary, "trajectory": trajectory}
