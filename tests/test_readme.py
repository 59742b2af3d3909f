"""The README's Python examples run as written (the README stays true)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_examples_run():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert len(blocks) >= 2
    namespace: dict = {}
    exec("\n".join(blocks), namespace)  # noqa: S102 - our own README
    solo, q, v = namespace["solo"], namespace["q"], namespace["v"]
    assert (solo.nq, solo.nv) == (19, 18)
    np.testing.assert_allclose(
        namespace["cgadyn"].difference(solo, q, namespace["q_next"]), 0.01 * v, atol=1e-14)
    # the quadruped held by its feet: still, and its weight on its feet
    weight = 9.81 * namespace["cgadyn"].total_mass(solo)
    assert abs(namespace["forces"][2::3].sum() - weight) <= 1e-12 * weight
    assert np.abs(namespace["qdd"]).max() <= 1e-10
    # solo12 stood on the ground by contact_step: only its feet touch, carrying about its
    # weight (the PD posture still sways a little)
    step = namespace["step"]
    assert len(step.contacts) and np.all(step.forces[:, 2] >= 0.0)
    assert abs(step.forces[:, 2].sum() - weight) <= 0.05 * weight
