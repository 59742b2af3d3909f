"""The on-disk model cache returns exactly the model the URDF builds."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

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


def _damage(entry, how: str) -> None:
    data = entry.read_bytes()
    if how == "emptied":
        entry.write_bytes(b"")
    elif how == "halved":
        entry.write_bytes(data[: len(data) // 2])
    else:  # bytes flipped in the middle
        middle = len(data) // 2
        entry.write_bytes(data[:middle] + bytes(b ^ 0xFF for b in data[middle:middle + 64])
                          + data[middle + 64:])


@pytest.mark.parametrize("how", ["emptied", "halved", "flipped"])
def test_damaged_entries_heal(tmp_path, monkeypatch, how):
    """An entry emptied, truncated or corrupted is rebuilt and rewritten, for good."""
    monkeypatch.setenv("CGADYN_CACHE_DIR", str(tmp_path))
    path = robot_path("gripper")
    fresh = load_urdf(path)
    (entry,) = (tmp_path / "models").glob("*.npz")
    _damage(entry, how)
    for _ in range(2):  # the first load rebuilds; the second reads the rewritten entry
        again = load_urdf(path)
        np.testing.assert_array_equal(again.inertias, fresh.inertias)
        assert again.joint_names == fresh.joint_names
    with np.load(entry, allow_pickle=False) as data:  # readable again
        assert "inertias" in data.files


def test_the_key_covers_the_package_sources():
    """A model built by other code (generated kernels included) is never read back."""
    from cgadyn import _sources
    from cgadyn.multibody import cache

    before = cache._key(b"<robot/>", None)
    real = _sources.fingerprint
    try:
        _sources.fingerprint.cache_clear()
        cache.fingerprint = lambda: "other code"
        assert cache._key(b"<robot/>", None) != before
    finally:
        cache.fingerprint = real
    sources = {p.name for p in _sources.PACKAGE.rglob("*.py")}
    assert {"_generated.py", "rnea.py", "dispatch.py", "urdf.py"} <= sources
