"""Reproduce the Appendix B checks of Dorst & De Keninck, "May the Forque be with You".

Integrates the PGA law of motion (Table 2.1) with RK4 and compares with the closed forms:
B.1 split equations, B.2 spherical top (B.5-B.6), B.3 symmetric top (B.15), B.4 tennis
racket (middle-axis instability), plus energy conservation of the hypercube on a spring in
d = 1..4. Writes validation/results/appendix_b*.png and appendix_b.md.

    /work/main/.venv/bin/python validation/appendix_b.py
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cgadyn.pga import Inertia, RigidBody, dynamics, pga  # noqa: E402
from cgadyn.pga.free_tops import (  # noqa: E402
    spherical_top,
    split_free_derivative,
    symmetric_top_motor,
)
from cgadyn.pga.simulate import hypercube_on_spring, simulate  # noqa: E402

OUT = Path(__file__).parent / "results"


def b1() -> list[str]:
    rows = []
    for d in (1, 2, 3, 4):
        m = pga(d)
        rng = np.random.default_rng(d)
        moments = rng.uniform(0.5, 2.0, size=len(m.eij))
        b = m.grade(rng.normal(size=(100, m.n)), 2)
        err = np.abs(dynamics(Inertia.principal(m, 1.3, moments), b, m.zeros())
                     - split_free_derivative(m, moments, b)).max()
        rows.append(f"| {d} | {err:.1e} |")
    return rows


def b2_b3(h: float = 0.01, duration: float = 10.0) -> list[str]:
    m = pga(3)
    m0 = m.motor(rotation=[0.3, -0.2, 0.5], translation=[1.0, 2.0, 3.0])
    b0 = m.translation_rate([0.4, -0.3, 0.2]) + m.rotation_rate([1.0, 0.7, -0.4])
    steps = int(round(duration / h))
    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    cases = [("B.2 spherical top (B.6)", [0.8, 0.8, 0.8], None),
             ("B.3 symmetric top i3=3i (B.15)", [3.0, 1.0, 1.0], 3.0),
             ("B.3 symmetric top i3=0.4i (B.15)", [0.4, 1.0, 1.0], 0.4)]
    probe = m.point([0.3, 0.1, 0.6])
    for ax, (name, moments, i3) in zip(axes, cases, strict=True):
        body = RigidBody(Inertia.principal(m, 2.0, moments))
        run = simulate(body, None, m0, b0, h, steps, "rk4")
        if i3 is None:
            exact = np.array([spherical_top(m, m0, b0, t)[0] for t in run["t"]])
        else:
            exact = np.array([symmetric_top_motor(m, 1.0, i3, m0, b0, t) for t in run["t"]])
        err = np.abs(run["M"] - exact).max(axis=1)
        rows.append(f"| {name} | {h} | {duration} | {err.max():.1e} |")
        xs = m.coords(m.sandwich(run["M"], probe))
        xe = m.coords(m.sandwich(exact[::25], probe))
        ax.plot(xs[:, 0], xs[:, 1], label="RK4")
        ax.plot(xe[:, 0], xe[:, 1], "k.", ms=3, label="closed form")
        ax.set_title(f"{name}\nmax |M_rk4 - M_exact| = {err.max():.1e}", fontsize=9)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT / "appendix_b_tops.png", dpi=100)
    plt.close(fig)
    return rows


def b4(h: float = 0.01, duration: float = 20.0) -> list[str]:
    m = pga(3)
    i = np.array([3.0, 2.0, 1.0])
    body = RigidBody(Inertia.principal(m, 1.0, i[::-1]))
    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(14, 3.6), sharey=True)
    for axis, ax in enumerate(axes):
        bk = np.full(3, 1e-3)
        bk[axis] = 2.0
        run = simulate(body, None, m.scalar(), m.rotation_rate([bk[2], -bk[1], bk[0]]), h,
                       int(round(duration / h)), "rk4")
        _, p = m.split_rate(run["B"])
        bks = np.stack([p[:, 2], -p[:, 1], p[:, 0]], 1)
        dev = np.abs(np.delete(bks, axis, axis=1)).max()
        verdict = "unstable" if dev > 0.5 else "stable"
        rows.append(f"| E{axis + 1} (i = {i[axis]:g}) | {dev:.2e} | {verdict} |")
        for k in range(3):
            ax.plot(run["t"], bks[:, k], label=f"B_b{k + 1}")
        ax.set_title(f"spin about E{axis + 1} (i={i[axis]:g}): {verdict}", fontsize=9)
        ax.set_xlabel("t [s]")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT / "appendix_b_tennis_racket.png", dpi=100)
    plt.close(fig)
    return rows


def energy(h: float = 0.005, duration: float = 20.0) -> list[str]:
    rows = []
    fig, ax = plt.subplots(figsize=(7, 4))
    for d in (1, 2, 3, 4):
        run = hypercube_on_spring(d, steps=int(round(duration / h)), dt=h, integrator="rk4",
                                  contact=False, damping=False)
        s, tr = run["summary"], run["trajectory"]
        rel = np.abs(tr["energy"] - tr["energy"][0]) / tr["energy"][0]
        worst = s["energy_max_deviation"] / s["energy_initial"]
        rows.append(f"| {d} | {h} | {duration} | {worst:.1e} | {s['motor_norm_error']:.1e} |")
        ax.semilogy(tr["t"][1:], rel[1:] + 1e-18, label=f"d={d}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|E(t) - E(0)| / E(0)")
    ax.set_title(f"hypercube on a spring, RK4 h={h}, no damping/contact")
    ax.legend()
    fig.tight_layout()
    fig.savefig(OUT / "appendix_b_energy.png", dpi=100)
    plt.close(fig)
    return rows


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    lines = [
        "# Appendix B checks (PGA free rigid bodies)",
        "",
        "Generated by `validation/appendix_b.py`: the PGA law of motion (Table 2.1) integrated "
        "with RK4 and motor renormalisation, against the closed forms of Dorst & De Keninck, "
        "Appendix B.",
        "",
        "## B.1: free motion splits into (B.2)",
        "",
        "max |I^-1[B × I[B]] - (eps(-v.**B**) + I_C^-1[**B** × I_C[**B**]])| over 100 random B:",
        "",
        "| d | max error |",
        "|---|---|",
        *b1(),
        "",
        "## B.2, B.3: spherical and symmetric top (3D, with translation, M0 != 1)",
        "",
        "| case | h | duration [s] | max motor error |",
        "|---|---|---|---|",
        *b2_b3(),
        "",
        "![tops](appendix_b_tops.png)",
        "",
        "## B.4: non-symmetric top, i = (3, 2, 1), spin 2 rad/s + 1e-3 perturbation, 20 s",
        "",
        "| spin axis | max other rate | verdict |",
        "|---|---|---|",
        *b4(),
        "",
        "![tennis racket](appendix_b_tennis_racket.png)",
        "",
        "## Energy: hypercube on a spring, gravity, no damping, no contact",
        "",
        "| d | h | duration [s] | max relative energy error | max abs(M M~ - 1) |",
        "|---|---|---|---|---|",
        *energy(),
        "",
        "![energy](appendix_b_energy.png)",
        "",
    ]
    lines.append(f"Total run time {time.perf_counter() - t0:.0f} s.")
    (OUT / "appendix_b.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
