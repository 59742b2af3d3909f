"""Faults on every path: no leaks, the same error on every call, safe threads.

Compiled code reports a fault by a status code and Python raises (``algorithms/status.py``):
raising inside numba's nopython mode would leak a reference to every array of the call.
"""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import cgadyn

PANDA = cgadyn.load("panda")
Z = np.zeros(9)


def _failing(call, times: int) -> None:
    for _ in range(times):
        try:
            call()
        except ValueError:
            pass
        else:
            raise AssertionError("expected a ValueError")


@pytest.mark.slow
@pytest.mark.parametrize("batch", [False, True])
def test_failing_calls_leak_no_references(batch):
    q = np.zeros((64, 9)) if batch else Z.copy()
    q[..., 3] = np.nan
    v = np.zeros_like(q)
    for call in (lambda: cgadyn.rnea(PANDA, q, v, v), lambda: cgadyn.aba(PANDA, q, v, v),
                 lambda: cgadyn.crba(PANDA, q)):
        _failing(call, 10)  # compile, register
        gc.collect()
        before = sys.getrefcount(q), sys.getrefcount(v)
        _failing(call, 1000)
        gc.collect()
        assert (sys.getrefcount(q), sys.getrefcount(v)) == before


def _rss_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


@pytest.mark.slow
def test_failing_batches_free_their_memory():
    """Twenty failing batches of 1e5 states used to keep about 140 MiB for good."""
    q = np.random.default_rng(0).uniform(-1, 1, (100_000, 9))
    q[-1, 0] = np.nan
    _failing(lambda: cgadyn.rnea(PANDA, q, q, q), 2)
    gc.collect()
    start = _rss_mib()
    _failing(lambda: cgadyn.rnea(PANDA, q, q, q), 20)
    gc.collect()
    assert _rss_mib() - start < 20


@pytest.mark.parametrize("algorithm", ["rnea", "aba", "nonlinear_effects", "energy"])
def test_overflow_is_the_same_error_on_every_call(algorithm):
    """v = 1e160 overflows: the first call and the tenth say so alike (the fast path too)."""
    v = np.full(9, 1e160)
    args = {"rnea": (Z, v, Z), "aba": (Z, v, Z), "nonlinear_effects": (Z, v),
            "energy": (Z, v)}[algorithm]
    f = getattr(cgadyn, algorithm)
    messages = set()
    for _ in range(10):
        with pytest.raises(ValueError, match="NaN or inf from finite inputs") as err:
            f(PANDA, *args)
        messages.add(str(err.value))
    assert len(messages) == 1
    assert "max |v| = 1e+160" in messages.pop()


def test_crba_overflow_is_reported():
    q = Z.copy()
    q[7] = 1e160  # a finger's prismatic joint, 1e160 m out
    for _ in range(3):
        with pytest.raises(ValueError, match="crba produced NaN or inf from finite inputs"):
            cgadyn.crba(PANDA, q)


def _two_links(tip_mass: str) -> str:
    return textwrap.dedent(f"""
        <robot name="subnormal">
          <link name="base"/>
          <link name="l1"><inertial><mass value="1"/><origin xyz="0 0 0.5"/>
            <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <link name="l2"><inertial><mass value="{tip_mass}"/><origin xyz="0 0 0.5"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
            <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
          <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
            <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
            <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
        </robot>""")


@pytest.mark.parametrize("mass", ["1e-310", "0"])
def test_singular_subtree_is_the_same_error_on_every_call(mass):
    model = cgadyn.load(_two_links(mass))
    for _ in range(10):
        with pytest.raises(ValueError, match="singular articulated-body inertia at joint 'j2'"):
            cgadyn.aba(model, [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="sample 0: singular .* 'j2'"):
        cgadyn.aba(model, np.zeros((3, 2)), np.zeros((3, 2)), np.zeros((3, 2)))
    for name, args in (("aba_derivatives", 3), ("minverse", 1)):  # M⁻¹ of 8 samples at once
        with pytest.raises(ValueError, match="j2") as one:
            getattr(cgadyn, name)(model, *[np.zeros(2)] * args)
        with pytest.raises(ValueError) as batch:
            getattr(cgadyn, name)(model, *[np.zeros((20, 2))] * args)
        assert str(batch.value) == "sample 0: " + str(one.value)


THREADS = """
import threading, numpy as np, cgadyn
m = cgadyn.load("panda")
rng = np.random.default_rng(0)
q, v, a = (rng.uniform(-1, 1, (256, 9)) for _ in range(3))
want = cgadyn.rnea(m, q, v, a), cgadyn.aba(m, q, v, a), cgadyn.crba(m, q)
bad = []
def work():
    for _ in range(25):
        got = cgadyn.rnea(m, q, v, a), cgadyn.aba(m, q, v, a), cgadyn.crba(m, q)
        bad.extend(not np.array_equal(g, w) for g, w in zip(got, want))
threads = [threading.Thread(target=work) for _ in range(4)]
for t in threads: t.start()
for t in threads: t.join()
import numba
print(numba.threading_layer(), sum(bad))
"""


@pytest.mark.slow
def test_batches_from_four_threads_under_the_workqueue_layer():
    """numba's workqueue layer aborts the process when two threads enter parallel code at
    once; cgadyn runs one batch at a time."""
    env = dict(os.environ, NUMBA_THREADING_LAYER="workqueue", NUMBA_NUM_THREADS="2")
    run = subprocess.run([sys.executable, "-c", THREADS], env=env, capture_output=True,
                         text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.split() == ["workqueue", "0"]
