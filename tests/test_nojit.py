"""The pure-Python path (NUMBA_DISABLE_JIT=1) computes the same numbers as the compiled one."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import cgadyn

pytestmark = pytest.mark.slow


SCRIPT = """
import json, numpy as np, cgadyn
m = cgadyn.load("{robot}")
rng = np.random.default_rng(3)
q, v, a = (rng.uniform(-1, 1, (2, m.nv)) for _ in range(3))
print(json.dumps({{
    "rnea": cgadyn.rnea(m, q[0], v[0], a[0]).tolist(),
    "rnea_ext": cgadyn.rnea(m, q[1], v[1], a[1], gravity=(0.5, 1.0, -3.0),
                            f_ext=rng.uniform(-1, 1, (m.nv, 6))).tolist(),
    "aba_ext": cgadyn.aba(m, q[0], v[0], a[0], f_ext=rng.uniform(-1, 1, (m.nv, 6))).tolist(),
    "crba_batch": cgadyn.crba(m, np.concatenate([q, q])).tolist(),
    "aba": cgadyn.aba(m, q, v, a).tolist(),
    "crba": cgadyn.crba(m, q[1]).tolist(),
    "minverse_batch": cgadyn.minverse(m, np.concatenate([q] * 10)).tolist(),
    "jac": cgadyn.jacobian(m, q[0], m.link_names[-1]).tolist(),
    "energy": cgadyn.energy(m, q[1], v[1]).tolist(),
    "simulate": cgadyn.simulate(m, q, v, 1e-3, 5, controller=cgadyn.PD(2.0, 0.1)).q.tolist(),
}}))
"""


def run(robot: str, disable_jit: bool) -> dict:
    env = dict(os.environ, NUMBA_DISABLE_JIT="1" if disable_jit else "0")
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT.format(robot=robot)],
        env=env, capture_output=True, text=True, check=True, timeout=600,
    )
    return json.loads(out.stdout)


def test_disable_jit_matches_compiled():
    for robot in ("double_pendulum", "gripper"):
        py, jit = run(robot, True), run(robot, False)
        for key in jit:
            a, b = np.array(py[key]), np.array(jit[key])
            assert np.abs(a - b).max() <= 1e-12 * max(1.0, np.abs(b).max()), (robot, key)
    assert cgadyn.load("gripper").nv == len(jit["rnea"])


GROUPS = """
import json, numpy as np, cgadyn
from cgadyn import oracle
m = cgadyn.load("solo12")
s = oracle.sample(m, 20, 0)
f = np.random.default_rng(1).normal(size=(20, m.njoints, 6))
print(json.dumps([cgadyn.minverse(m, s.q).tolist()]
                 + [x.tolist() for x in cgadyn.rnea_derivatives(m, s.q, s.v, s.a, f_ext=f)]
                 + [x.tolist() for x in cgadyn.aba_derivatives(m, s.q, s.v, s.tau, f_ext=f)]))
"""


def test_disable_jit_groups_on_a_free_flyer():
    """The batches that compute groups of samples at once (``minverse_lanes``,
    ``rnea_derivatives_lanes``, ``aba_derivatives_lanes``: the joint motors, the free
    root's quaternion included, the moves of eqs. 4 and 16 and the forward pass of the
    derivatives on arrays of vectors) compute the same numbers in pure Python as
    compiled."""
    out = {}
    for disable_jit in (True, False):
        env = dict(os.environ, NUMBA_DISABLE_JIT="1" if disable_jit else "0")
        done = subprocess.run([sys.executable, "-c", GROUPS], env=env, capture_output=True,
                              text=True, check=True, timeout=600)
        out[disable_jit] = [np.array(x) for x in json.loads(done.stdout)]
    for py, jit in zip(out[True], out[False], strict=True):
        assert py.shape == (20, 18, 18)
        assert np.abs(py - jit).max() <= 1e-12 * np.abs(jit).max()
