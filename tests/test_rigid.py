"""The closed-form rigid inertia transform equals eq. (16) on rigid inertias."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from cgadyn.cga.conventions import (
    inertia_from_pinocchio,
    inertia_to_pinocchio,
    inertia_transform,
    motor_from_matrix,
)
from cgadyn.kernels.rigid import rigid_inertia_transform


@pytest.mark.parametrize("seed", range(5))
def test_rigid_transform_equals_eq16_and_pinocchio(seed):
    np.random.seed(seed)
    inertia = pin.Inertia.Random()
    pose = pin.SE3.Random()
    I = inertia_from_pinocchio(inertia.matrix())
    M = motor_from_matrix(pose.homogeneous)
    out = np.empty((6, 6))
    rigid_inertia_transform(M, I, out)
    np.testing.assert_allclose(out, inertia_transform(M, I), atol=1e-13)
    np.testing.assert_allclose(inertia_to_pinocchio(out), pose.act(inertia).matrix(), atol=1e-12)
    rigid_inertia_transform(M, I, I)  # in place
    np.testing.assert_allclose(I, out, atol=0)


def test_massless_inertia_stays_zero():
    M = motor_from_matrix(pin.SE3.Random().homogeneous)
    out = np.ones((6, 6))
    rigid_inertia_transform(M, np.zeros((6, 6)), out)
    assert not out.any()
