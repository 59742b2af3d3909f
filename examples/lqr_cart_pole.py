"""Balance a cart-pole upright with LQR, linearised by ``cgadyn.aba_derivatives``.

The robot is ``robots/cart_pole.urdf``: a cart on a rail (prismatic joint ``cart_slide``,
effort limit 50 N) carrying a pole on a hinge (continuous joint ``pole_hinge``, no effort
limit declared). The actuated coordinates are those of the joints whose URDF ``<limit>``
declares a finite effort: the cart only; the hinge is passive. With q = 0 the pole points
up (its centre of mass 0.5 m above the hinge), an unstable equilibrium.

1. Linearise forward dynamics at the upright equilibrium (q0, v = 0, τ0 = rnea(q0, 0, 0)),
   with the state x = (δq, v), δq = q ⊖ q0 in the tangent space::

       ẋ = A x + B u,   A = [[0, 1], [∂q̈/∂q, ∂q̈/∂v]],   B = [[0], [∂q̈/∂τ[:, actuated]]]

   and check ∂q̈/∂q, ∂q̈/∂v against central finite differences of ``cgadyn.aba`` (through
   ``cgadyn.integrate``).
2. Solve the continuous algebraic Riccati equation (``scipy.linalg.solve_continuous_are``),
   ``K = R⁻¹ Bᵀ P``.
3. Simulate the closed loop ``u = -K x`` (held over each step) with ``cgadyn.aba`` and
   semi-implicit Euler on the configuration manifold (``v += dt q̈``,
   ``q = integrate(q, dt v)``) from a tilted start, and plot it.

Needs scipy (``pip install "cgadyn[examples]"``); matplotlib for the plot::

    python examples/lqr_cart_pole.py [--seconds 6] [--dt 0.001] [--perturbation 0.3]
                                     [--plot validation/results/lqr_cart_pole.png]

``run(seconds, dt, perturbation)`` does steps 1-3 without printing or plotting and returns a
dict of the results, for tests.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import cgadyn

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_PLOT = ROOT / "validation" / "results" / "lqr_cart_pole.png"
Q_WEIGHTS = (10.0, 100.0, 1.0, 10.0)
"""LQR state weights: cart position, pole angle, cart velocity, pole rate."""
R_WEIGHT = 0.1
"""LQR input weight on the cart force."""


def load_model():
    """The cart-pole from cgadyn's registry (``robots/`` of a checkout, or the wheel's copy)."""
    return cgadyn.load("cart_pole")


def actuated_coordinates(model) -> np.ndarray:
    """Velocity indices of the joints whose URDF declares a finite, positive effort limit."""
    coords = []
    for j in range(model.njoints):
        effort = model.effort_limit[j]
        if np.isfinite(effort) and effort > 0.0:
            coords.extend(range(model.idx_v[j], model.idx_v[j + 1]))
    if not coords:
        raise ValueError(f"{model.name}: no joint declares a finite effort limit; "
                         "nothing to actuate")
    return np.array(coords, dtype=int)


def equilibrium(model, q0):
    """``τ0 = rnea(q0, 0, 0)``, the torques that hold q0 at rest; raises if a passive
    coordinate would need one (q0 is then not an equilibrium the actuators can hold)."""
    nv = model.nv
    tau0 = cgadyn.rnea(model, q0, np.zeros(nv), np.zeros(nv))
    passive = np.setdiff1d(np.arange(nv), actuated_coordinates(model))
    if np.any(np.abs(tau0[passive]) > 1e-9):
        raise ValueError(f"q0 = {q0} is not an equilibrium: the passive coordinates "
                         f"{passive.tolist()} would need torques {tau0[passive]}")
    return tau0


def linearise(model, q0, v0, tau0):
    """``(A, B)`` of ``ẋ = A x + B u`` at (q0, v0, τ0) from ``cgadyn.aba_derivatives``; u
    the torques of the actuated coordinates."""
    nv = model.nv
    dq, dv, minv = cgadyn.aba_derivatives(model, q0, v0, tau0)
    act = actuated_coordinates(model)
    A = np.block([[np.zeros((nv, nv)), np.eye(nv)], [dq, dv]])
    B = np.vstack([np.zeros((nv, len(act))), minv[:, act]])
    return A, B


def finite_difference_jacobians(model, q, v, tau, eps: float = 1e-6):
    """Central differences of ``aba``: ``∂q̈/∂q`` along ``integrate(q, ±eps e_l)`` (the
    tangent space, as ``aba_derivatives``) and ``∂q̈/∂v``."""
    nv = model.nv
    dq = np.empty((nv, nv))
    dv = np.empty((nv, nv))
    for l in range(nv):
        e = np.zeros(nv)
        e[l] = eps
        qp, qm = cgadyn.integrate(model, q, e), cgadyn.integrate(model, q, -e)
        dq[:, l] = (cgadyn.aba(model, qp, v, tau) - cgadyn.aba(model, qm, v, tau)) / (2 * eps)
        dv[:, l] = (cgadyn.aba(model, q, v + e, tau) - cgadyn.aba(model, q, v - e, tau)) / (2 * eps)
    return dq, dv


def linearisation_error(model, q, v, tau, eps: float = 1e-6) -> float:
    """Largest difference between ``aba_derivatives`` and central finite differences."""
    dq, dv, _ = cgadyn.aba_derivatives(model, q, v, tau)
    fq, fv = finite_difference_jacobians(model, q, v, tau, eps)
    return float(max(np.abs(dq - fq).max(), np.abs(dv - fv).max()))


def lqr_gain(A, B, Q, R):
    """``K = R⁻¹ Bᵀ P`` with P the stabilising solution of the continuous Riccati equation
    ``Aᵀ P + P A - P B R⁻¹ Bᵀ P + Q = 0``."""
    try:
        from scipy.linalg import solve_continuous_are
    except ImportError:
        raise ImportError(
            "examples/lqr_cart_pole.py needs scipy to solve the Riccati equation: "
            "pip install 'cgadyn[examples]' (or pip install scipy)") from None
    P = solve_continuous_are(A, B, Q, R)
    return np.linalg.solve(R, B.T @ P)


def simulate(model, q0, tau0, K, x0, seconds: float, dt: float):
    """The closed loop ``τ = τ0 + u``, ``u = -K x`` on the actuated coordinates, integrated
    with semi-implicit Euler; returns times, states x = (q ⊖ q0, v) and inputs u."""
    nv = model.nv
    act = actuated_coordinates(model)
    steps = int(round(seconds / dt))
    q = cgadyn.integrate(model, q0, x0[:nv])
    v = np.array(x0[nv:], dtype=float)
    t = np.arange(steps + 1) * dt
    xs = np.empty((steps + 1, 2 * nv))
    us = np.empty((steps + 1, len(act)))
    tau = tau0.copy()
    for i in range(steps + 1):
        x = np.concatenate([cgadyn.difference(model, q0, q), v])
        u = -K @ x
        xs[i], us[i] = x, u
        if i == steps:
            break
        tau[act] = tau0[act] + u
        v = v + dt * cgadyn.aba(model, q, v, tau)
        q = cgadyn.integrate(model, q, dt * v)
    return t, xs, us


def run(seconds: float = 6.0, dt: float = 1e-3, perturbation=0.3, gain=None) -> dict:
    """Linearise, design the LQR gain and simulate the closed loop.

    ``perturbation``: the start's deviation from upright: a number is the pole's tilt in
    radians (the cart at rest at the origin), an array the whole state (δq, v) (2 nv).
    ``gain``: a gain K to use instead of the LQR one (e.g. zeros, to watch the pole fall).
    Returns the model, the linearisation (A, B), its error against finite differences at
    the equilibrium and at the start, K, the closed-loop eigenvalues, the trajectory, the
    initial and final state error (2-norm of x), the largest |u| and the effort limits of
    the actuated joints.
    """
    model = load_model()
    nv = model.nv
    q0, v0 = np.zeros(model.nq), np.zeros(nv)
    tau0 = equilibrium(model, q0)
    A, B = linearise(model, q0, v0, tau0)
    if np.ndim(perturbation) == 0:
        x0 = np.zeros(2 * nv)
        x0[model.idx_v[model.joint_index("pole_hinge")]] = float(perturbation)
    else:
        x0 = np.asarray(perturbation, dtype=float)
        if x0.shape != (2 * nv,):
            raise ValueError(f"perturbation: a number (the pole's tilt) or a state of "
                             f"{2 * nv} values (δq, v), got shape {x0.shape}")
    if gain is None:
        K = lqr_gain(A, B, np.diag(Q_WEIGHTS), np.array([[R_WEIGHT]]))
    else:
        K = np.asarray(gain, dtype=float).reshape(B.shape[1], 2 * nv)
    q_start = cgadyn.integrate(model, q0, x0[:nv])
    tau_start = tau0.copy()
    tau_start[actuated_coordinates(model)] += -K @ x0
    t, xs, us = simulate(model, q0, tau0, K, x0, seconds, dt)
    act = actuated_coordinates(model)
    return {
        "model": model,
        "A": A,
        "B": B,
        "fd_error_equilibrium": linearisation_error(model, q0, v0, tau0),
        "fd_error_start": linearisation_error(model, q_start, x0[nv:], tau_start),
        "K": K,
        "open_loop_eigenvalues": np.linalg.eigvals(A),
        "closed_loop_eigenvalues": np.linalg.eigvals(A - B @ K),
        "t": t,
        "x": xs,
        "u": us,
        "initial_error": float(np.linalg.norm(xs[0])),
        "final_error": float(np.linalg.norm(xs[-1])),
        "max_abs_u": float(np.abs(us).max()),
        "effort_limit": model.effort_limit[model.dof_joint[act]],
        "actuated": act,
    }


def plot(result: dict, path) -> Path:
    """Save the trajectory (cart position, pole angle, cart force) to ``path`` (Agg)."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("plotting needs matplotlib: pip install 'cgadyn[examples]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, x, u = result["t"], result["x"], result["u"]
    fig, axes = plt.subplots(3, 1, figsize=(6, 5), sharex=True)
    axes[0].plot(t, x[:, 0], color="tab:blue")
    axes[0].set_ylabel("cart x [m]")
    axes[1].plot(t, np.degrees(x[:, 1]), color="tab:orange")
    axes[1].set_ylabel("pole tilt [deg]")
    axes[2].plot(t, u[:, 0], color="tab:green")
    axes[2].set_ylabel("cart force [N]")
    axes[2].set_xlabel("time [s]")
    for ax in axes:
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.grid(alpha=0.3)
    axes[0].set_title(f"LQR cart-pole from {np.degrees(x[0, 1]):.0f}° tilt: "
                      f"|x(T)| = {result['final_error']:.1e}")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=6.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--perturbation", type=float, default=0.3,
                        help="initial tilt of the pole from upright [rad]")
    parser.add_argument("--plot", default=str(DEFAULT_PLOT), help="where to save the figure")
    args = parser.parse_args(argv)
    try:
        r = run(args.seconds, args.dt, args.perturbation)
    except ImportError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    np.set_printoptions(precision=4, suppress=True)
    print(f"model {r['model'].name}: joints {r['model'].joint_names}, "
          f"actuated coordinates {r['actuated'].tolist()}")
    print("linearisation at upright, A =")
    print(r["A"])
    print(f"B = {r['B'][:, 0]}")
    print(f"aba_derivatives vs central differences of aba: max error "
          f"{r['fd_error_equilibrium']:.1e} at upright, {r['fd_error_start']:.1e} at the start")
    print(f"open-loop eigenvalues  {np.sort_complex(r['open_loop_eigenvalues'])}")
    print(f"K = {r['K'][0]}")
    print(f"closed-loop eigenvalues {np.sort_complex(r['closed_loop_eigenvalues'])}")
    print(f"simulated {args.seconds} s, dt {args.dt}: |x(0)| = {r['initial_error']:.3f}, "
          f"|x(T)| = {r['final_error']:.2e}, max |u| = {r['max_abs_u']:.2f} N "
          f"(effort limit {r['effort_limit'][0]:.0f} N)")
    try:
        print(f"plot: {plot(r, args.plot)}")
    except ImportError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
