"""The joint types of issue 33 beyond the spherical joint, in every algorithm: Pinocchio's
planar (``JointModelPlanar``), translation (``JointModelTranslation``) and helical
(``JointModelHX``/``HY``/``HZ``/``HelicalUnaligned``) joints, and its universal
(``JointModelUniversal``) and spherical ZYX (``JointModelSphericalZYX``) joints, converted
to the chains of revolute joints they are (``pinocchio_model.CHAINS``): each in a chain, a
tree and below a free-flyer root, built in Pinocchio, converted by ``cgadyn.from_pinocchio``
and compared with Pinocchio on every check of ``oracle.CHECKS`` (rnea, aba, crba, M⁻¹, both
derivatives, placements, Jacobians, centre of mass, centroidal momentum, integrate,
difference); the energy; batches against single calls; the manifold's identities; a
rollout that keeps the planar ``(cos θ, sin θ)`` unit.

Pinocchio 4.1's analytic derivatives of rnea and aba are wrong for the universal and ZYX
joints (they differ from central differences of its own ``rnea`` and ``aba`` by O(10)): the
derivatives of models with those joints are checked against those central differences."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from joint_cases import random_model

import cgadyn
from cgadyn import oracle
from cgadyn.multibody.joints import HELICAL, PLANAR, TRANSLATION, TYPES
from cgadyn.validate import leaf_links

TOL = 1e-10


def _helical() -> pin.JointModel:
    return pin.JointModelHelicalUnaligned(np.array([0.6, 0.0, 0.8]), -0.13)


def _universal() -> pin.JointModel:
    return pin.JointModelUniversal(np.array([0.0, 0.6, 0.8]), np.array([1.0, 0.0, 0.0]))


_JOINT = {
    "planar": (PLANAR, pin.JointModelPlanar),
    "translation": (TRANSLATION, pin.JointModelTranslation),
    "helical": (HELICAL, lambda: pin.JointModelHZ(0.21)),
}
_CODE = {"planar": PLANAR, "translation": TRANSLATION, "helical": HELICAL, "universal": -1}

MODELS = {
    "planar-chain": lambda: random_model("chain", [
        (0, pin.JointModelRX()), (1, pin.JointModelPlanar()), (2, pin.JointModelRY()),
        (3, pin.JointModelPlanar())], 1),
    "planar-tree": lambda: random_model("tree", [
        (0, pin.JointModelPlanar()), (1, pin.JointModelSpherical()), (2, pin.JointModelRY()),
        (1, pin.JointModelPZ()), (4, pin.JointModelPlanar()), (5, pin.JointModelRUBZ())], 2),
    "planar-floating": lambda: random_model("floating", [
        (0, pin.JointModelFreeFlyer()), (1, pin.JointModelPlanar()), (2, pin.JointModelRZ())],
        3),
    "translation-chain": lambda: random_model("chain", [
        (0, pin.JointModelTranslation()), (1, pin.JointModelRX()),
        (2, pin.JointModelTranslation()), (3, pin.JointModelRY())], 4),
    "translation-tree": lambda: random_model("tree", [
        (0, pin.JointModelRZ()), (1, pin.JointModelTranslation()), (2, pin.JointModelRY()),
        (1, pin.JointModelSpherical()), (4, pin.JointModelTranslation())], 5),
    "translation-floating": lambda: random_model("floating", [
        (0, pin.JointModelFreeFlyer()), (1, pin.JointModelTranslation()),
        (2, pin.JointModelRZ())], 6),
    "helical-chain": lambda: random_model("chain", [
        (0, pin.JointModelHX(0.1)), (1, pin.JointModelRY()), (2, _helical()),
        (3, pin.JointModelHZ(-0.4))], 7),
    "helical-tree": lambda: random_model("tree", [
        (0, pin.JointModelHY(0.3)), (1, pin.JointModelRX()), (2, _helical()),
        (1, pin.JointModelHZ(0.05)), (4, pin.JointModelPlanar())], 8),
    "helical-floating": lambda: random_model("floating", [
        (0, pin.JointModelFreeFlyer()), (1, _helical()), (2, pin.JointModelHX(0.2))], 9),
    "universal-chain": lambda: random_model("chain", [
        (0, _universal()), (1, pin.JointModelRY()), (2, pin.JointModelSphericalZYX()),
        (3, pin.JointModelPX())], 10),
    "universal-tree": lambda: random_model("tree", [
        (0, pin.JointModelSphericalZYX()), (1, _universal()), (2, pin.JointModelRX()),
        (1, pin.JointModelSpherical()), (4, _universal())], 11),
    "universal-floating": lambda: random_model("floating", [
        (0, pin.JointModelFreeFlyer()), (1, pin.JointModelSphericalZYX()),
        (1, _universal()), (3, pin.JointModelPlanar())], 12),
}
CHAINED = ("JointModelUniversal", "JointModelSphericalZYX")
DERIVATIVES = ("rnea_derivatives", "aba_derivatives")


@pytest.fixture(scope="module", params=sorted(MODELS))
def models(request):
    pm = MODELS[request.param]()
    return cgadyn.from_pinocchio(pm), pm, _CODE[request.param.split("-")[0]]


@pytest.mark.parametrize("name", sorted(_JOINT))
def test_the_record_matches_pinocchios_sizes(name):
    code, make = _JOINT[name]
    joint, record = make(), TYPES[code]
    assert (record.pinocchio_nq, record.nv) == (joint.nq, joint.nv)
    assert joint.shortname() in record.pinocchio and record.mujoco is None
    pm = random_model(name, [(0, joint)], 0)
    assert np.array_equal(np.asarray(record.neutral), pin.neutral(pm))


def test_the_conversion(models):
    model, pm, code = models
    assert model.nv == pm.nv
    chained = [i for i in range(1, pm.njoints) if pm.joints[i].shortname() in CHAINED]
    if not chained:
        assert model.joint_names == tuple(pm.names[1:])
        for j in range(model.njoints):
            assert pm.joints[j + 1].shortname() in TYPES[int(model.joint_types[j])].pinocchio
        assert code in model.joint_types
    else:  # one revolute joint per coordinate, the last with the joint's name and body
        assert model.njoints == pm.njoints - 1 + sum(pm.joints[i].nv - 1 for i in chained)
        assert set(pm.names[1:]) <= set(model.joint_names)
        for i in chained:
            j = model.joint_names.index(pm.names[i])
            assert model.body_mass[j] == pm.inertias[i].mass
            assert np.all(model.body_mass[j - pm.joints[i].nv + 1:j] == 0.0)
    assert model.link_names[1:] == tuple(f.name for f in pm.frames
                                         if f.type == pin.FrameType.BODY)[1:]
    assert np.array_equal(oracle.pin_configuration(model, cgadyn.neutral(model)),
                          pin.neutral(pm))
    back = cgadyn.from_pinocchio(oracle.pinocchio_of(model))  # the oracle's own model
    assert np.array_equal(back.axes, model.axes)


def test_every_check_matches_pinocchio(models):
    """rnea, aba, crba, g(q), the Jacobians, the placements, the derivatives, M⁻¹, ccrba,
    the centre of mass and the manifold, at random states: to 1e-10 relative (× cond(M)
    for the solves, ``oracle.SCALED``)."""
    model, pm, _ = models
    states = oracle.sample(model, 5, 7)
    leaves = leaf_links(model)
    frames = oracle._frames(pm, leaves)
    data = pm.createData()
    qp = oracle.pin_configuration(model, states.q)
    cond = oracle.conditioning(model, states.q)
    chained = any(pm.joints[i].shortname() in CHAINED for i in range(1, pm.njoints))
    worst = {}
    for check in oracle.CHECKS:
        if chained and check.key in DERIVATIVES:
            continue  # Pinocchio's are wrong there: test_derivatives_of_chained_joints
        if check.theirs is None:
            ref = np.stack([oracle.fk_reference(pm, data, qp[i], model.link_names)
                            for i in range(5)])
        else:
            ref = np.stack([check.theirs(pm, data, qp[i], states, i, frames)
                            for i in range(5)])
        rel = oracle.relative_error(check.mine(model, states, leaves), ref)
        scale = cond if check.scaled else 1.0
        worst[check.key] = float((rel / scale).max())
    assert all(w <= TOL for w in worst.values()), worst


def test_derivatives_of_chained_joints_match_central_differences_of_pinocchio(models):
    """rnea and aba derivatives against central differences (h = 1e-6) of Pinocchio's rnea
    and aba, on the models with universal and ZYX joints, where Pinocchio 4.1's analytic
    derivatives differ from those same differences (by 11-15 on entries of about 20)."""
    model, pm, _ = models
    if not any(pm.joints[i].shortname() in CHAINED for i in range(1, pm.njoints)):
        pytest.skip("no universal or ZYX joint: the derivatives are checked by every_check")
    data = pm.createData()
    s = oracle.sample(model, 2, 15)
    for q, v, a, tau in zip(s.q, s.v, s.a, s.tau, strict=True):
        rq = _central(pm, data, model, pin.rnea, [q, v, a], 0)
        rv = _central(pm, data, model, pin.rnea, [q, v, a], 1)
        aq = _central(pm, data, model, pin.aba, [q, v, tau], 0)
        mq, mv, _ = cgadyn.rnea_derivatives(model, q, v, a)
        nq, _, _ = cgadyn.aba_derivatives(model, q, v, tau)
        scale = max(np.abs(rq).max(), np.abs(aq).max(), 1.0)
        assert np.abs(mq - rq).max() <= 1e-6 * scale
        assert np.abs(mv - rv).max() <= 1e-6 * scale
        assert np.abs(nq - aq).max() <= 1e-6 * scale


def _central(pm, data, model, f, args, k, h=1e-6) -> np.ndarray:
    """Central differences of Pinocchio's ``f(pm, data, q, v, x)`` in its argument k (q in
    cgadyn's layout, moved along each velocity coordinate by ``integrate``)."""
    columns = []
    for e in np.eye(model.nv):
        out = []
        for sign in (1.0, -1.0):
            moved = [np.array(x, dtype=float) for x in args]
            moved[k] = (cgadyn.integrate(model, moved[0], sign * h * e) if k == 0
                        else moved[k] + sign * h * e)
            out.append(f(pm, data, oracle.pin_configuration(model, moved[0]), *moved[1:]))
        columns.append((out[0] - out[1]) / (2 * h))
    return np.stack(columns, 1)


