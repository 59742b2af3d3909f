"""Actuators: the generalised torques of a control vector (MuJoCo's ``qfrc_actuator`` of
``<motor>``, ``<position>`` and ``<velocity>`` on a hinge, a slide or a fixed tendon;
``docs/joints.md``, A1).

    L_a = w_a · q,   L̇_a = w_a · v                       the actuator's length and rate
    f_a = clamp(g_a clamp(u_a, ctrlrange_a) + b₀ + b₁ L_a + b₂ L̇_a, forcerange_a)
    τ  += w_a f_a                                                                   (A1)

for each actuator a of ``Model.actuators``, whose moment arm ``w_a`` (nv) is its gear on
the coordinate it drives (``Model.actuator_dof``), or its gear times the Jacobian ``c_t`` of
the fixed tendon it pulls (``actuator_tendon``, ``Model.tendon_coefficients``); ``g_a`` and
``b`` are ``Model.actuator_gain`` and ``actuator_bias`` (a motor: 1 and 0; a position servo:
``kp`` and ``(0, -kp, -kv)``). MuJoCo clamps the control, then the force; cgadyn's models
clamp a force only where it does not depend on the state (``Model._check_actuators``).

An actuator with activation dynamics (``Model.actuator_dynamics``) takes its activation
``w_a`` in place of the clamped control, a state of its own that the control moves, one
step ``dt`` at a time, as MuJoCo's Euler step moves ``act``:

    integrator:   w⁺ = w + dt u
    filter:       w⁺ = w + dt (u - w) / T
    filterexact:  w⁺ = w + (u - w) (1 - exp(-dt / T))
    w⁺ ← clamp(w⁺, actrange)                                                        (A2)

(``u`` the control clamped to ``ctrlrange``; ``activations``). The force of step n takes
``w_n``, the activation at the step's start, and holds it over the step (MuJoCo's RK4
moves ``act`` within the step too: with ``integrator="rk4"`` the two differ by O(dt) in
the activation).

A servo's state-dependent part ``w_a (b₁ L_a + b₂ L̇_a)`` is a spring of stiffness ``-b₁``
and a damper ``-b₂`` along ``w_a``, a tendon of rest length 0 (``passive``, P2):
``simulate(ctrl=...)`` adds the control's part ``w_a clamp(g_a u_a + b₀)`` to its torques
and that spring to the compiled loop's tendons (``actuator_springs``). Plain numpy.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints.table import additive_values
from ._inputs import time_step


def actuator_moments(model) -> np.ndarray:
    """(na, nv): each actuator's moment arm ``w_a`` (A1): its gear on its coordinate, or
    its gear times its tendon's coefficients."""
    W = np.zeros((len(model.actuator_names), model.nv))
    for a, gear in enumerate(model.actuator_gear):
        t = int(model.actuator_tendon[a])
        if t >= 0:
            W[a] = gear * model.tendon_coefficients[t]
        else:
            W[a, model.actuator_dof[a]] = gear
    return W


def state_dependent(model) -> np.ndarray:
    """(na,) bool: the actuators whose force depends on their length or rate (a servo)."""
    return np.any(model.actuator_bias[:, 1:] != 0.0, axis=1)


def _controls(model, ctrl) -> np.ndarray:
    na = len(model.actuator_names)
    try:
        u = np.asarray(ctrl, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"ctrl must be an array of numbers, got {type(ctrl).__name__}") \
            from None
    if u.ndim == 0 or u.shape[-1] != na:
        raise ValueError(f"ctrl must have {na} entries per sample (one per actuator of "
                         f"{model.name!r}: {', '.join(model.actuator_names) or 'none'}), "
                         f"got shape {u.shape}")
    if not np.all(np.isfinite(u)):
        raise ValueError("ctrl has entries that are not finite; expected finite controls")
    return np.clip(u, model.actuator_ctrlrange[:, 0], model.actuator_ctrlrange[:, 1])


def dynamic(model) -> np.ndarray:
    """(na,) bool: the actuators with an activation state (``Model.actuator_dynamics``)."""
    return np.array([k != "none" for k in model.actuator_dynamics], dtype=bool)


def _activation(model, act, shape: tuple) -> np.ndarray:
    """``act`` (None: zeros, MuJoCo's ``act`` after a reset) checked against ``shape``."""
    na = len(model.actuator_names)
    if act is None:
        return np.zeros(shape)
    try:
        w = np.asarray(act, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"act must be an array of numbers, got {type(act).__name__}") \
            from None
    if w.ndim == 0 or w.shape[-1] != na or not np.all(np.isfinite(w)):
        raise ValueError(f"act must hold {na} finite activations per sample (one per "
                         f"actuator of {model.name!r}, 0 for those without activation "
                         f"dynamics), got shape {w.shape}")
    return np.broadcast_to(w, shape).astype(float)


