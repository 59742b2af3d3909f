"""What issue 33 asks of every new joint type beyond ``test_joint_types.py`` and
``test_spherical.py``, on their models (a chain, a tree and a free-flyer root of spherical,
planar, translation, helical, universal and ZYX joints):

- armature (Pinocchio's ``model.armature``) in rnea, aba, crba, M⁻¹ and both derivatives,
  single calls and batches of eleven (a group of eight in lanes, and three);
- the derivatives of the models with universal and ZYX joints against Pinocchio's analytic
  ones on the revolute chains they become (``oracle.pinocchio_of``; Pinocchio's own are wrong
  for those two joints, docs/joints.md), the chain shown to be the same mechanism by
  Pinocchio's rnea, aba and crba of both;
- the one-sample calls of g(q), the Jacobians, the placements, the centroidal quantities,
  the energy and the manifold against their batches (which ``test_every_check`` and
  ``test_energy`` of those files compare with Pinocchio);
- rollouts, one and two initial states, against the same RK4 on Pinocchio
  (``test_simulate.pin_rollout``);
- the tasks: J̇ against Pinocchio's ``getFrameJacobianTimeVariation`` (on the chain for
  universal and ZYX joints), and inverse
  kinematics of a chain's last body judged by Pinocchio's ``log6``."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from joint_cases import ik_reaches_poses
from test_joint_types import CHAINED
from test_joint_types import MODELS as JOINT_MODELS
from test_simulate import pin_rollout
from test_spherical import MODELS as SPHERICAL_MODELS

import cgadyn
from cgadyn import oracle
from cgadyn.validate import leaf_links

MODELS = {**JOINT_MODELS, **{f"spherical-{k}": v for k, v in SPHERICAL_MODELS.items()}}
SAMPLES = 11
TOL = 1e-10


def _chained(pm) -> bool:
    return any(pm.joints[i].shortname() in CHAINED for i in range(1, pm.njoints))


@pytest.fixture(scope="module", params=sorted(MODELS))
def case(request):
    """(model, Pinocchio model with armature, the Pinocchio model the derivatives are
    checked on, states)."""
    pm = MODELS[request.param]()
    pm.armature = np.random.default_rng(3).uniform(0.05, 2.0, pm.nv)
    model = cgadyn.from_pinocchio(pm)
    return model, pm, oracle.pinocchio_of(model) if _chained(pm) else pm, \
        oracle.sample(model, SAMPLES, 3)


def _rel(got, ref) -> float:
    return float(oracle.relative_error(np.asarray(got)[None], np.asarray(ref)[None])[0])


def test_armature_is_read(case):
    model, pm, _, _ = case
    assert np.array_equal(model.armature, pm.armature) and model.armature.min() > 0.0


@pytest.mark.parametrize("batch", [False, True])
def test_armature_in_every_algorithm(case, batch):
    model, pm, oracle_pm, s = case
    d, do = pm.createData(), oracle_pm.createData()
    sym = oracle.symmetric
    mine = {
        "rnea": lambda x: cgadyn.rnea(model, x.q, x.v, x.a),
        "aba": lambda x: cgadyn.aba(model, x.q, x.v, x.tau),
        "crba": lambda x: cgadyn.crba(model, x.q),
        "minverse": lambda x: cgadyn.minverse(model, x.q),
        "rnea_derivatives": lambda x: np.stack(cgadyn.rnea_derivatives(model, x.q, x.v,
                                                                       x.a)[:2], -3),
        "aba_derivatives": lambda x: np.stack(cgadyn.aba_derivatives(model, x.q, x.v,
                                                                     x.tau)[:2], -3),
    }
    got = ({k: f(s) for k, f in mine.items()} if batch else
           {k: np.stack([f(oracle.States(s.q[i], s.v[i], s.a[i], s.tau[i]))
                         for i in range(SAMPLES)]) for k, f in mine.items()})
    cond = np.linalg.cond(got["crba"])
    scaled = ("aba", "minverse", "aba_derivatives")
    for i in range(SAMPLES):
        qp, v, a, tau = oracle.pin_configuration(model, s.q[i]), s.v[i], s.a[i], s.tau[i]
        ref = {"rnea": pin.rnea(pm, d, qp, v, a).copy(),
               "aba": pin.aba(pm, d, qp, v, tau).copy(),
               "crba": sym(pin.crba(pm, d, qp)),
               "minverse": sym(pin.computeMinverse(pm, d, qp)),
               "rnea_derivatives": np.stack([x.copy() for x in pin.computeRNEADerivatives(
                   oracle_pm, do, qp, v, a)[:2]]),
               "aba_derivatives": np.stack([x.copy() for x in pin.computeABADerivatives(
                   oracle_pm, do, qp, v, tau)[:2]])}
        if oracle_pm is not pm:  # the chain is the mechanism: Pinocchio says so
            assert _rel(pin.rnea(oracle_pm, do, qp, v, a), ref["rnea"]) <= 1e-12
            assert _rel(pin.aba(oracle_pm, do, qp, v, tau), ref["aba"]) <= 1e-12 * cond[i]
            assert _rel(sym(pin.crba(oracle_pm, do, qp)), ref["crba"]) <= 1e-12
        for key, value in ref.items():
            limit = TOL * (cond[i] if key in scaled else 1.0)
            assert _rel(got[key][i], value) <= limit, (key, i, _rel(got[key][i], value))


def test_single_calls_equal_batches(case):
    model, _, _, s = case
    links = leaf_links(model)
    batch = {
        "gravity": cgadyn.gravity_torques(model, s.q),
        "nonlinear": cgadyn.nonlinear_effects(model, s.q, s.v),
        "jacobians": np.stack([cgadyn.jacobian(model, s.q, link, frame)
                               for link in links for frame in ("world", "local")], 1),
        "placements": cgadyn.link_placements(model, s.q),
        "centroidal": cgadyn.centroidal_momentum_matrix(model, s.q),
        "com": np.stack(cgadyn.center_of_mass(model, s.q, s.v, s.a), 1),
        "energy": cgadyn.energy(model, s.q, s.v),  # (B, 2): kinetic, potential
        "integrate": cgadyn.integrate(model, s.q, s.v),
        "difference": cgadyn.difference(model, s.q, np.roll(s.q, 1, 0)),
    }
    for i in range(SAMPLES):
        q, v, a = s.q[i], s.v[i], s.a[i]
        single = {
            "gravity": cgadyn.gravity_torques(model, q),
            "nonlinear": cgadyn.nonlinear_effects(model, q, v),
            "jacobians": np.stack([cgadyn.jacobian(model, q, link, frame)
                                   for link in links for frame in ("world", "local")]),
            "placements": cgadyn.link_placements(model, q),
            "centroidal": cgadyn.centroidal_momentum_matrix(model, q),
            "com": np.stack(cgadyn.center_of_mass(model, q, v, a)),
            "energy": cgadyn.energy(model, q, v),
            "integrate": cgadyn.integrate(model, q, v),
            "difference": cgadyn.difference(model, q, s.q[i - 1]),
        }
        for key, value in single.items():
            assert np.allclose(batch[key][i], value, rtol=1e-12, atol=1e-12), (key, i)


def test_rollouts_match_rk4_on_pinocchio(case):
    """RK4 over 0.4 s (dt 2 ms) from two initial states, in one batch and alone, against
    the same RK4 on Pinocchio's aba and integrate (armature included)."""
    model, pm, _, s = case
    steps, dt = 200, 2e-3
    q0, v0 = s.q[:2], 0.5 * s.v[:2]
    both = cgadyn.simulate(model, q0, v0, dt, steps)
    alone = cgadyn.simulate(model, q0[1], v0[1], dt, steps)
    assert not np.any(both.diverged) and not alone.diverged
    assert np.allclose(alone.q, both.q[1], rtol=0, atol=1e-12)
    for b in range(2):
        Q, V, _ = pin_rollout(pm, oracle.pin_configuration(model, q0[b]), v0[b], dt, steps)
        assert _rel(oracle.pin_configuration(model, both.q[b, -1]), Q[-1]) <= 1e-9
        assert _rel(both.v[b, -1], V[-1]) <= 1e-9


