"""Arithmetic on ``W`` samples at once: one vector instruction per operation.

A batch of one model runs the same recursion, with the same loops and branches, on every
sample; only the numbers differ. Laid out with the sample innermost (element ``x`` of
sample ``l`` at ``x * W + l`` of a flat array), the numbers of ``W`` samples are one
vector, and every multiply-add of the recursion becomes one instruction on ``W`` doubles
(AVX-512, or two AVX halves) instead of ``W`` scalar ones.

numba's optimiser does not form these instructions from scalar loops by itself (its
superword vectoriser is off by default, since numba 0.57), so the operations are written
in LLVM IR (``_jit.intrinsic``), on a numba type of their own, ``Lanes``, whose value is
an LLVM vector of ``W`` doubles: it stays in a register between operations; ``lane(x, l)``
reads one sample's number. (Under ``NUMBA_DISABLE_JIT=1`` the same operations work on
tuples.)
"""

from __future__ import annotations

import numba
from llvmlite import ir
from numba import types
from numba.core import datamodel
from numba.core.imputils import lower_cast

from .._jit import intrinsic

W = 8
"""Samples per vector: eight doubles, one AVX-512 register."""

_VEC = ir.VectorType(ir.DoubleType(), W)
_FLAGS = ("contract",)  # the cores' one liberty with IEEE arithmetic: fused multiply-adds


class Lanes(types.Type):
    """``W`` doubles, one number of each sample of a group: an LLVM vector in registers."""

    def __init__(self):
        super().__init__(name=f"Lanes{W}")

    def unify(self, typingctx, other):
        """A number and ``Lanes`` (the two arms of ``x if c else 0.0``) unify to ``Lanes``:
        the number in every lane."""
        if isinstance(other, (types.Float, types.Integer)):
            return self
        return None


LANES = Lanes()


@datamodel.register_default(Lanes)
class _LanesModel(datamodel.models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, _VEC)


@lower_cast(types.Float, Lanes)
@lower_cast(types.Integer, Lanes)
def _number_to_lanes(context, builder, fromty, toty, val):
    s = context.cast(builder, val, fromty, types.float64)
    v = ir.Constant(_VEC, ir.Undefined)
    for i in range(W):
        v = builder.insert_element(v, s, ir.Constant(ir.IntType(32), i))
    return v


def _element(context, builder, array_type, array, offset):
    data = context.make_array(array_type)(context, builder, array).data
    return builder.gep(data, [offset])


def _intp(context, builder, signature, args, i):
    return context.cast(builder, args[i], signature.args[i], types.intp)


@intrinsic
def load(typingctx, array, offset):
    """The ``W`` numbers ``array.flat[offset : offset + W]`` (``array`` C-contiguous)."""

    def codegen(context, builder, signature, args):
        ptr = _element(context, builder, signature.args[0], args[0],
                       _intp(context, builder, signature, args, 1))
        return builder.load(builder.bitcast(ptr, _VEC.as_pointer()), align=8)

    return LANES(array, offset), codegen


@intrinsic
def store(typingctx, array, offset, x):
    """``array.flat[offset : offset + W] = x``."""

    def codegen(context, builder, signature, args):
        ptr = _element(context, builder, signature.args[0], args[0],
                       _intp(context, builder, signature, args, 1))
        builder.store(args[2], builder.bitcast(ptr, _VEC.as_pointer()), align=8)
        return context.get_dummy_value()

    return types.none(array, offset, x), codegen


@intrinsic
def gather(typingctx, array, offset, stride):
    """The ``W`` numbers ``array.flat[offset + l * stride]``, l = 0 .. W - 1 (one number of
    each of ``W`` samples stored one after another)."""

    def codegen(context, builder, signature, args):
        off = _intp(context, builder, signature, args, 1)
        step = _intp(context, builder, signature, args, 2)
        v = ir.Constant(_VEC, ir.Undefined)
        for i in range(W):
            ptr = _element(context, builder, signature.args[0], args[0], off)
            x = builder.load(ptr, align=8)
            v = builder.insert_element(v, x, ir.Constant(ir.IntType(32), i))
            off = builder.add(off, step)
        return v

    return LANES(array, offset, stride), codegen


