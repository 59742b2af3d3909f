"""Straight-line kernels lowered to LLVM IR from their own source, typed by a caller at once.

The generated kernels (``_generated``: a motor product, an inertia congruence) are
straight-line code: loads of array coefficients at constant indices, products and sums,
stores at constant indices, returned values. Inlined by numba, each of their hundreds of
operations is typed and lowered again in every caller (numba resolves every ``+`` and
``*`` through its typing templates), which made the greater part of a first compilation;
yet nothing in such a body needs typing. ``kernel`` reads the function's source once (its
abstract syntax tree) and makes it a numba intrinsic whose code generator emits the same
operations, in the same order, straight into the caller's LLVM function: a caller types
one call, and gets the machine code that numba's inlining gave (the same loads,
``fmul``/``fadd``/``fsub``/``fdiv`` and stores, to which the caller's ``fastmath`` flags
are applied as to its own operations).

The same kernel runs on the ``W`` samples of a lane group (``lane_arrays``): where an
argument is a ``LaneArray`` or ``Lanes``, an element is a vector of ``W`` doubles loaded
from the lanes layout, a number meeting a vector is put in every lane, and the operations
are the vector instructions ``lanes`` uses (``contract`` flagged, as there), as numba
compiled them from the same source through ``lane_arrays``' operators.

Called from Python, a kernel runs its source as written (and under ``NUMBA_DISABLE_JIT``
``kernel`` returns the function itself). The default; ``CGADYN_KERNELS=numba`` asks for
numba's inlining instead (``STRAIGHT``).

What a straight-line body may hold (anything else is refused when the kernel is declared):
``a, b = x[0], x[1, 2]`` and ``c = expr`` (each name bound once), ``out[i] = expr``,
``out[i] += name``, ``return expr`` or ``return expr, expr, ...`` (last); expressions of
names, numbers, ``x[i]`` at constant indices, ``+ - * /``, unary ``-``, and ``** n`` for a
constant integer ``n >= 1``.

numba's own route to the same end, an ``overload`` of the function inlined into the
caller (``inline="always"``), gave wrong numbers in the constrained dynamics (the wrapper's
typed IR inlined into a function that numba had itself inlined), so the intrinsic is the
kernel's numba type directly.
"""

from __future__ import annotations

import ast
import functools
import inspect
import os
import textwrap
from collections.abc import Callable

import numba
from llvmlite import ir
from numba.core import cgutils, types
from numba.core.extending import _Intrinsic
from numba.np.arrayobj import load_item, store_item

from .._jit import inline
from .lane_arrays import LaneArray, element_pointer
from .lanes import _FLAGS, _VEC, LANES, Lanes, W

_F64 = ir.DoubleType()
_DOUBLE = types.float64
_I32 = ir.IntType(32)


class NotStraight(ValueError):
    """A kernel's body holds something other than straight-line arithmetic."""


def _index(node: ast.expr, what: str) -> tuple[int, ...]:
    parts = node.elts if isinstance(node, ast.Tuple) else [node]
    index = []
    for p in parts:
        if not (isinstance(p, ast.Constant) and type(p.value) is int and p.value >= 0):
            raise NotStraight(f"{what}: an index that is not a constant integer >= 0")
        index.append(p.value)
    return tuple(index)


