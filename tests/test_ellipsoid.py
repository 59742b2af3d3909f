"""The ellipsoid (``cgadyn.Ellipsoid``, K6a): its inertia against coal's, at rest and rocking
on the ground as a free body, read from MJCF geoms (dm_control's quadruped stands on its
legs and torso), drawn in the viewer. Its distances against coal: ``tests/test_shapes.py``."""

import warnings

import numpy as np
import pytest

import cgadyn
from cgadyn.contact.bodies import Body, empty_model, shape_inertia
from cgadyn.contact.world import World

ELLIPSOID = cgadyn.Ellipsoid([0.1, 0.2, 0.05])
SIE = "semi_implicit_euler"


def _drop(body, steps):
    return cgadyn.simulate(empty_model(), np.zeros(0), np.zeros(0), 1e-3, steps,
                           integrator=SIE, world=World(bodies=[body]))


def test_the_inertia_is_coals():
    coal = pytest.importorskip("coal")
    theirs = coal.Ellipsoid(0.1, 0.2, 0.05)
    com, inertia = shape_inertia(ELLIPSOID, 1.0)
    ref = theirs.computeMomentofInertiaRelatedToCOM() / theirs.computeVolume()
    assert np.abs(inertia - ref).max() < 1e-14 and not com.any()


def test_an_ellipsoid_rests_on_its_lowest_point():
    tr = _drop(Body(ELLIPSOID, 1.0, position=(0.0, 0.0, 0.05)), 1000)
    assert np.abs(tr.q - tr.q[0]).max() < 1e-9
    assert tr.contact_count[-1] == 1
    np.testing.assert_allclose(tr.contact_forces[-1].sum(axis=0), [0.0, 0.0, 9.81],
                               rtol=0, atol=1e-9)


def test_a_tilted_ellipsoid_rocks_on_the_ground_without_gaining_energy():
    """Released tilted by 0.3 rad with its lowest point on the ground: it rocks, its lowest
    point ``z - |A Rᵀ e_z|`` never sinks more than 1e-4 m, and its energy never rises."""
    a = 0.3
    lowest = np.hypot(0.2 * np.sin(a), 0.05 * np.cos(a))
    tr = _drop(Body(ELLIPSOID, 1.0, position=(0.0, 0.0, lowest),
                    orientation=(np.sin(a / 2), 0.0, 0.0, np.cos(a / 2))), 3000)
    x, y, z, w = tr.q[:, 3:7].T
    # R^T e_z: the third row of R, from the unit quaternion (x, y, z, w)
    up = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    depth = tr.q[:, 2] - np.linalg.norm(up * ELLIPSOID.radii, axis=1)
    assert depth.min() > -1e-4
    assert np.diff(tr.energy).max() <= 1e-9 * tr.energy[0]
    assert np.ptp(up[:, 1]) > 0.1  # it did rock


def test_mujoco_ellipsoid_geoms_are_read_and_drawn():
    pytest.importorskip("mujoco")
    from cgadyn.sim.html import shape_visuals

    model = cgadyn.load("dm_control:fish")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cm = cgadyn.collision_model(model)
    torso = cm[cm.names.index("torso")]
    assert isinstance(torso.shape, cgadyn.Ellipsoid)
    np.testing.assert_array_equal(torso.shape.radii, [0.01, 0.08, 0.04])
    drawn = [v for v in shape_visuals(model) if v["link"] == torso.link
             and np.allclose(v["origin"][:3, :3], np.diag([0.01, 0.08, 0.04]))]
    assert len(drawn) == 1 and drawn[0]["kind"] == "sphere" and drawn[0]["size"] == [1.0]


def test_bad_radii_are_named():
    with pytest.raises(ValueError, match="Ellipsoid: radii must be three numbers"):
        cgadyn.Ellipsoid([0.1, 0.2])
    with pytest.raises(ValueError, match="Ellipsoid: the radius must be finite and > 0"):
        cgadyn.Ellipsoid([0.1, -0.2, 0.3])


def test_the_quadrupeds_torso_is_an_ellipsoid_and_its_terrain_is_warned_of():
    pytest.importorskip("mujoco")
    model = cgadyn.load("dm_control:quadruped")
    with pytest.warns(UserWarning, match=r"the world's geoms 'terrain' \(hfield\) are not"):
        cm = cgadyn.collision_model(model)
    assert isinstance(cm[cm.names.index("torso")].shape, cgadyn.Ellipsoid)
    assert "terrain" not in cm.names and "floor" in cm.names
