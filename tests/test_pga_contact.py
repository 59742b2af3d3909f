"""Impulse contact against a plane (section 2.6): eqs. (2.32)-(2.33) and detection 2.6.1."""

import numpy as np
import pytest

from cgadyn.pga import hypercube, kinetic_energy
from cgadyn.pga.contact import contact_impulse, normal_velocity, penetrations
from cgadyn.pga.simulate import hypercube_on_spring


def approaching_case(d, seed=0):
    rng = np.random.default_rng(seed)
    body = hypercube(d, 2.0, np.arange(1, d + 1) * 0.7)
    m = body.model
    floor = m.hyperplane(np.eye(d)[-1], 0.0)
    for _ in range(50):
        motor = m.motor(rotation=rng.normal(size=len(m.eij)), translation=rng.normal(size=d))
        b = m.grade(rng.normal(size=m.n), 2)
        for v in body.vertices:
            vn = normal_velocity(m, motor, b, m.point(v), floor)
            if vn < -0.05:
                return body, motor, b, v, floor, vn
    raise AssertionError("no approaching vertex found")


@pytest.mark.parametrize("d", [1, 2, 3, 4])
@pytest.mark.parametrize("rho", [0.0, 0.5, 1.0])
def test_impulse_reverses_normal_velocity_by_restitution(d, rho):
    body, motor, b, v, floor, vn = approaching_case(d)
    m = body.model
    new_b, j = contact_impulse(body, motor, b, v, floor, rho)
    assert normal_velocity(m, motor, new_b, m.point(v), floor) == pytest.approx(-rho * vn)
    dt = kinetic_energy(body.inertia, new_b) - kinetic_energy(body.inertia, b)
    if rho == 1.0:
        assert abs(dt) < 1e-12  # elastic: kinetic energy kept
    else:
        assert dt < 0


def test_penetration_detection_finds_vertices_below_the_floor():
    body = hypercube(3)
    m = body.model
    floor = m.hyperplane([0.0, 0.0, 1.0], -0.4)  # z = -0.4 cuts the bottom face (z = -0.5)
    idx, depth = penetrations(body, m.scalar(), floor)
    assert sorted(idx) == [0, 1, 2, 3]
    np.testing.assert_allclose(depth, -0.1)
    idx, _ = penetrations(body, m.motor(translation=[0, 0, 1.0]), floor)
    assert len(idx) == 0


def test_bad_restitution_is_rejected():
    body, motor, b, v, floor, _ = approaching_case(2)
    with pytest.raises(ValueError, match="restitution must be in"):
        contact_impulse(body, motor, b, v, floor, 1.5)


@pytest.mark.parametrize("d", [2, 3])
def test_hypercube_bounces_on_the_floor(d):
    """Fig. 2.5: with contact the cube hits the floor, its energy never rises (damping and
    restitution 0.5 only remove energy), and no vertex sinks deep into the floor."""
    free = hypercube_on_spring(d, steps=500, dt=1 / 300, contact=False)
    run = hypercube_on_spring(d, steps=500, dt=1 / 300, integrator="rk4")
    s, tr = run["summary"], run["trajectory"]
    assert free["summary"]["lowest_height"] < s["floor_height"] - 0.1
    assert s["contacts"] >= 1
    assert s["lowest_height"] > s["floor_height"] - 0.02
    assert np.all(np.diff(tr["energy"]) < 1e-9)
    assert s["motor_norm_error"] < 1e-13
