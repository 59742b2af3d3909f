"""The on-disk model cache returns exactly the model the URDF builds."""

from __future__ import annotations

import dataclasses

import numpy as np

from cgadyn.multibody import load_urdf, robot_path
from cgadyn.multibody.model import Model


def test_second_load_comes_from_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CGADYN_CACHE_DIR", str(tmp_path))
    path = robot_path("gripper")
    first = load_urdf(path)
    files = list((tmp_path / "models").glob("*.npz"))
    assert len(files) == 1
    second = load_urdf(path)
    for f in dataclasses.fields(Model):
        a, b = getattr(first, f.name), getattr(second, f.name)
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b)
            assert not b.flags.writeable
        else:
            assert a == b, f.name


def test_unwritable_cache_still_loads(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("CGADYN_CACHE_DIR", str(blocker))
    model = load_urdf(robot_path("cart_pole"))
    assert model.nv == 2


def test_corrupt_entry_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("CGADYN_CACHE_DIR", str(tmp_path))
    path = robot_path("cart_pole")
    load_urdf(path)
    (entry,) = (tmp_path / "models").glob("*.npz")
    entry.write_bytes(b"garbage")
    assert load_urdf(path).nv == 2
