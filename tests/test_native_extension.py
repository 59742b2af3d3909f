"""Without the C extension ``cgadyn._native`` single calls take numba's dispatcher, several
times slower: that is said once, with a ``NativeExtensionMissing`` warning when the compiled
algorithms load, and by ``cgadyn info``. Each case runs in a fresh interpreter, the
extension's import made to fail as where it was never built."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

import cgadyn

pytestmark = pytest.mark.slow


SCRIPT = """
import json, sys, warnings
if {block}:
    sys.modules["cgadyn._native"] = None  # its import fails, as if never built
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    import numpy as np
    import cgadyn
    m = cgadyn.load("double_pendulum")
    for _ in range(2):
        cgadyn.rnea(m, np.zeros(2), np.zeros(2), np.zeros(2))
        cgadyn.crba(m, np.zeros(2))
from cgadyn.commands.info import native_extension
print(json.dumps({{"warnings": [[w.category.__name__, str(w.message)] for w in caught
                               if issubclass(w.category, cgadyn.NativeExtensionMissing)],
                  "native": native_extension()}}))
"""


def _run(block: bool, **env: str) -> dict:
    out = subprocess.run([sys.executable, "-c", SCRIPT.format(block=block)],
                         env=dict(os.environ, **env), capture_output=True, text=True,
                         timeout=900)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_a_missing_extension_warns_once_saying_how_to_get_it():
    result = _run(block=True)
    (warning,) = result["warnings"]
    category, message = warning
    assert category == "NativeExtensionMissing"
    assert "cgadyn._native is missing" in message and "C compiler" in message
    assert "reinstall cgadyn" in message and "slower" in message
    native = result["native"]
    assert native["status"].startswith("missing") and not native["fast_single_calls"]
    assert "C compiler" in native["note"]


def test_no_warning_where_it_is_built_or_turned_off():
    pytest.importorskip("cgadyn._native")  # built in this environment
    result = _run(block=False)
    assert result["warnings"] == [] and result["native"]["status"] == "loaded"
    result = _run(block=False, CGADYN_NATIVE="0")
    assert result["warnings"] == []
    assert result["native"]["status"] == "disabled (CGADYN_NATIVE=0)"


def test_the_category_is_importable_before_the_algorithms():
    assert issubclass(cgadyn.NativeExtensionMissing, RuntimeWarning)
    assert "NativeExtensionMissing" in cgadyn.__all__
