"""Kernels inlined by LLVM rather than by numba: the same machine code, compiled once.

A kernel (a motor product, an inertia transform) is called from dozens of places in the
recursions. Inlined by numba (``inline="always"``), its typed IR is copied into each caller
and typed and lowered there again, which makes a first compilation slow (the cost grows with
the number of call sites times the kernel's size). Compiled instead as a function of its
own, a kernel is typed, lowered and cached once; a caller links its LLVM module in (numba
does this for every compiled callee) and LLVM inlines it there, so the recursion is again
one function without calls.

LLVM inlines a callee only where its cost model says so unless the callee carries the
``alwaysinline`` attribute. numba has no option for that, so this module marks the kernels'
functions in the module numba hands to callers for linking
(``CPUCodeLibrary._get_module_for_linking``, a numba internal): a kernel is recognised by the
prefix of its mangled name (``_ZN`` and the length-prefixed parts of its module and name,
Itanium's scheme, which numba uses). Where that internal is not there (another numba),
``available()`` is False and ``_jit`` keeps numba's own inlining.

``_jit`` uses this only where asked (``CGADYN_INLINE=llvm``): the first compilation is
several times shorter and the results agree to rounding (the fused multiply-adds land
elsewhere), but measured on the benchmark robots the rnea derivatives run 5-12 % slower
(their eight-sample batches more), above the 5 % this project allows, so numba's inlining
stays the default until that is understood.
"""

from __future__ import annotations

from collections.abc import Callable

from numba.core import codegen

_PREFIXES: set[str] = set()
"""The mangled-name prefixes of the kernels to inline."""

_LIBRARY = getattr(codegen, "CPUCodeLibrary", None)
_LINKING = getattr(_LIBRARY, "_get_module_for_linking", None)


def available() -> bool:
    """Whether kernels can be inlined by LLVM with this numba."""
    return _LINKING is not None


def prefix(fn: Callable) -> str:
    """The start of the mangled name numba gives ``fn``'s compiled function."""
    parts = f"{fn.__module__}.{fn.__qualname__}".split(".")
    return "_ZN" + "".join(f"{len(p)}{p}" for p in parts)


def always_inline(fn: Callable) -> None:
    """Mark ``fn``'s compiled functions ``alwaysinline`` wherever they are linked."""
    _PREFIXES.add(prefix(fn))


def _module_for_linking(self):
    module = _LINKING(self)
    if not getattr(self, "_cgadyn_inlining", False):  # once per library: numba keeps it
        for function in module.functions:
            if not function.is_declaration and function.name.startswith(tuple(_PREFIXES)):
                function.add_function_attribute("alwaysinline")
        self._cgadyn_inlining = True
    return module


def install() -> None:
    """Have numba's code libraries mark the kernels (``always_inline``) when linking them;
    only where ``_jit`` inlines by LLVM, so that numba's own linking is otherwise untouched."""
    if available() and _LIBRARY._get_module_for_linking is not _module_for_linking:
        _LIBRARY._get_module_for_linking = _module_for_linking
