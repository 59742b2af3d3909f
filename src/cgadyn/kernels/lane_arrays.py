"""The kernels written for numbers, run on ``W`` samples at once.

The kernels of ``cgadyn.kernels`` (motor products, the rigid moves of eqs. 4 and 16, the
joint motors of eq. 6) read numbers from arrays, combine them with ``+``, ``-`` and ``*``
and write numbers into arrays. Here Python's arithmetic operators are defined on ``Lanes``
(and between a number and ``Lanes``, the number in every lane), and ``lane_array`` views a
flat array in the lanes layout (element ``x`` of sample ``l`` at ``x * W + l``) as an array
of ``Lanes`` that a kernel indexes as it indexes an array of numbers: ``a[i]`` (one index)
or ``a[i, k]`` (a matrix; ``a[i]`` is then its row i; ``lane_tensor``'s ``a[j]`` a
matrix, ``a[j, i]`` its row i, ``a[j, i, k]`` a number). So the same
kernel, unchanged, computes one sample on numbers or ``W`` samples on vectors, with the same
operations in the same order.

A view holds the flat array and an offset, no reference of its own: it is valid while the
array is (workspace arrays, within one compiled call). Under ``NUMBA_DISABLE_JIT=1`` the
same is done by numpy: ``Lanes`` are arrays of ``W`` numbers, with numpy's operators, and
``lane_array`` is a small class.
"""

from __future__ import annotations

import math
import operator

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils, datamodel
from numba.extending import make_attribute_wrapper, overload

from .._jit import inline, intrinsic
from .lanes import _VEC, LANES, Lanes, W, add, div, mul, splat, sub

_NUMBER = (types.Float, types.Integer)


class LaneArray(types.Type):
    """A view of a flat float array as an array of ``Lanes`` of one, two or three
    dimensions (the strides of the first two, in elements, ``s0`` and ``s1``)."""

    def __init__(self, array, ndim):
        self.array, self.ndim = array, ndim
        super().__init__(name=f"LaneArray({array}, {ndim})")


@datamodel.register_default(LaneArray)
class _LaneArrayModel(datamodel.models.StructModel):
    def __init__(self, dmm, fe_type):
        members = [("array", fe_type.array), ("offset", types.intp), ("s0", types.intp),
                   ("s1", types.intp)]
        super().__init__(dmm, fe_type, members)


make_attribute_wrapper(LaneArray, "array", "array")
make_attribute_wrapper(LaneArray, "offset", "offset")
make_attribute_wrapper(LaneArray, "s0", "s0")
make_attribute_wrapper(LaneArray, "s1", "s1")


def _view(ndim):
    def typer(typingctx, array, offset, s0, s1):
        def codegen(context, builder, signature, args):
            view = cgutils.create_struct_proxy(signature.return_type)(context, builder)
            view.array = args[0]
            if context.enable_nrt:  # a new reference, where references are counted
                context.nrt.incref(builder, signature.args[0], args[0])
            view.offset = context.cast(builder, args[1], signature.args[1], types.intp)
            view.s0 = context.cast(builder, args[2], signature.args[2], types.intp)
            view.s1 = context.cast(builder, args[3], signature.args[3], types.intp)
            return view._getvalue()

        return LaneArray(array, ndim)(array, offset, s0, s1), codegen

    return typer


_vector = intrinsic(_view(1))
_matrix = intrinsic(_view(2))
_tensor = intrinsic(_view(3))


@numba.njit(inline="always")
def lane_array(array, offset):
    """Elements ``offset + i`` of ``array`` in the lanes layout, as ``Lanes`` ``a[i]``."""
    return _vector(array, offset, 0, 0)


@numba.njit(inline="always")
def lane_matrix(array, offset, cols):
    """Elements ``offset + i * cols + k`` of ``array`` in the lanes layout, as ``Lanes``
    ``a[i, k]``; ``a[i]`` is row i, a ``lane_array``."""
    return _matrix(array, offset, cols, 0)


@numba.njit(inline="always")
def lane_tensor(array, offset, rows, cols):
    """``a[j]`` the ``lane_matrix`` of ``rows`` x ``cols`` elements at ``offset + j * rows *
    cols`` of ``array``."""
    return _tensor(array, offset, rows * cols, cols)


@intrinsic
def offset_in(typingctx, x, base):
    """How many numbers ``x``'s data lie after ``base``'s."""

    def codegen(context, builder, signature, args):
        at = [builder.ptrtoint(context.make_array(t)(context, builder, a).data, ir.IntType(64))
              for t, a in zip(signature.args, args, strict=True)]
        return builder.sdiv(builder.sub(at[0], at[1]), ir.IntType(64)(8))

    return types.intp(x, base), codegen


