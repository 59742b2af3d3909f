"""The position correction of the contacts' penetrations (contact/correction.py;
docs/contact.md K43): a body started inside the ground is taken out by its configuration
alone, a fraction β of its depth per step, and no velocity is left behind to throw it."""

import math

import numpy as np
import pytest
from contact_cases import solo12_on_the_ground
from test_contact_step import BALL, BOX, _free

import cgadyn
from cgadyn.contact.step import contact_step

DT, BETA, DEPTH = 1e-3, 0.2, 0.01
SIE = "semi_implicit_euler"


def _sim(model, cm, q, steps, **kw):
    return cgadyn.simulate(model, q, np.zeros(model.nv), DT, steps, integrator=SIE,
                           world=cgadyn.World(), collisions=cm, **kw)


def _deep(urdf: str):
    """A free body of half-height 0.1 m, level, ``DEPTH`` inside the ground."""
    model, cm = _free(urdf)
    q = cgadyn.neutral(model)
    q[2] = 0.1 - DEPTH
    return model, cm, q


@pytest.mark.parametrize("urdf", [BALL, BOX], ids=["ball", "box"])
def test_a_body_started_inside_the_ground_rises_to_its_surface_at_rest(urdf):
    """Its depth after k steps is ``DEPTH (1 - β)^k`` (to 1e-8 m: the sweeps stop within
    a millionth of a correction, ``correction.TOLERANCE``), it never passes the
    surface, and its velocity stays zero (to 1e-6 m/s: what the solvers' tolerances leave
    on the box's four corners): K23's old term ``β d / dt`` threw it up at 2 m/s. The
    compiled loop takes the same steps."""
    model, cm, q = _deep(urdf)
    z, v = [q[2]], []
    qk, vk = q, np.zeros(6)
    for _ in range(40):
        s = contact_step(model, cm, qk, vk, np.zeros(6), DT)
        qk, vk = s.q, s.v
        z.append(qk[2])
        v.append(vk)
    k = np.arange(41)
    assert np.abs(np.array(z) - (0.1 - DEPTH * (1 - BETA) ** k)).max() < 1e-8
    assert max(z) <= 0.1
    assert np.abs(np.array(v)).max() < 1e-6
    tr = _sim(model, cm, q, 40)
    assert np.abs(tr.q[:, 2] - np.array(z)).max() < 1e-10
    assert np.abs(tr.v).max() < 1e-6
    assert np.abs(tr.q[:, 3:6]).max() < 1e-9  # the correction lifts it straight


def test_a_tilted_box_is_turned_out_of_the_ground_without_moving():
    """Without gravity, a box tilted so that one edge is ``DEPTH`` inside the ground and
    its other corners are above it: the correction (in M's metric, turning and lifting)
    takes the edge out at the rate ``1 - β`` a step or faster, never puts the other
    corners inside, and leaves the box at rest (its velocity zero to 1e-12)."""
    model, cm = _free(BOX)
    q = cgadyn.neutral(model)
    angle = 0.3
    q[3:7] = [math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2)]
    corners = cgadyn.ground_contacts(model, cm, q, margin=1.0).distance
    q[2] -= corners.min() + DEPTH
    tr = _sim(model, cm, q, 60, gravity=np.zeros(3))
    depth = np.array([cgadyn.ground_contacts(model, cm, tr.q[k], margin=1.0).distance.min()
                      for k in range(61)])
    assert depth[0] == pytest.approx(-DEPTH, abs=1e-12)
    assert np.all(depth[1:] >= (1 - BETA) * depth[:-1] - 1e-12)
    assert depth[-1] > -DEPTH * (1 - BETA) ** 60 - 1e-12
    assert np.abs(tr.v).max() < 1e-12
    assert np.abs(tr.q[-1, 3:7] - q[3:7]).max() > 1e-4  # it turned as well as rose


def test_solo12_started_in_the_ground_stands_up_without_a_jump():
    """solo12 lowered 5 mm into the ground under joint PD: its feet come out (above -1e-9
    m after 0.2 s) while the base's kinetic energy stays below 0.01 J and its upward
    speed below 0.05 m/s; with K23's old velocity term the feet were thrown out at 0.2
    m/s with 0.12 J."""
    model, cm, q = solo12_on_the_ground()
    q[2] -= 0.005
    tr = _sim(model, cm, q, 300,
              controller=cgadyn.PD(kp=20.0, kd=0.5, q_ref=q, gravity_compensation=False))
    assert not tr.diverged, tr.message
    assert tr.kinetic.max() < 0.01
    assert tr.v[:, 2].max() < 0.05
    deepest = min(cgadyn.ground_contacts(model, cm, tr.q[k], margin=1.0).distance.min()
                  for k in range(200, 301, 20))
    assert deepest > -1e-9