def activations(model, ctrl, dt: float, act=None) -> np.ndarray:
    """The activations ``w_0 .. w_steps`` (..., steps + 1, na) that the controls ``ctrl``
    (..., steps, na), each held over a step of ``dt``, give from ``act`` (..., na) (zeros by
    default) by A2; 0 for the actuators without activation dynamics."""
    u = _controls(model, ctrl)
    if u.ndim < 2:
        raise ValueError(f"ctrl must be a sequence of controls (steps, na), got shape "
                         f"{u.shape}")
    step = time_step(dt)
    kinds = np.array(model.actuator_dynamics)
    T = np.where(model.actuator_time_constant > 0.0, model.actuator_time_constant, 1.0)
    rate = np.select([kinds == "filter", kinds == "filterexact"],
                     [step / T, -np.expm1(-step / T)], 0.0)  # the filters' gain per step
    lo, hi = model.actuator_actrange[:, 0], model.actuator_actrange[:, 1]
    on = dynamic(model)
    batch = u.shape[:-2] if act is None else _samples(u.shape[:-2], np.shape(act)[:-1])
    u = np.broadcast_to(u, batch + u.shape[-2:])
    out = np.zeros(batch + (u.shape[-2] + 1, u.shape[-1]))
    w = _activation(model, act, batch + u.shape[-1:]) * on
    out[..., 0, :] = w
    for n in range(u.shape[-2]):
        un = u[..., n, :]
        w = np.where(kinds == "integrator", w + step * un, w + rate * (un - w))
        w = np.clip(w, lo, hi) * on
        out[..., n + 1, :] = w
    return out


def _driving(model, u: np.ndarray, act) -> np.ndarray:
    """What each actuator's force takes (A1, A2): its activation where it has activation
    dynamics (``act``, required then), else its clamped control ``u``."""
    on = dynamic(model)
    if not np.any(on):
        return u
    if act is None:
        names = [n for n, d in zip(model.actuator_names, on, strict=True) if d]
        raise ValueError(f"the actuators {', '.join(map(repr, names))} of {model.name!r} "
                         f"have activation dynamics: their force takes the activation; "
                         f"pass act (cgadyn.activations)")
    return np.where(on, _activation(model, act, _samples(u.shape, np.shape(act))), u)


def _samples(ctrl: tuple, act: tuple) -> tuple:
    """The samples' shape of controls and activations given with the shapes ``ctrl`` and
    ``act`` (numpy's broadcasting), or a ``ValueError`` naming both."""
    try:
        return np.broadcast_shapes(ctrl, act)
    except ValueError:
        raise ValueError(f"act's samples {act} and ctrl's {ctrl} must be the same (or "
                         f"one shared by all)") from None


def actuator_torques(model, ctrl, q=None, v=None, act=None) -> np.ndarray:
    """The joint torques (nv,) or (..., nv) of controls ``ctrl`` (na,) or (..., na), one
    entry per actuator in ``model.actuator_names``' order, at the state ``(q, v)`` (A1)
    and the activations ``act`` (A2; MuJoCo's ``act``). ``q`` and ``v`` may be left out
    where no actuator's force depends on the state (motors alone), ``act`` where no
    actuator has activation dynamics; they broadcast against ``ctrl``'s samples."""
    u = _driving(model, _controls(model, ctrl), act)
    force = model.actuator_gain * u + model.actuator_bias[:, 0]
    W = actuator_moments(model)
    servo = state_dependent(model)
    if np.any(servo):
        if q is None or v is None:
            names = [n for n, s in zip(model.actuator_names, servo, strict=True) if s]
            raise ValueError(f"the actuators {', '.join(map(repr, names))} of "
                             f"{model.name!r} are servos, whose force depends on the state: "
                             f"pass q and v")
        from .passive import _state

        q = _state(model, q, model.nq, "q")
        v = _state(model, v, model.nv, "v")
        length, rate = additive_values(model, q) @ W.T, v @ W.T
        force = force + model.actuator_bias[:, 1] * length + model.actuator_bias[:, 2] * rate
    return _clamped(model, force) @ W


def control_torques(model, ctrl, act=None) -> np.ndarray:
    """``Σ_a w_a clamp(g_a u_a + b₀)``: the torques of the controls alone (of the
    activations ``act`` for the actuators with activation dynamics, A2), without the
    servos' springs and dampers (``actuator_springs``), which ``simulate`` evaluates at
    each stage's state."""
    u = _driving(model, _controls(model, ctrl), act)
    force = model.actuator_gain * u + model.actuator_bias[:, 0]
    return _clamped(model, force) @ actuator_moments(model)


def _clamped(model, force: np.ndarray) -> np.ndarray:
    """The forces clamped to each actuator's ``forcerange`` (A1)."""
    return np.clip(force, model.actuator_forcerange[:, 0], model.actuator_forcerange[:, 1])


def actuator_springs(model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The servos' state-dependent parts as fixed tendons of rest length 0 (A1, P2): their
    moment arms (n, nv), stiffnesses ``-b₁`` and dampers ``-b₂`` (n,)."""
    servo = state_dependent(model)
    return (actuator_moments(model)[servo], -model.actuator_bias[servo, 1],
            -model.actuator_bias[servo, 2])