@intrinsic
def scatter(typingctx, array, offset, stride, x):
    """``array.flat[offset + l * stride] = x[l]``, l = 0 .. W - 1 (``gather``'s inverse)."""

    def codegen(context, builder, signature, args):
        off = _intp(context, builder, signature, args, 1)
        step = _intp(context, builder, signature, args, 2)
        for i in range(W):
            ptr = _element(context, builder, signature.args[0], args[0], off)
            x = builder.extract_element(args[3], ir.Constant(ir.IntType(32), i))
            builder.store(x, ptr, align=8)
            off = builder.add(off, step)
        return context.get_dummy_value()

    return types.none(array, offset, stride, x), codegen


def _butterfly(b: int) -> tuple[ir.Constant, ir.Constant]:
    """The two shuffles that exchange bit ``b`` of the vector index with bit ``b`` of the
    lane index, for a pair of vectors ``i`` and ``i + b``: three such stages (b = 1, 2, 4)
    transpose eight vectors of eight."""
    lo = [p if not p & b else W + p - b for p in range(W)]
    hi = [p + b if not p & b else W + p for p in range(W)]
    mask = ir.VectorType(ir.IntType(32), W)
    return ir.Constant(mask, lo), ir.Constant(mask, hi)


@intrinsic
def store_transposed(typingctx, array, offset, stride, x0, x1, x2, x3, x4, x5, x6, x7):
    """``array.flat[offset + l * stride + i] = x_i[l]`` for i, l = 0 .. W - 1: the numbers
    ``i`` of ``W`` samples written as one run of ``W`` numbers per sample (``scatter`` of
    ``W`` vectors at once: a transpose in registers, then whole-vector stores)."""

    def codegen(context, builder, signature, args):
        off = _intp(context, builder, signature, args, 1)
        step = _intp(context, builder, signature, args, 2)
        x = list(args[3:])
        b = 1
        while b < W:
            lo, hi = _butterfly(b)
            y = list(x)
            for i in range(W):
                if not i & b:
                    y[i] = builder.shuffle_vector(x[i], x[i + b], lo)
                    y[i + b] = builder.shuffle_vector(x[i], x[i + b], hi)
            x, b = y, 2 * b
        for v in x:
            ptr = _element(context, builder, signature.args[0], args[0], off)
            builder.store(v, builder.bitcast(ptr, _VEC.as_pointer()), align=8)
            off = builder.add(off, step)
        return context.get_dummy_value()

    return types.none(array, offset, stride, *[LANES] * W), codegen


@intrinsic
def stream(typingctx, array, offset, x):
    """``array.flat[offset : offset + W] = x`` past the caches: a non-temporal store, for
    results written once and not read again soon, whose cache line is then neither read
    from memory first nor kept. ``array.flat[offset]`` must lie on a 64-byte boundary
    (``boundary``); ``fence`` orders these stores before whatever the thread does next."""

    def codegen(context, builder, signature, args):
        ptr = _element(context, builder, signature.args[0], args[0],
                       _intp(context, builder, signature, args, 1))
        st = builder.store(args[2], builder.bitcast(ptr, _VEC.as_pointer()), align=64)
        st.set_metadata("nontemporal", builder.module.add_metadata([ir.IntType(32)(1)]))
        return context.get_dummy_value()

    return types.none(array, offset, x), codegen


@intrinsic
def boundary(typingctx, array):
    """How many numbers of ``array`` come before its first 64-byte boundary (0 .. W - 1),
    or -1 when its data are not aligned to 8 bytes (``stream`` cannot be used)."""

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0]).data
        at = builder.ptrtoint(data, ir.IntType(64))
        odd = builder.icmp_unsigned("!=", builder.and_(at, ir.IntType(64)(7)),
                                    ir.IntType(64)(0))
        head = builder.lshr(builder.and_(builder.neg(at), ir.IntType(64)(63)),
                            ir.IntType(64)(3))
        return builder.select(odd, ir.IntType(64)(-1), head)

    return types.int64(array), codegen


@intrinsic
def fence(typingctx):
    """Every store of this thread, ``stream``'s included, before any that follows."""

    def codegen(context, builder, signature, args):
        builder.fence("seq_cst")
        return context.get_dummy_value()

    return types.none(), codegen


