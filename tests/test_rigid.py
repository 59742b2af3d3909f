"""The closed-form rigid inertia kernels equal eqs. (4), (15) and (16) on rigid inertias."""

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
from cgadyn.kernels import inertia_apply, twist_sandwich
from cgadyn.kernels.rigid import (
    rigid_apply,
    rigid_axis_transform,
    rigid_inertia_transform,
    rigid_matrix,
    rigid_parameters,
)


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


@pytest.mark.parametrize("seed", range(5))
def test_ten_parameter_kernels_equal_the_general_ones(seed):
    """``rigid_axis_transform`` equals the twist sandwich (eq. 4) and eq. (16), and
    ``rigid_apply`` equals eq. (15)."""
    np.random.seed(seed)
    I = inertia_from_pinocchio(pin.Inertia.Random().matrix())
    M = motor_from_matrix(pin.SE3.Random().homogeneous)
    B, V = np.random.randn(6), np.random.randn(6)
    S, par = np.empty(6), np.empty(10)
    rigid_axis_transform(M, B, I, S, par)
    S_ref = np.empty(6)
    twist_sandwich(M, B, S_ref)
    np.testing.assert_allclose(S, S_ref, atol=1e-14)
    Iw = np.empty((6, 6))
    rigid_matrix(par, Iw)
    np.testing.assert_allclose(Iw, inertia_transform(M, I), atol=1e-13)
    np.testing.assert_allclose(rigid_parameters(Iw), par, atol=1e-14)
    F, F_ref = np.array(rigid_apply(par, V)), np.empty(6)
    inertia_apply(Iw, V, F_ref)
    np.testing.assert_allclose(F, F_ref, atol=1e-13)