def element_pointer(builder, data, offset, s0, s1, index):
    """The address, as a pointer to ``W`` doubles, of element ``index`` (intp values, one
    per dimension) of a ``LaneArray`` with the flat array's ``data`` pointer, ``offset``,
    ``s0`` and ``s1``: element ``(offset + i0 s0 + i1 s1 + i2) W`` of the flat array. The
    lanes layout's one rule of addressing: ``a[i]``, ``a[i, k]`` and ``a[j, i, k]`` below
    and the kernels that ``kernels.straight`` emits address elements by it."""
    at = offset
    for i, stride in zip(index[:-1], (s0, s1), strict=False):
        at = builder.add(at, builder.mul(i, stride))
    at = builder.add(at, index[-1])
    ptr = builder.gep(data, [builder.mul(at, ir.Constant(at.type, W))])
    return builder.bitcast(ptr, _VEC.as_pointer())


def _element_of(context, builder, view_type, view, index_type, index):
    """``element_pointer`` of a ``LaneArray`` value at a numba index (an integer or a tuple
    of integers)."""
    v = cgutils.create_struct_proxy(view_type)(context, builder, value=view)
    data = context.make_array(view_type.array)(context, builder, v.array).data
    if isinstance(index_type, types.BaseTuple):
        values = [context.cast(builder, x, t, types.intp)
                  for x, t in zip(cgutils.unpack_tuple(builder, index), index_type, strict=True)]
    else:
        values = [context.cast(builder, index, index_type, types.intp)]
    return element_pointer(builder, data, v.offset, v.s0, v.s1, values)


@intrinsic
def _load_element(typingctx, a, i):
    def codegen(context, builder, signature, args):
        ptr = _element_of(context, builder, signature.args[0], args[0], signature.args[1],
                          args[1])
        return builder.load(ptr, align=8)

    return LANES(a, i), codegen


@intrinsic
def _store_element(typingctx, a, i, x):
    def codegen(context, builder, signature, args):
        ptr = _element_of(context, builder, signature.args[0], args[0], signature.args[1],
                          args[1])
        builder.store(args[2], ptr, align=8)
        return context.get_dummy_value()

    return types.none(a, i, x), codegen


def _full_index(a, i) -> bool:
    """Whether ``i`` names one element of the view ``a`` (one index per dimension)."""
    if isinstance(i, types.Integer):
        return a.ndim == 1
    return (isinstance(i, types.BaseTuple) and len(i) == a.ndim
            and all(isinstance(t, types.Integer) for t in i))


@overload(operator.getitem)
def _getitem(a, i):
    if not isinstance(a, LaneArray):
        return None
    if _full_index(a, i):
        return lambda a, i: _load_element(a, i)
    if isinstance(i, types.Integer):  # a row (of a matrix) or a matrix (of a tensor)
        if a.ndim == 2:
            return lambda a, i: _vector(a.array, a.offset + i * a.s0, 0, 0)
        return lambda a, i: _matrix(a.array, a.offset + i * a.s0, a.s1, 0)
    if isinstance(i, types.BaseTuple) and len(i) == 2 and a.ndim == 3:
        return lambda a, i: _vector(a.array, a.offset + i[0] * a.s0 + i[1] * a.s1, 0, 0)
    return None


@overload(operator.setitem)
def _setitem(a, i, x):
    if not isinstance(a, LaneArray):
        return None
    if isinstance(x, _NUMBER):
        return lambda a, i, x: _setitem_lanes(a, i, splat(x))
    if isinstance(x, Lanes) and _full_index(a, i):
        return lambda a, i, x: _store_element(a, i, x)
    return None


@numba.njit(inline="always")
def _setitem_lanes(a, i, x):
    a[i] = x


def _binary(op, lanes_op):
    @overload(op)
    def _op(x, y):
        if isinstance(x, Lanes) and isinstance(y, Lanes):
            return lambda x, y: lanes_op(x, y)
        if isinstance(x, Lanes) and isinstance(y, _NUMBER):
            return lambda x, y: lanes_op(x, splat(y))
        if isinstance(x, _NUMBER) and isinstance(y, Lanes):
            return lambda x, y: lanes_op(splat(x), y)
        return None

    return _op


_binary(operator.add, add)
_binary(operator.sub, sub)
_binary(operator.mul, mul)
_binary(operator.truediv, div)
_binary(operator.iadd, add)
_binary(operator.isub, sub)
_binary(operator.imul, mul)


@intrinsic
def _sqrt(typingctx, x):
    def codegen(context, builder, signature, args):
        t = args[0].type
        f = cgutils.get_or_insert_function(builder.module, ir.FunctionType(t, [t]),
                                           f"llvm.sqrt.v{W}f64")
        return builder.call(f, [args[0]])

    return x(x), codegen


@overload(math.sqrt)
def _math_sqrt(x):
    if isinstance(x, Lanes):
        return lambda x: _sqrt(x)
    return None


@inline
def sqrt(x):
    """``math.sqrt`` of a number, or of each lane of ``Lanes``: for kernels that run on
    both (``math.sqrt`` itself would refuse an array of lanes in pure Python)."""
    return math.sqrt(x)