def test_jacobian_time_variation_matches_pinocchio(case):
    """J̇ against Pinocchio's; with universal and ZYX joints against Pinocchio's on the
    revolute chain (its J̇ of those joints is off as its derivatives are: 0.3-0.7 relative
    from central differences of its own Jacobians, where the chain's and cgadyn's agree
    with them to 2e-10)."""
    from cgadyn.tasks import jacobian_time_variation

    model, _, pm, s = case
    d = pm.createData()
    for link in leaf_links(model):
        fid = pm.getFrameId(link, pin.BODY)
        for i in range(3):
            qp = oracle.pin_configuration(model, s.q[i])
            pin.computeJointJacobians(pm, d, qp)
            pin.computeJointJacobiansTimeVariation(pm, d, qp, s.v[i])
            pin.updateFramePlacements(pm, d)
            for frame, ref in (("world", pin.WORLD), ("local", pin.LOCAL)):
                mine = jacobian_time_variation(model, s.q[i], s.v[i], link, frame)
                theirs = pin.getFrameJacobianTimeVariation(pm, d, fid, ref)
                assert _rel(mine, theirs) <= TOL, (link, frame, _rel(mine, theirs))


@pytest.mark.parametrize("name", ["planar-chain", "translation-chain", "helical-chain",
                                  "universal-chain"])
def test_inverse_kinematics_reaches_poses_through_every_joint_type(name):
    """Levenberg-Marquardt on the manifold: poses of the chain's last body reached from
    the neutral configuration, judged by Pinocchio's log6 (``test_spherical`` does the
    same through spherical joints)."""
    ik_reaches_poses(MODELS[name]())
