"""What a wheel ships: the project's own URDFs (real files in the top-level ``robots/``) and
the C extension."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]


def test_robots_are_real_files_shipped_in_the_wheel(tmp_path):
    robots = sorted(p.name for p in (ROOT / "robots").iterdir() if p.suffix in (".urdf", ".xml"))
    assert robots == ["cart_pole.urdf", "gripper.urdf", "prismatic_tree.urdf", "skew_arm.urdf",
                      "slide_arm.xml"]
    assert not any(p.is_symlink() for p in (ROOT / "robots").iterdir())
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                    "-q", "-w", str(tmp_path), str(ROOT)], check=True, timeout=600,
                   capture_output=True)
    (wheel,) = tmp_path.glob("cgadyn-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    top = [n for n in names if n.startswith("cgadyn/robots/") and n.count("/") == 2]
    assert sorted(n.split("/")[-1] for n in top) == robots
    suites = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "robots" / "mujoco").rglob("*")
                    if p.is_file())
    assert len(suites) > 22  # Gymnasium's and dm_control's models, included files, licence
    assert sorted(n.removeprefix("cgadyn/") for n in names
                  if n.startswith("cgadyn/robots/mujoco/")) == suites
    assert any(n.startswith("cgadyn/_native") and n.endswith(".so") for n in names)