def test_energy_matches_pinocchio(models):
    model, pm, _ = models
    data = pm.createData()
    s = oracle.sample(model, 3, 8)
    for q, v in zip(s.q, s.v, strict=True):
        qp = oracle.pin_configuration(model, q)
        kinetic, potential = cgadyn.energy(model, q, v)
        assert kinetic == pytest.approx(pin.computeKineticEnergy(pm, data, qp, v), rel=TOL)
        assert potential == pytest.approx(pin.computePotentialEnergy(pm, data, qp), rel=TOL,
                                          abs=1e-12)


def test_integrate_difference_neutral_random_match_pinocchio(models):
    model, pm, _ = models
    s = oracle.sample(model, 4, 14)
    for i in range(4):
        qp = oracle.pin_configuration(model, s.q[i])
        qp1 = oracle.pin_configuration(model, s.q[(i + 1) % 4])
        mine = oracle.pin_configuration(model, cgadyn.integrate(model, s.q[i], s.v[i]))
        assert np.abs(mine - pin.integrate(pm, qp, s.v[i])).max() <= 1e-12
        d = cgadyn.difference(model, s.q[i], s.q[(i + 1) % 4])
        assert np.abs(d - pin.difference(pm, qp, qp1)).max() <= 1e-12
    q = cgadyn.random_configuration(model, np.random.default_rng(0))
    assert q.shape == (model.nq,) and np.all(np.isfinite(q))
    assert np.abs(cgadyn.normalize(model, q) - q).max() <= 1e-15  # unit blocks already unit


