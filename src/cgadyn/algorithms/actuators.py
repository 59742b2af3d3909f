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

A servo's state-dependent part ``w_a (b₁ L_a + b₂ L̇_a)`` is a spring of stiffness ``-b₁``
and a damper ``-b₂`` along ``w_a``, a tendon of rest length 0 (``passive``, P2):
``simulate(ctrl=...)`` adds the control's part ``w_a clamp(g_a u_a + b₀)`` to its torques
and that spring to the compiled loop's tendons (``actuator_springs``). Plain numpy.
"""

from __future__ import annotations

import numpy as np

from ..multibody.joints.table import additive_values


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


def actuator_torques(model, ctrl, q=None, v=None) -> np.ndarray:
    """The joint torques (nv,) or (..., nv) of controls ``ctrl`` (na,) or (..., na), one
    entry per actuator in ``model.actuator_names``' order, at the state ``(q, v)`` (A1).
    ``q`` and ``v`` may be left out where no actuator's force depends on the state (motors
    alone); they broadcast against ``ctrl``'s samples."""
    u = _controls(model, ctrl)
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


def control_torques(model, ctrl) -> np.ndarray:
    """``Σ_a w_a clamp(g_a u_a + b₀)``: the torques of the controls alone, without the
    servos' springs and dampers (``actuator_springs``), which ``simulate`` evaluates at
    each stage's state."""
    u = _controls(model, ctrl)
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
