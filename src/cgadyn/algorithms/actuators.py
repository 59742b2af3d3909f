"""Motors: the generalised torques of a control vector (MuJoCo's ``qfrc_actuator`` of
``<motor joint=...>`` and ``<motor tendon=...>`` on fixed tendons).

    f_a = clamp(clamp(ctrl_a, ctrlrange_a), forcerange_a)
    τ[dof_a] += gear_a f_a            a joint motor
    τ += gear_a f_a c_t               a motor pulling the fixed tendon t of length c_t · q

for each actuator a of ``Model.actuators`` (``Model.actuator_dof``, ``actuator_tendon``,
``actuator_gear``, ``actuator_ctrlrange``, ``actuator_forcerange``; MuJoCo clamps the
control, then the force before the gear; a tendon's force reaches the joints through its
Jacobian ``c_t``, ``Model.tendon_coefficients``). Plain numpy: a motor's torque does not
depend on the state (a fixed tendon's Jacobian is constant).
"""

from __future__ import annotations

import numpy as np


def actuator_torques(model, ctrl) -> np.ndarray:
    """The joint torques (nv,) or (..., nv) of controls ``ctrl`` (na,) or (..., na), one
    entry per actuator in ``model.actuator_names``' order."""
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
    u = np.clip(u, model.actuator_ctrlrange[:, 0], model.actuator_ctrlrange[:, 1])
    force = np.clip(u, model.actuator_forcerange[:, 0], model.actuator_forcerange[:, 1])
    tau = np.zeros(u.shape[:-1] + (model.nv,))
    for a in range(na):  # two motors may drive one coordinate: add, do not assign
        t = model.actuator_tendon[a]
        if t >= 0:
            tau += (model.actuator_gear[a] * force[..., a])[..., None] \
                * model.tendon_coefficients[t]
        else:
            tau[..., model.actuator_dof[a]] += model.actuator_gear[a] * force[..., a]
    return tau
