"""Array views on raw memory for compiled code: stack buffers and reference-free views.

Inside a one-sample call, whose arithmetic is short, a heap allocation, an array
reshape and the reference counting of views each cost a measurable share. These helpers
give compiled code bare C-contiguous views instead (``numba.carray`` on a pointer): of a
buffer on the caller's stack, or of an argument array. Such a view owns nothing; it is
valid while the memory it points into is. Under ``NUMBA_DISABLE_JIT=1`` every helper falls
back to ordinary numpy arrays.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic, overload


def _bare_array(context, builder, array, data, dims):
    """A C-contiguous ``array`` (a numba array type) of the extents ``dims`` (LLVM intp
    values) on ``data``, owning nothing (no meminfo): the one way these helpers build an
    array."""
    intp = types.intp
    itemsize = context.get_constant(intp, context.get_abi_sizeof(
        context.get_data_type(array.dtype)))
    strides, step = [], itemsize
    for d in reversed(dims):
        strides.insert(0, step)
        step = builder.mul(step, d)
    out = context.make_array(array)(context, builder)
    context.populate_array(out, data=data, shape=cgutils.pack_array(builder, dims),
                           strides=cgutils.pack_array(builder, strides),
                           itemsize=itemsize, meminfo=None)
    return out._getvalue()


@intrinsic
def _stack_array(typingctx, size):
    array = types.Array(types.float64, 1, "C")
    sig = array(types.intp)

    def codegen(context, builder, signature, args):
        data = builder.alloca(context.get_value_type(types.float64), size=args[0])
        return _bare_array(context, builder, array, data, [args[0]])

    return sig, codegen


@intrinsic
def _advance(typingctx, pointer, offset):
    sig = pointer(pointer, types.intp)

    def codegen(context, builder, signature, args):
        return builder.gep(args[0], [args[1]])

    return sig, codegen


@intrinsic
def _bare_view(typingctx, pointer, shape):
    """``numba.carray(pointer, shape)`` as one intrinsic: a C-contiguous array of
    ``shape`` on ``pointer``'s data, no owner. numba's ``carray`` is an overload compiled
    as a function returning an array, which a caller compiled without reference counts
    (``_jit.core``) may not call."""
    if not (isinstance(pointer, types.CPointer) and isinstance(shape, types.BaseTuple)
            and all(isinstance(s, types.Integer) for s in shape)):
        return None
    array = types.Array(pointer.dtype, len(shape), "C")
    sig = array(pointer, shape)

    def codegen(context, builder, signature, args):
        dims = [context.cast(builder, d, t, types.intp)
                for d, t in zip(cgutils.unpack_tuple(builder, args[1]), shape, strict=True)]
        return _bare_array(context, builder, array, args[0], dims)

    return sig, codegen


@intrinsic
def _data_pointer(typingctx, array):
    sig = types.CPointer(array.dtype)(array)

    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data

    return sig, codegen


@intrinsic
def _as_int64(typingctx, pointer):
    sig = types.CPointer(types.int64)(pointer)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(signature.return_type))

    return sig, codegen


if numba.config.DISABLE_JIT:

    def stack_buffer(size: int) -> np.ndarray:
        """Pure Python: a heap array stands in for the stack buffer."""
        return np.empty(size)

    def data_pointer(array: np.ndarray) -> np.ndarray:
        """Pure Python: the array's data as a flat view."""
        return array.reshape(-1)

    def as_int64(array: np.ndarray) -> np.ndarray:
        """Pure Python: the same bytes viewed as int64."""
        return array.view(np.int64)

    def bare_view(pointer: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
        """Pure Python: the first elements of the flat array, in ``shape``."""
        return pointer[:int(np.prod(shape))].reshape(shape)

else:
    data_pointer = _data_pointer
    """The data of a C-contiguous array as a pointer for ``carve``; views made from it
    are valid only while the array is alive (use it on arguments of the function)."""

    as_int64 = _as_int64
    """The same pointer read as 8-byte integers: for int64 data stored in a float64 buffer."""

    bare_view = _bare_view
    """A C-contiguous array of ``shape`` on a pointer's data (``numba.carray``), owning
    nothing: ``bare_view(data_pointer(work), (0, 6))`` is an empty array without an allocation."""

    stack_buffer = _stack_array
    """``size`` uninitialised floats on the stack of the compiled function that calls it,
    as a bare array (no owner, no reference counts) of the same type as ``np.empty(size)``,
    so that a core called with either is compiled once. Valid until that function
    returns, so call it only in the body of an entry point (never in a loop, never in a
    helper that returns it)."""


def carve(buf, offset, shape):
    """A C-contiguous view of ``shape`` into ``buf`` at ``offset``, and the next offset.

    ``buf`` is a pointer from ``data_pointer`` (compiled: a bare view, valid while that
    array lives) or, in pure Python, the array itself. One buffer per call holds every
    array of an algorithm's workspace.
    """
    size = 1
    for s in shape:
        size *= s
    return buf[offset:offset + size].reshape(shape), offset + size


@overload(carve)
def _carve(buf, offset, shape):
    def bare(buf, offset, shape):
        size = 1
        for s in shape:
            size *= s
        return _bare_view(_advance(buf, offset), shape), offset + size

    return bare
