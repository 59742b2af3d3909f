"""Build steps that pyproject.toml cannot declare (metadata lives there).

- The C extension ``cgadyn._native`` (src/cgadyn/_native.c) calls the compiled algorithms
  with the data of numpy arrays, the fast path of a one-sample call. It is optional: where it
  cannot be built, cgadyn calls the same compiled code through numba's dispatcher.
- The project's own URDFs (and MJCF files, ``*.xml``) live in the top-level ``robots/``; a
  wheel ships them as ``cgadyn/robots/`` (an editable install reads them from the checkout).
"""

from pathlib import Path

import numpy
from setuptools import Extension, setup
from setuptools.command.build_py import build_py


class BuildWithRobots(build_py):
    """``build_py`` that also copies ``robots/*.urdf``, ``robots/*.xml`` (MJCF) and the
    MuJoCo suites under ``robots/mujoco/`` (their files, included ones and licence) into the
    built package."""

    def run(self):
        super().run()
        target = Path(self.build_lib) / "cgadyn" / "robots"
        target.mkdir(parents=True, exist_ok=True)
        robots = Path(__file__).parent.joinpath("robots")
        for robot in sorted([*robots.glob("*.urdf"), *robots.glob("*.xml")]):
            self.copy_file(str(robot), str(target / robot.name))
        for path in sorted((robots / "mujoco").rglob("*")):
            if path.is_file():
                out = target / path.relative_to(robots)
                out.parent.mkdir(parents=True, exist_ok=True)
                self.copy_file(str(path), str(out))


setup(
    cmdclass={"build_py": BuildWithRobots},
    ext_modules=[Extension("cgadyn._native", ["src/cgadyn/_native.c"],
                           include_dirs=[numpy.get_include()], extra_compile_args=["-O2"],
                           optional=True)],
)