class Body:
    """A kernel's statements read from its source and checked: its parameters, the rank
    each array parameter is indexed with, and how many values it returns."""

    def __init__(self, fn: Callable):
        definition = ast.parse(textwrap.dedent(inspect.getsource(fn))).body[0]
        args = definition.args
        if not isinstance(definition, ast.FunctionDef) or args.vararg or args.kwarg or \
                args.kwonlyargs or args.defaults or args.posonlyargs:
            raise NotStraight(f"{fn.__name__}: expected a function of plain parameters")
        self.name = fn.__name__
        self.params = [a.arg for a in args.args]
        body = definition.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body = body[1:]  # the docstring
        self.statements = body
        self.ranks: dict[str, int] = {}
        self.stored: set[str] = set()  # the parameters written into
        self.returns: int | None = None  # None: nothing; 0: one value; n: a tuple of n
        bound = set(self.params)
        for i, st in enumerate(body):
            self._check(st, bound, last=i == len(body) - 1)

    def _subscript(self, node: ast.Subscript, what: str) -> None:
        if not (isinstance(node.value, ast.Name) and node.value.id in self.params):
            raise NotStraight(f"{what}: only a parameter may be indexed")
        rank = len(_index(node.slice, what))
        if self.ranks.setdefault(node.value.id, rank) != rank:
            raise NotStraight(f"{what}: {node.value.id} is indexed with different ranks")

    def _expr(self, node: ast.expr, bound: set[str], what: str) -> None:
        if isinstance(node, ast.Name):
            if node.id not in bound:
                raise NotStraight(f"{what}: {node.id} is used before it is bound")
        elif isinstance(node, ast.Constant):
            if type(node.value) not in (int, float):
                raise NotStraight(f"{what}: a constant that is not a number")
        elif isinstance(node, ast.Subscript):
            self._subscript(node, what)
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            self._expr(node.operand, bound, what)
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            n = node.right
            if not (isinstance(n, ast.Constant) and type(n.value) is int and n.value >= 1):
                raise NotStraight(f"{what}: a power whose exponent is not an integer >= 1")
            self._expr(node.left, bound, what)
        elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult,
                                                                   ast.Div)):
            self._expr(node.left, bound, what)
            self._expr(node.right, bound, what)
        else:
            raise NotStraight(f"{what}: {ast.unparse(node)} is not straight-line arithmetic")

    def _bind(self, target: ast.expr, bound: set[str], what: str) -> None:
        if not isinstance(target, ast.Name) or target.id in bound:
            raise NotStraight(f"{what}: each name is bound once, to one value")
        bound.add(target.id)

    def _check(self, st: ast.stmt, bound: set[str], last: bool) -> None:
        what = f"{self.name}, line {st.lineno}"
        if isinstance(st, ast.Assign) and len(st.targets) == 1:
            target = st.targets[0]
            if isinstance(target, ast.Tuple):
                if not (isinstance(st.value, ast.Tuple)
                        and len(st.value.elts) == len(target.elts)):
                    raise NotStraight(f"{what}: names bound to something other than a tuple")
                for v in st.value.elts:
                    self._expr(v, bound, what)
                for t in target.elts:
                    self._bind(t, bound, what)
                return
            self._expr(st.value, bound, what)
            if isinstance(target, ast.Subscript):
                self._subscript(target, what)
                self.stored.add(target.value.id)
            else:
                self._bind(target, bound, what)
        elif isinstance(st, ast.AugAssign) and isinstance(st.op, ast.Add) and \
                isinstance(st.target, ast.Subscript):
            self._subscript(st.target, what)
            self.stored.add(st.target.value.id)
            self._expr(st.value, bound, what)
        elif isinstance(st, ast.Return) and st.value is not None and last:
            values = st.value.elts if isinstance(st.value, ast.Tuple) else [st.value]
            for v in values:
                self._expr(v, bound, what)
            self.returns = len(values) if isinstance(st.value, ast.Tuple) else 0
        else:
            line = ast.unparse(st).splitlines()[0][:60]
            raise NotStraight(f"{what}: {line} is not a straight-line statement")

    def signature(self, args: tuple[types.Type, ...]):
        """The call's signature, or None where an argument is not what the body reads:
        arrays of doubles (or ``LaneArray``) of the ranks the body indexes, or for a vector
        only read, a tuple of numbers or ``Lanes`` (``layout.coefficients``' registers);
        numbers (or ``Lanes``) for the other parameters. The values are ``Lanes`` where any
        argument is of the lanes."""
        lanes = False
        for name, ty in zip(self.params, args, strict=True):
            if name in self.ranks:
                if isinstance(ty, LaneArray) and ty.ndim == self.ranks[name]:
                    lanes = True
                elif isinstance(ty, types.BaseTuple) and self.ranks[name] == 1 and \
                        name not in self.stored and all(
                            isinstance(t, (types.Float, types.Integer, Lanes)) for t in ty):
                    lanes = lanes or any(isinstance(t, Lanes) for t in ty)
                elif not (isinstance(ty, types.Array) and ty.dtype == _DOUBLE
                          and ty.ndim == self.ranks[name]):
                    return None
            elif isinstance(ty, Lanes):
                lanes = True
            elif not isinstance(ty, (types.Float, types.Integer)):
                return None
        value = LANES if lanes else types.float64
        if self.returns is None:
            result = types.none
        elif self.returns == 0:
            result = value
        else:
            result = types.UniTuple(value, self.returns)
        return result(*args)