def test_batches_equal_single_calls(models):
    """Eleven samples: a group of eight in lanes where a pass has them, and the rest."""
    model, _, _ = models
    s = oracle.sample(model, 11, 9)
    batch = {
        "rnea": cgadyn.rnea(model, s.q, s.v, s.a),
        "aba": cgadyn.aba(model, s.q, s.v, s.tau),
        "crba": cgadyn.crba(model, s.q),
        "minverse": cgadyn.minverse(model, s.q),
        "rnea_derivatives": np.stack(cgadyn.rnea_derivatives(model, s.q, s.v, s.a), 1),
        "aba_derivatives": np.stack(cgadyn.aba_derivatives(model, s.q, s.v, s.tau), 1),
    }
    for i in range(11):
        single = {
            "rnea": cgadyn.rnea(model, s.q[i], s.v[i], s.a[i]),
            "aba": cgadyn.aba(model, s.q[i], s.v[i], s.tau[i]),
            "crba": cgadyn.crba(model, s.q[i]),
            "minverse": cgadyn.minverse(model, s.q[i]),
            "rnea_derivatives": np.stack(cgadyn.rnea_derivatives(model, s.q[i], s.v[i],
                                                                 s.a[i])),
            "aba_derivatives": np.stack(cgadyn.aba_derivatives(model, s.q[i], s.v[i],
                                                               s.tau[i])),
        }
        for key, value in single.items():
            assert np.allclose(batch[key][i], value, rtol=1e-12, atol=1e-12), (key, i)


