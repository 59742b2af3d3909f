"""Build steps that pyproject.toml cannot declare: the C extension ``cgadyn._native``.

Metadata lives in pyproject.toml. ``cgadyn._native`` (src/cgadyn/_native.c) calls the compiled
algorithms with the data of numpy arrays, the fast path of a one-sample call; it is optional:
where it cannot be built, cgadyn calls the same compiled code through numba's dispatcher.
"""

import numpy
from setuptools import Extension, setup

setup(ext_modules=[Extension(
    "cgadyn._native", ["src/cgadyn/_native.c"], include_dirs=[numpy.get_include()],
    extra_compile_args=["-O2"], optional=True)])
