"""``sim.contact.world_arrays`` is made once per scene and kept: the same arrays for the
same model, collision model, world and settings; new ones for another world, other
settings or another collision model."""

from __future__ import annotations

import cgadyn
from cgadyn.contact.settings import ContactSettings
from cgadyn.sim.contact import FRICTION, world_arrays

BALL = ('<robot name="ball"><link name="ball"><inertial><mass value="1"/>'
        '<inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.004"/>'
        '</inertial><collision><geometry><sphere radius="0.1"/></geometry></collision>'
        '</link></robot>')


def _ball():
    model = cgadyn.load(BALL, floating_base=True)
    return model, cgadyn.collision_model(model, BALL)


def test_the_same_scene_is_served_the_same_arrays():
    model, cm = _ball()
    first = world_arrays(model, cm, cgadyn.World(), ContactSettings())
    again = world_arrays(model, cm, cgadyn.World(), ContactSettings())  # equal, not the same
    assert again is first


def test_another_world_or_settings_get_their_own():
    model, cm = _ball()
    level = world_arrays(model, cm, cgadyn.World(), ContactSettings())
    icy = world_arrays(model, cm, cgadyn.World(friction=0.1), ContactSettings())
    loose = world_arrays(model, cm, cgadyn.World(), ContactSettings(tolerance=1e-6))
    unlimited = world_arrays(model, cm, cgadyn.World(), ContactSettings(), joint_limits=False)
    assert len({id(level), id(icy), id(loose), id(unlimited)}) == 4
    assert level.params[FRICTION] == 1.0 and icy.params[FRICTION] == 0.1


def test_a_softer_collision_model_gets_its_own():
    model, cm = _ball()
    rigid = world_arrays(model, cm, cgadyn.World(), ContactSettings())
    soft = world_arrays(model, cm.compliant(1e5, 10.0), cgadyn.World(), ContactSettings())
    assert soft is not rigid
    assert rigid.compliance.tolist() == [[0.0, 0.0]]
    assert soft.compliance.tolist() == [[1e5, 10.0]]
