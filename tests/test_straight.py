"""The generated kernels emitted from their source (``kernels.straight``) compute what numba
compiles from the same source: bitwise, on numbers and on lane groups, with and without
fused multiply-adds, with an output that aliases an input; a body that is not straight-line
is refused by name."""

from __future__ import annotations

import ast
import functools

import numba
import numpy as np
import pytest

from cgadyn.kernels import _generated
from cgadyn.kernels.lane_arrays import lane_array, lane_matrix
from cgadyn.kernels.lanes import W, store
from cgadyn.kernels.straight import Body, Kernel, NotStraight

pytestmark = pytest.mark.skipif(numba.config.DISABLE_JIT, reason="compiled kernels only")

KERNELS = sorted(name for name, value in vars(_generated).items()
                 if getattr(value, "__module__", "") == _generated.__name__)
"""The generated kernels, as ``kernel`` declared them (emitted by default; inlined by numba
with ``CGADYN_KERNELS=numba``)."""


@functools.cache
def straight(name: str) -> Kernel:
    """The generated kernel ``name`` emitted from its source, whatever the default."""
    return Kernel(getattr(_generated, name).py_func)


def shapes(body: Body) -> dict[str, tuple[int, ...]]:
    """Each array parameter's shape: one past the largest index the body reads or writes."""
    found: dict[str, list[int]] = {}
    for node in ast.walk(ast.Module(body=body.statements, type_ignores=[])):
        if isinstance(node, ast.Subscript):
            parts = node.slice.elts if isinstance(node.slice, ast.Tuple) else [node.slice]
            cur = found.setdefault(node.value.id, [0] * len(parts))
            for k, p in enumerate(parts):
                cur[k] = max(cur[k], p.value + 1)
    return {name: tuple(s) for name, s in found.items()}


def wrappers(k: Kernel, fastmath):
    """``k`` called from compiled code (the intrinsic) and its source compiled by numba,
    inlined as the kernels were before, both under the same ``fastmath``."""
    params = ", ".join(k.body.params)
    source = numba.njit(inline="always", error_model="numpy")(k.py_func)
    scope = {"k": k, "source": source}
    exec(f"def a({params}):\n    return k({params})\n"
         f"def b({params}):\n    return source({params})\n", scope)
    jit = numba.njit(fastmath=fastmath, error_model="numpy")
    return jit(scope["a"]), jit(scope["b"])


def arguments(k: Kernel, rng, alias: bool) -> list:
    sh = shapes(k.body)
    args = [rng.standard_normal(sh[p]) if p in sh else float(rng.standard_normal())
            for p in k.body.params]
    if alias and "out" in k.body.params:  # out is also the input of its shape, read first
        i = k.body.params.index("out")
        same = [j for j, a in enumerate(args) if j != i and isinstance(a, np.ndarray)
                and a.shape == args[i].shape]
        if same:
            args[i] = args[same[0]]
    return args


def copied(args):
    out, seen = [], {}
    for a in args:
        if isinstance(a, np.ndarray):
            seen.setdefault(id(a), a.copy())
            out.append(seen[id(a)])
        else:
            out.append(a)
    return out


@pytest.mark.parametrize("name", KERNELS)
@pytest.mark.parametrize("fastmath", [False, {"contract"}])
def test_a_kernel_is_bitwise_numbas_compilation_of_its_source(name, fastmath):
    k = straight(name)
    mine, numbas = wrappers(k, fastmath)
    rng = np.random.default_rng(len(name))
    for alias in (False, True):
        args = arguments(k, rng, alias)
        a, b = copied(args), copied(args)
        ra, rb = mine(*a), numbas(*b)
        assert (ra is None and rb is None) or np.array_equal(np.asarray(ra), np.asarray(rb))
        for x, y in zip(a, b, strict=True):
            if isinstance(x, np.ndarray):
                assert np.array_equal(x, y)


@pytest.mark.parametrize("name", ["inertia_apply", "twist_cross", "motor_mul", "dot",
                                  "inertia_congruence_downdate_add", "translator_rotor"])
def test_a_kernel_on_a_lane_group_is_numbas_lanes_compilation(name):
    """Arrays viewed as lane groups (``lane_array``, ``lane_matrix``): the vector
    instructions equal those numba compiles from the source through lane_arrays'
    operators, bitwise, for every lane."""
    k = straight(name)
    sh = shapes(k.body)
    params = k.body.params
    views, offsets, at = [], {}, 0
    for p in params:
        if p in sh:
            offsets[p] = at
            at += int(np.prod(sh[p]))
            views.append(f"lane_array(buf, {offsets[p]})" if len(sh[p]) == 1 else
                         f"lane_matrix(buf, {offsets[p]}, {sh[p][1]})")
        else:
            views.append(p)
    scalars = [p for p in params if p not in sh]
    source = numba.njit(inline="always", error_model="numpy")(k.py_func)
    scope = {"k": k, "source": source, "lane_array": lane_array, "lane_matrix": lane_matrix,
             "store": store}
    head = ", ".join(["buf", "res"] + scalars)
    keep = "store(res, 0, r)" if k.body.returns == 0 else "pass"
    exec(f"def a({head}):\n    r = k({', '.join(views)})\n    {keep}\n"
         f"def b({head}):\n    r = source({', '.join(views)})\n    {keep}\n", scope)
    jit = numba.njit(fastmath={"contract"}, error_model="numpy")
    rng = np.random.default_rng(7)
    buf = rng.standard_normal(at * W)
    numbers = [float(x) for x in rng.standard_normal(len(scalars))]
    a, b, ra, rb = buf.copy(), buf.copy(), np.zeros(W), np.zeros(W)
    jit(scope["a"])(a, ra, *numbers)
    jit(scope["b"])(b, rb, *numbers)
    assert np.array_equal(a, b) and np.array_equal(ra, rb)
    assert not np.array_equal(a, buf) or np.all(ra != 0.0)  # the kernel did write


def test_a_kernel_called_from_python_runs_its_source():
    a, b = np.arange(8.0), np.arange(8.0)[::-1].copy()
    out, ref = np.zeros(8), np.zeros(8)
    straight("motor_mul")(a, b, out)
    _generated.motor_mul.py_func(a, b, ref)
    assert np.array_equal(out, ref)


def test_a_body_that_is_not_straight_line_is_refused_by_line():
    def looped(x, out):
        for i in range(3):
            out[i] = x[i]

    def rebound(x, out):
        a = x[0]
        a = a * 2.0
        out[0] = a

    with pytest.raises(NotStraight, match=r"looped, line \d+: .*not a straight-line"):
        Kernel(looped)
    with pytest.raises(NotStraight, match="each name is bound once"):
        Kernel(rebound)