class _Emitter:
    """The LLVM IR of one call of a straight-line body, emitted into the caller."""

    def __init__(self, body: Body, context, builder, signature, args):
        self.body, self.context, self.builder = body, context, builder
        self.values: dict[str, ir.Value] = {}
        self.arrays: dict[str, tuple] = {}
        for name, ty, value in zip(body.params, signature.args, args, strict=True):
            if isinstance(ty, LaneArray):
                view = cgutils.create_struct_proxy(ty)(context, builder, value=value)
                data = context.make_array(ty.array)(context, builder, view.array).data
                self.arrays[name] = (ty, data, view.offset, view.s0, view.s1)
            elif isinstance(ty, types.BaseTuple):
                self.arrays[name] = (ty, value)
            elif isinstance(ty, types.Array):
                array = context.make_array(ty)(context, builder, value)
                self.arrays[name] = (ty, array.data, cgutils.unpack_tuple(builder, array.shape),
                                     cgutils.unpack_tuple(builder, array.strides))
            elif isinstance(ty, Lanes):
                self.values[name] = value
            else:
                self.values[name] = context.cast(builder, value, ty, types.float64)

    def _lane_pointer(self, entry, index: tuple[int, ...]) -> ir.Value:
        """The element at constant ``index`` of a view of one, two or three dimensions, by
        ``lane_arrays``' own addressing (``element_pointer``)."""
        ty, data, offset, s0, s1 = entry
        intp = self.context.get_value_type(types.intp)
        return element_pointer(self.builder, data, offset, s0, s1, [intp(i) for i in index])

    def load(self, node: ast.Subscript) -> ir.Value:
        entry, index = self.arrays[node.value.id], _index(node.slice, "")
        if isinstance(entry[0], LaneArray):
            return self.builder.load(self._lane_pointer(entry, index), align=8)
        if isinstance(entry[0], types.BaseTuple):  # numba's static getitem of a tuple
            ty, value = entry
            item = self.builder.extract_value(value, index[0])
            if isinstance(ty[index[0]], Lanes):
                return item
            return self.context.cast(self.builder, item, ty[index[0]], types.float64)
        ty, data, shape, strides = entry
        intp = self.context.get_value_type(types.intp)
        ptr = cgutils.get_item_pointer2(self.context, self.builder, data, shape, strides,
                                        ty.layout, [intp(i) for i in index])
        return load_item(self.context, self.builder, ty, ptr)

    def store(self, node: ast.Subscript, value: ir.Value) -> None:
        entry, index = self.arrays[node.value.id], _index(node.slice, "")
        if isinstance(entry[0], LaneArray):
            self.builder.store(self._vector(value), self._lane_pointer(entry, index), align=8)
            return
        ty, data, shape, strides = entry
        intp = self.context.get_value_type(types.intp)
        ptr = cgutils.get_item_pointer2(self.context, self.builder, data, shape, strides,
                                        ty.layout, [intp(i) for i in index])
        store_item(self.context, self.builder, ty, value, ptr)

    def _vector(self, value: ir.Value) -> ir.Value:
        """A number in every lane (``lanes.splat``); a vector as it is."""
        if value.type == _VEC:
            return value
        v = ir.Constant(_VEC, ir.Undefined)
        for i in range(W):
            v = self.builder.insert_element(v, value, _I32(i))
        return v

    def _binary(self, op: str, left: ir.Value, right: ir.Value) -> ir.Value:
        if left.type == _VEC or right.type == _VEC:  # lane_arrays' operators
            return getattr(self.builder, op)(self._vector(left), self._vector(right),
                                             flags=_FLAGS)
        return getattr(self.builder, op)(left, right)

    def expr(self, node: ast.expr) -> ir.Value:
        if isinstance(node, ast.Name):
            return self.values[node.id]
        if isinstance(node, ast.Constant):
            return ir.Constant(_F64, float(node.value))
        if isinstance(node, ast.Subscript):
            return self.load(node)
        if isinstance(node, ast.UnaryOp):
            if isinstance(node.operand, ast.Constant):  # a negative number, as Python folds it
                return ir.Constant(_F64, -float(node.operand.value))
            value = self.expr(node.operand)
            if value.type == _VEC:
                return self.builder.fneg(value)  # lane_arrays' negation
            return self.builder.fsub(ir.Constant(_F64, -0.0), value)  # numba's
        if isinstance(node.op, ast.Pow):  # numba's power by a constant integer, unrolled
            value, result, n = self.expr(node.left), None, node.right.value
            while n:
                if n & 1:
                    result = value if result is None else self._binary("fmul", result, value)
                n >>= 1
                if n:
                    value = self._binary("fmul", value, value)
            return result
        op = {ast.Add: "fadd", ast.Sub: "fsub", ast.Mult: "fmul", ast.Div: "fdiv"}
        left, right = self.expr(node.left), self.expr(node.right)
        return self._binary(op[type(node.op)], left, right)

    def run(self, signature) -> ir.Value:
        for st in self.body.statements:
            if isinstance(st, ast.Assign):
                target = st.targets[0]
                if isinstance(target, ast.Tuple):
                    values = [self.expr(v) for v in st.value.elts]
                    for t, v in zip(target.elts, values, strict=True):
                        self.values[t.id] = v
                elif isinstance(target, ast.Subscript):
                    self.store(target, self.expr(st.value))
                else:
                    self.values[target.id] = self.expr(st.value)
            elif isinstance(st, ast.AugAssign):
                old = self.load(st.target)
                self.store(st.target, self._binary("fadd", old, self.expr(st.value)))
            else:
                result = signature.return_type
                if isinstance(st.value, ast.Tuple):
                    values = [self.expr(v) for v in st.value.elts]
                    if isinstance(result.dtype, Lanes):
                        values = [self._vector(v) for v in values]
                    return self.context.make_tuple(self.builder, result, values)
                value = self.expr(st.value)
                return self._vector(value) if isinstance(result, Lanes) else value
        return self.context.get_dummy_value()


