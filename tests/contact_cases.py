"""Contact scenes shared by the contact tests (``test_contact_step.py``,
``test_simulate_contact.py``)."""

from __future__ import annotations

import warnings

import numpy as np

import cgadyn

STAND = np.tile([0.0, 0.8, -1.6], 4)  # solo12's standing posture: hip, knee of each leg


def solo12_on_the_ground():
    """solo12, its collision hulls and a configuration in its standing posture (``STAND``)
    lowered until its lowest foot touches the level ground."""
    model = cgadyn.load("solo12")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cgadyn.MeshSimplified)
        cm = cgadyn.collision_model(model, "solo12")
    q = cgadyn.neutral(model)
    q[7:] = STAND
    q[2] = 0.3
    q[2] -= cgadyn.ground_contacts(model, cm, q, margin=1.0).distance.min()
    return model, cm, q
