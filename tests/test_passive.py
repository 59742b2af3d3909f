"""Joint damping and springs on the model: read from URDF's ``<dynamics damping>``, from a
Pinocchio model's ``damping``; ``cgadyn.passive_torques``; what the model refuses."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cgadyn

URDF = """<robot name="two">
  <link name="base"/>
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"
    ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="continuous"><parent link="base"/><child link="a"/>
    <axis xyz="0 0 1"/><dynamics damping="0.7" friction="0.1"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def test_urdf_damping_is_read_as_pinocchio_reads_it():
    pin = pytest.importorskip("pinocchio")
    model = cgadyn.load(URDF)
    assert np.array_equal(model.damping, [0.7, 0.0])
    assert np.array_equal(model.damping, pin.buildModelFromXML(URDF).damping)
    assert np.array_equal(model.friction, [0.1, 0.0])  # the friction loss (docs/contact.md)
    assert np.array_equal(model.friction, pin.buildModelFromXML(URDF).friction)
    assert np.array_equal(cgadyn.from_pinocchio(pin.buildModelFromXML(URDF)).friction,
                          [0.1, 0.0])
    assert np.array_equal(model.armature, [0.0, 0.0])
    with pytest.raises(ValueError, match=r"joint 'j1': <dynamics damping=\"-1.0\"> is not a "
                                         r"finite number >= 0"):
        cgadyn.load(URDF.replace('damping="0.7"', 'damping="-1"'))
    with pytest.raises(ValueError, match=r"<dynamics friction=\"-1.0\"> is not a finite"):
        cgadyn.load(URDF.replace('friction="0.1"', 'friction="-1"'))


def test_pinocchio_damping_and_armature_are_read():
    pin = pytest.importorskip("pinocchio")
    pm = pin.buildModelFromXML(URDF)
    pm.armature = np.array([0.2, 0.3])
    model = cgadyn.from_pinocchio(pm)
    assert np.array_equal(model.armature, [0.2, 0.3])
    assert np.array_equal(model.damping, [0.7, 0.0])


def test_passive_torques_are_damping_and_springs():
    model = dataclasses.replace(cgadyn.load(URDF), stiffness=np.array([0.0, 4.0]),
                                spring_reference=np.array([0.0, 0.25]))
    q, v = np.array([0.3, 0.5]), np.array([2.0, -1.0])
    np.testing.assert_allclose(cgadyn.passive_torques(model, q, v),
                               [-0.7 * 2.0, -4.0 * (0.5 - 0.25)])
    batch = cgadyn.passive_torques(model, np.tile(q, (3, 1)), np.tile(v, (3, 1)))
    assert batch.shape == (3, 2)
    with pytest.raises(ValueError, match=r"q must have shape \(2,\)"):
        cgadyn.passive_torques(model, np.zeros(3), v)


def test_the_model_refuses_what_is_not_physical():
    model = cgadyn.load(URDF)
    with pytest.raises(ValueError, match=r"Model.damping\[0\] \(joint 'j1'\) is -1.0"):
        dataclasses.replace(model, damping=np.array([-1.0, 0.0]))
    with pytest.raises(ValueError, match=r"Model.armature has shape \(3,\), expected \(2,\)"):
        dataclasses.replace(model, armature=np.zeros(3))
    floating = cgadyn.load(URDF, floating_base=True)
    with pytest.raises(ValueError, match="joint 'root_joint' .* has a nonzero stiffness"):
        dataclasses.replace(floating, stiffness=np.r_[np.ones(6), 0.0, 0.0])
