"""The passes that run on ``W`` samples at once are the scalar passes run on the lane twin of
their workspace. ``minverse_lanes`` is the whole recursion so: each sample of a group gets,
bit for bit, the numbers that the scalar pass gives it in the same compiled batch (the
samples after a chunk's last whole group take the scalar pass). That holds for the machine
code numba keeps in its cache, which every process after the first loads; in the process
that compiles it, LLVM's just-in-time compiler may fuse the group's multiply-adds
differently, to the last bits. The derivatives' forward passes in lanes
(``rnea_derivatives_lanes``, ``aba_derivatives_lanes``) agree with their scalar pass to the
last bits only. Models with joints of several coordinates anywhere in the tree (spherical)
take the lanes too."""

from __future__ import annotations

import json
import subprocess
import sys

import numba
import numpy as np
import pinocchio as pin
import pytest
from joint_cases import random_model

import cgadyn
from cgadyn import oracle
from cgadyn.algorithms._workspace import chunks
from cgadyn.kernels.lanes import W

pytestmark = pytest.mark.slow

BATCH = 41  # on any thread count, whole groups and a tail in some chunk
MODELS = ["panda", "solo12", "talos", "spherical_tree"]


def _spherical_tree():
    return cgadyn.from_pinocchio(random_model("tree", [
        (0, pin.JointModelSpherical()), (1, pin.JointModelSpherical()),
        (2, pin.JointModelRY()), (1, pin.JointModelPZ()), (4, pin.JointModelSpherical()),
        (5, pin.JointModelRUBZ())], 2))


def _model(name):
    return _spherical_tree() if name == "spherical_tree" else oracle.models(name)[0]


def _tails_as_group_samples(s):
    """The states of ``s`` with each tail sample (the scalar pass) set to a sample of its
    chunk's first group (the lanes); the pairs (tail, group sample)."""
    q, v, a, tau = s.q.copy(), s.v.copy(), s.a.copy(), s.tau.copy()
    starts, stops = chunks(q.shape[0], numba.get_num_threads())
    pairs = []
    for lo, hi in zip(starts, stops, strict=True):
        full = lo + (hi - lo) // W * W
        for i in range(full, hi) if full > lo else ():
            g = lo + (i - full) % W
            q[i], v[i], a[i], tau[i] = q[g], v[g], a[g], tau[g]
            pairs.append((i, g))
    assert pairs, "no chunk with a group and a tail"
    return q, v, a, tau, pairs


def _close(x, y, tol):
    return np.abs(x - y).max() <= tol * max(np.abs(y).max(), 1.0)


@pytest.mark.parametrize("name", MODELS)
def test_lanes_agree_with_the_scalar_pass(name):
    model = _model(name)
    q, v, a, tau, pairs = _tails_as_group_samples(oracle.sample(model, BATCH, 11))
    minv = cgadyn.minverse(model, q)
    derivatives = (*cgadyn.rnea_derivatives(model, q, v, a),
                   *cgadyn.aba_derivatives(model, q, v, tau))
    for i, g in pairs:
        assert _close(minv[i], minv[g], 1e-13)
        for x in derivatives:
            assert _close(x[i], x[g], 1e-12)


BITWISE = """
import json, sys
import numpy as np, cgadyn
sys.path.insert(0, {tests!r})
import test_lanes as t
same = {{}}
for name in t.MODELS:
    model = t._model(name)
    q, _, _, _, pairs = t._tails_as_group_samples(t.oracle.sample(model, t.BATCH, 11))
    minv = cgadyn.minverse(model, q)
    same[name] = all(np.array_equal(minv[i], minv[g]) for i, g in pairs)
print(json.dumps(same))
"""


def test_minverse_lanes_equal_the_scalar_pass_bit_for_bit():
    """In a new process, on the machine code that the test above compiled and cached."""
    for name in MODELS:  # compiled and cached here, if not already
        cgadyn.minverse(_model(name), oracle.sample(_model(name), BATCH, 11).q)
    from pathlib import Path

    done = subprocess.run([sys.executable, "-c", BITWISE.format(tests=str(Path(__file__).parent))],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == dict.fromkeys(MODELS, True)


def test_spherical_joints_take_the_lanes_and_agree_with_single_calls():
    """M⁻¹ of a tree with spherical joints below other joints, in a batch (groups of W in
    lanes): each sample equals its single call and inverts M."""
    model = _spherical_tree()
    s = oracle.sample(model, BATCH, 12)
    many = cgadyn.minverse(model, s.q)
    for b in range(BATCH):
        one = cgadyn.minverse(model, s.q[b])
        assert _close(many[b], one, 1e-12)
        M = cgadyn.crba(model, s.q[b])
        assert np.abs(many[b] @ M - np.eye(model.nv)).max() < 1e-10