@intrinsic
def _negate(typingctx, x):
    def codegen(context, builder, signature, args):
        return builder.fneg(args[0])

    return x(x), codegen


@overload(operator.neg)
def _neg(x):
    if isinstance(x, Lanes):
        return lambda x: _negate(x)
    return None


@intrinsic
def _select_nonnegative(typingctx, x, a, b):
    def codegen(context, builder, signature, args):
        zero = ir.Constant(args[0].type, None)  # every lane 0.0
        return builder.select(builder.fcmp_ordered(">=", args[0], zero), args[1], args[2])

    return x(x, x, x), codegen


def select_nonnegative(x, a, b):
    """``a`` where ``x >= 0``, else ``b``: of numbers, or lane by lane of ``Lanes`` (one
    vector select, where a number's branch would split the lanes). For a kernel that picks
    between two formulas, each exact on its half of the domain (the planar joint's half
    angle, ``joints.planar``)."""
    out = np.where(np.asarray(x) >= 0.0, a, b)
    return out if out.ndim else float(out)


@overload(select_nonnegative)
def _select(x, a, b):
    if isinstance(x, Lanes):
        return lambda x, a, b: _select_nonnegative(x, a, b)
    if isinstance(x, types.Float):
        return lambda x, a, b: a if x >= 0.0 else b
    return None


@intrinsic
def _all_positive(typingctx, x):
    def codegen(context, builder, signature, args):
        t = args[0].type
        one = ir.Constant(t, [ir.Constant(ir.DoubleType(), 1.0)] * W)
        inf = ir.Constant(t, [ir.Constant(ir.DoubleType(), math.inf)] * W)
        ok = builder.and_(builder.fcmp_ordered(">", args[0], ir.Constant(t, None)),
                          builder.fcmp_ordered("<", builder.fdiv(one, args[0]), inf))
        every = ir.Constant(ir.IntType(W), (1 << W) - 1)
        return builder.icmp_unsigned("==", builder.bitcast(ok, ir.IntType(W)), every)

    return types.boolean(x), codegen


def positive(x):
    """True where a pivot ``x`` is positive and its inverse finite: of a number, or of
    every lane of ``Lanes`` (a pivot of a recursion that runs on both, ``minverse``)."""
    x = np.asarray(x)
    with np.errstate(divide="ignore"):
        return bool(np.all(x > 0.0) and np.all(np.isfinite(1.0 / x)))


@overload(positive)
def _positive(x):
    if isinstance(x, Lanes):
        return lambda x: _all_positive(x)
    if isinstance(x, types.Float):
        return lambda x: x > 0.0 and math.isfinite(1.0 / x)
    return None


if numba.config.DISABLE_JIT:  # pure Python: numpy does the arithmetic of W numbers

    class _PyLaneArray:
        def __init__(self, array, offset, s0=0, s1=0, ndim=1):
            self.flat, self.offset, self.s0, self.s1, self.ndim = (array.reshape(-1), offset,
                                                                   s0, s1, ndim)

        def _at(self, i):
            if len(i) == 3:
                return self.offset + i[0] * self.s0 + i[1] * self.s1 + i[2]
            return self.offset + i[0] * self.s0 + i[1]

        def __getitem__(self, i):
            if isinstance(i, tuple) and len(i) == 2 and self.ndim == 3:
                return _PyLaneArray(self.flat, self.offset + i[0] * self.s0 + i[1] * self.s1)
            if isinstance(i, tuple):
                o = self._at(i) * W
                return np.array(self.flat[o:o + W])
            if self.ndim == 1:
                o = (self.offset + i) * W
                return np.array(self.flat[o:o + W])
            return _PyLaneArray(self.flat, self.offset + i * self.s0, self.s1, 0, self.ndim - 1)

        def __setitem__(self, i, x):
            o = self._at(i) if isinstance(i, tuple) else self.offset + i
            self.flat[o * W:o * W + W] = x

    def sqrt(x):  # noqa: F811
        """``math.sqrt`` of a number, or of each lane."""
        return np.sqrt(x)

    def offset_in(x, base):  # noqa: F811
        """How many numbers ``x``'s data lie after ``base``'s."""
        return (x.ctypes.data - base.ctypes.data) // 8

    def lane_array(array, offset):  # noqa: F811
        """Elements ``offset + i`` of ``array`` in the lanes layout."""
        return _PyLaneArray(array, offset)

    def lane_matrix(array, offset, cols):  # noqa: F811
        """Elements ``offset + i * cols + k`` of ``array`` in the lanes layout."""
        return _PyLaneArray(array, offset, cols, 0, 2)

    def lane_tensor(array, offset, rows, cols):  # noqa: F811
        """``a[j]`` the matrix of ``rows`` x ``cols`` elements at ``offset + j rows cols``."""
        return _PyLaneArray(array, offset, rows * cols, cols, 3)