def test_manifold_identities(models):
    """``q0 ⊕ (q1 ⊖ q0) = q1`` and ``d/dt (q ⊕ t v) = v``."""
    model, _, _ = models
    s = oracle.sample(model, 4, 11)
    q0, q1 = s.q, np.roll(s.q, 1, axis=0)
    back = cgadyn.integrate(model, q0, cgadyn.difference(model, q0, q1))
    T0 = cgadyn.link_placements(model, back)
    assert np.abs(T0 - cgadyn.link_placements(model, q1)).max() <= 1e-12
    h = 1e-6
    slope = (cgadyn.difference(model, q0, cgadyn.integrate(model, q0, h * s.v)) -
             cgadyn.difference(model, q0, cgadyn.integrate(model, q0, -h * s.v))) / (2 * h)
    assert np.abs(slope - s.v).max() <= 1e-8


def test_the_planar_half_angle_holds_on_the_whole_circle():
    """Planar joints at angles on both halves of the circle, at ±π and at 0, placed as
    Pinocchio places them (the two formulas of ``planar_rotor`` meet at cos θ = 0)."""
    pm = MODELS["planar-chain"]()
    model = cgadyn.from_pinocchio(pm)
    data = pm.createData()
    q = cgadyn.neutral(model)
    j = [int(model.idx_q[j]) for j in range(model.njoints) if model.joint_types[j] == PLANAR]
    for theta in (0.0, np.pi / 2, -np.pi / 2, np.pi, -np.pi, 3.0, -3.0, 1e-9, np.pi - 1e-9):
        for i in j:
            q[i + 2:i + 4] = np.cos(theta), np.sin(theta)
        ref = oracle.fk_reference(pm, data, oracle.pin_configuration(model, q),
                                  model.link_names)
        assert np.abs(cgadyn.link_placements(model, q) - ref).max() <= 1e-13, theta