@intrinsic
def lane(typingctx, x, i):
    """The number of sample ``i`` in ``x``."""

    def codegen(context, builder, signature, args):
        return builder.extract_element(args[0], _intp(context, builder, signature, args, 1))

    return types.float64(x, i), codegen


@intrinsic
def splat(typingctx, s):
    """``s`` in every lane."""

    def codegen(context, builder, signature, args):
        s = context.cast(builder, args[0], signature.args[0], types.float64)
        v = ir.Constant(_VEC, ir.Undefined)
        for i in range(W):
            v = builder.insert_element(v, s, ir.Constant(ir.IntType(32), i))
        return v

    return LANES(s), codegen


def _binary(name: str, doc: str):
    @intrinsic
    def op(typingctx, x, y):
        def codegen(context, builder, signature, args):
            return getattr(builder, name)(args[0], args[1], flags=_FLAGS)

        return LANES(LANES, LANES), codegen

    op.__doc__ = doc
    return op


add = _binary("fadd", "``x + y`` lane by lane.")
sub = _binary("fsub", "``x - y`` lane by lane.")
mul = _binary("fmul", "``x * y`` lane by lane.")
div = _binary("fdiv", "``x / y`` lane by lane.")


@intrinsic
def fma(typingctx, x, y, z):
    """``x * y + z`` lane by lane, fused."""

    def codegen(context, builder, signature, args):
        a, b, c = args
        return builder.fadd(builder.fmul(a, b, flags=_FLAGS), c, flags=_FLAGS)

    return LANES(LANES, LANES, LANES), codegen


@intrinsic
def fnma(typingctx, x, y, z):
    """``z - x * y`` lane by lane, fused."""

    def codegen(context, builder, signature, args):
        a, b, c = args
        return builder.fsub(c, builder.fmul(a, b, flags=_FLAGS), flags=_FLAGS)

    return LANES(LANES, LANES, LANES), codegen


if numba.config.DISABLE_JIT:  # pure Python: the same operations on tuples

    def load(array, offset):  # noqa: F811
        """The ``W`` numbers ``array.flat[offset : offset + W]``."""
        return tuple(array.reshape(-1)[offset:offset + W])

    def store(array, offset, x):  # noqa: F811
        """``array.flat[offset : offset + W] = x``."""
        array.reshape(-1)[offset:offset + W] = x

    def gather(array, offset, stride):  # noqa: F811
        """The ``W`` numbers ``array.flat[offset + l * stride]``."""
        return tuple(array.reshape(-1)[offset + l * stride] for l in range(W))

    def scatter(array, offset, stride, x):  # noqa: F811
        """``array.flat[offset + l * stride] = x[l]``."""
        for l in range(W):
            array.reshape(-1)[offset + l * stride] = x[l]

    def store_transposed(array, offset, stride, *x):  # noqa: F811
        """``array.flat[offset + l * stride + i] = x_i[l]``."""
        for l in range(W):
            array.reshape(-1)[offset + l * stride:offset + l * stride + W] = [v[l] for v in x]

    def stream(array, offset, x):  # noqa: F811
        """``array.flat[offset : offset + W] = x``."""
        array.reshape(-1)[offset:offset + W] = x

    def boundary(array):  # noqa: F811
        """Numbers before ``array``'s first 64-byte boundary, or -1."""
        at = array.ctypes.data
        return -1 if at % 8 else (-at % 64) // 8

    def fence():  # noqa: F811
        """Nothing to order in pure Python."""

    def lane(x, i):  # noqa: F811
        """The number of sample ``i`` in ``x``."""
        return x[i]

    def splat(s):  # noqa: F811
        """``s`` in every lane."""
        return (float(s),) * W

    def add(x, y):  # noqa: F811
        return tuple(a + b for a, b in zip(x, y, strict=True))

    def sub(x, y):  # noqa: F811
        return tuple(a - b for a, b in zip(x, y, strict=True))

    def mul(x, y):  # noqa: F811
        return tuple(a * b for a, b in zip(x, y, strict=True))

    def div(x, y):  # noqa: F811
        return tuple(a / b for a, b in zip(x, y, strict=True))

    def fma(x, y, z):  # noqa: F811
        return tuple(a * b + c for a, b, c in zip(x, y, z, strict=True))

    def fnma(x, y, z):  # noqa: F811
        return tuple(c - a * b for a, b, c in zip(x, y, z, strict=True))
