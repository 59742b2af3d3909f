"""Compiled calls leave no memory behind: every allocation numba's runtime makes during a
call (an output, a batch's workspace, the owner it wraps around an argument array) is freed
when the call returns.

The cores are compiled without reference counts (``_jit.core``): they allocate nothing and
see only arrays their caller holds. This checks that promise where it could break (a core
keeping a reference, or dropping one, would unbalance the runtime's counts), on every
algorithm of the table, single and batched, on a fixed and a floating base, and on the
constrained dynamics and a contact rollout.
"""

from __future__ import annotations

import numpy as np
import pytest
from contact_cases import solo12_on_the_ground
from numba.core.runtime import _nrt_python, rtsys

import cgadyn
from cgadyn.algorithms.calls import run
from cgadyn.algorithms.table import ALGORITHMS


@pytest.fixture(autouse=True)
def _counting():
    """numba's runtime counts its allocations only when asked."""
    was = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    yield
    if not was:
        _nrt_python.memsys_disable_stats()


def _balance() -> tuple[int, int]:
    """Allocations and meminfos numba's runtime holds now (made minus freed)."""
    s = rtsys.get_allocation_stats()
    return s.alloc - s.free, s.mi_alloc - s.mi_free


def _inputs(model, alg, batch, rng):
    sizes = {"nq": model.nq, "nv": model.nv}
    arrays = []
    for _, size in alg.inputs:
        if size == "nq":
            q = [cgadyn.random_configuration(model, rng) for _ in range(batch or 1)]
            arrays.append(np.array(q) if batch else q[0])
        else:
            shape = (batch, sizes[size]) if batch else (sizes[size],)
            arrays.append(rng.uniform(-1, 1, shape))
    return tuple(arrays)


def _repeat_balanced(call, times: int = 5) -> None:
    call()  # compiles, and fills whatever caches a first call fills
    before = _balance()
    for _ in range(times):
        call()
    assert _balance() == before, f"{times} calls left {np.subtract(_balance(), before)} " \
                                 "(allocations, meminfos) unfreed"


@pytest.mark.parametrize("robot", ["panda", "solo12"])
@pytest.mark.parametrize("batch", [0, 3])
@pytest.mark.parametrize("alg", ALGORITHMS, ids=lambda a: a.name)
def test_every_algorithm_frees_what_it_allocates(robot, batch, alg):
    model = cgadyn.load(robot)
    arrays = _inputs(model, alg, batch, np.random.default_rng(0))
    options = (model.nlinks - 1, 0)[:len(alg.options)]
    wrenches = (batch, model.njoints, 6) if batch else (model.njoints, 6)
    f_ext = np.zeros(wrenches) if alg.forces else None
    _repeat_balanced(lambda: run(alg.name, model, arrays, f_ext=f_ext, options=options))


def test_constrained_dynamics_and_contact_rollouts_free_what_they_allocate():
    model, cm, q = solo12_on_the_ground()
    rng = np.random.default_rng(1)
    v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
    feet = [cgadyn.Constraint(model, "point", foot, q=q) for foot in ("FL_FOOT", "FR_FOOT")]
    _repeat_balanced(lambda: cgadyn.constrained_dynamics(model, q, v, tau, feet))
    _repeat_balanced(lambda: cgadyn.simulate(model, q, np.zeros(model.nv), 1e-3, 20,
                                             world=cgadyn.World(), collisions=cm,
                                             integrator="semi_implicit_euler"), times=2)