def test_off_unit_planar_direction_is_refused_by_name():
    model = cgadyn.from_pinocchio(MODELS["planar-chain"]())
    j = next(j for j in range(model.njoints) if model.joint_types[j] == PLANAR)
    q = oracle.sample(model, 1, 12).q[0]
    q[model.idx_q[j] + 2:model.idx_q[j] + 4] *= 1.1
    with pytest.raises(ValueError, match=model.joint_names[j]):
        cgadyn.rnea(model, q, np.zeros(model.nv), np.zeros(model.nv))
    fixed = cgadyn.normalize(model, q)
    assert np.linalg.norm(fixed[model.idx_q[j] + 2:model.idx_q[j] + 4]) == \
        pytest.approx(1.0, abs=1e-15)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["planar-tree", "helical-chain", "translation-tree"])
def test_rollout_keeps_planar_directions_unit(name):
    """RK4 on the manifold: every planar joint's ``(cos θ, sin θ)`` stays unit, and
    without damping the energy drifts little."""
    model = cgadyn.from_pinocchio(MODELS[name]())
    s = oracle.sample(model, 2, 13)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = cgadyn.simulate(model, s.q, 0.5 * s.v, 1e-3, 300, passive=False)
    assert not np.any(traj.diverged)
    for j in range(model.njoints):
        if model.joint_types[j] == PLANAR:
            unit = traj.q[..., model.idx_q[j] + 2:model.idx_q[j] + 4]
            assert np.abs(np.linalg.norm(unit, axis=-1) - 1.0).max() <= 1e-12
    drift = np.abs(traj.energy[:, -1] - traj.energy[:, 0]) / np.abs(traj.energy[:, 0])
    assert drift.max() <= 1e-6


@pytest.mark.parametrize("name", [n for n in sorted(MODELS) if n.startswith("universal")])
def test_pinocchios_joint_indexed_arrays_move_by_the_joint_map(name):
    """A universal or spherical ZYX joint is a chain of joints in cgadyn: Pinocchio's
    wrenches per joint (``f_ext``) and joint placements (``oMi``) move between the
    libraries by ``oracle.joint_map``, the wrenches by ``oracle.cgadyn_wrenches``."""
    from cgadyn.cga.conventions import matrix_from_motor

    pm = MODELS[name]()
    model = cgadyn.from_pinocchio(pm)
    assert model.njoints > pm.njoints - 1  # the chains' joints
    data = pm.createData()
    rng = np.random.default_rng(3)
    states = oracle.sample(model, 3, 5)
    for q, v, a in zip(states.q, states.v, states.a, strict=True):
        qp = oracle.pin_configuration(model, q)
        f_pin = rng.standard_normal((pm.njoints - 1, 6))
        f = oracle.cgadyn_wrenches(model, pm, f_pin)
        expected = pin.rnea(pm, data, qp, v, a, oracle.forces(f_pin))
        np.testing.assert_allclose(cgadyn.rnea(model, q, v, a, f_ext=f), expected,
                                   rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        expected = pin.aba(pm, data, qp, v, a, oracle.forces(f_pin))
        np.testing.assert_allclose(cgadyn.aba(model, q, v, a, f_ext=f), expected,
                                   rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        pin.forwardKinematics(pm, data, qp)
        joints, _ = cgadyn.forward_kinematics(model, q)
        for i, j in enumerate(oracle.joint_map(model, pm)):
            np.testing.assert_allclose(matrix_from_motor(joints[j]),
                                       data.oMi[i + 1].homogeneous, atol=1e-12)


def test_the_joint_map_refuses_another_model():
    pm = MODELS["universal-chain"]()
    with pytest.raises(ValueError, match="are not joints of 'panda'"):
        oracle.joint_map(cgadyn.load("panda"), pm)
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 4, 6\)"):
        oracle.cgadyn_wrenches(cgadyn.from_pinocchio(pm), pm, np.zeros((5, 6)))