class Kernel(_Intrinsic):
    """A straight-line kernel: to numba an intrinsic that emits its body into the caller;
    called from Python, its source (``py_func``) as written."""

    def __init__(self, fn: Callable):
        body = Body(fn)

        def typer(typingctx, *args):
            sig = body.signature(args)
            if sig is None:
                return None

            def codegen(context, builder, signature, values):
                return _Emitter(body, context, builder, signature, values).run(signature)

            return sig, codegen

        # numba folds an intrinsic's arguments by the names of its typer's parameters
        params = ", ".join(body.params)
        scope = {"typer": typer}
        exec(f"def {body.name}(typingctx, {params}):\n"  # noqa: S102
             f"    return typer(typingctx, {params})\n", scope)
        super().__init__(body.name, scope[body.name])
        functools.update_wrapper(self, fn)
        self.py_func, self.body = fn, body
        self._register()

    def __call__(self, *args):
        return self.py_func(*args)


STRAIGHT = os.environ.get("CGADYN_KERNELS", "straight") != "numba"
"""Whether the generated kernels are emitted from their source (the default) or, with
``CGADYN_KERNELS=numba``, inlined by numba (``_jit.inline``). Emitted, a cold first
``cgadyn.aba`` compiles in half the time, with bitwise the same numbers and, the cores
counting no references (``_jit.core``), the same speed (``validation/results/ab_speed.md``).
"""


def kernel(fn: Callable) -> Callable:
    """Declare the straight-line kernel ``fn``: a ``Kernel`` where ``STRAIGHT``, else
    inlined by numba into every compiled caller (``_jit.inline``); ``fn`` itself under
    ``NUMBA_DISABLE_JIT``."""
    if numba.config.DISABLE_JIT:
        return fn
    return Kernel(fn) if STRAIGHT else inline(fn)
