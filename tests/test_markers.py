"""Every pytest marker the tests use is registered in ``pyproject.toml``, and
``--strict-markers`` makes an unregistered one an error: a misspelt ``slow`` would otherwise
run a slow test in the quick command (``pytest -m "not slow"``) without a word."""

from __future__ import annotations

import re
from pathlib import Path

TESTS = Path(__file__).resolve().parent
BUILTIN = {"parametrize", "skip", "skipif", "xfail", "usefixtures", "filterwarnings"}


def test_markers_are_strict(pytestconfig):
    assert "--strict-markers" in pytestconfig.getini("addopts")


def test_every_marker_used_is_registered(pytestconfig):
    registered = {line.split(":")[0].strip() for line in pytestconfig.getini("markers")}
    assert {"slow", "cli", "browser", "cluster"} <= registered
    used = set()
    for path in TESTS.glob("*.py"):
        used |= set(re.findall(r"pytest\.mark\.(\w+)", path.read_text()))
    assert used - BUILTIN <= registered, sorted(used - BUILTIN - registered)
