"""An on-disk cache of loaded models, so a second process need not parse the URDF again.

Parsing a URDF imports yourdfpy (and trimesh), which is slow next to reading back a model,
a few kilobytes of arrays. ``cached(xml, key, build)`` returns the model stored under a
hash of the URDF text, the loader's options (``key``) and the fingerprint of the package's
code (its version and every source file, generated kernels included: ``cgadyn._sources``),
or builds and stores it. Files are ``.npz`` archives read with ``allow_pickle=False``; an
entry that cannot be read whole (emptied, truncated, corrupted, of another format) is
rebuilt and rewritten, atomically, so the cache heals itself. The directory is
``$CGADYN_CACHE_DIR``, else ``$XDG_CACHE_HOME/cgadyn``, else ``~/.cache/cgadyn``; when it
cannot be written the model is simply built every time.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from cgadyn._sources import fingerprint
from cgadyn.multibody.model import Model

FORMAT = 1


def cache_dir() -> Path:
    env = os.environ.get("CGADYN_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "cgadyn"


def _key(xml: bytes, name) -> str:
    h = hashlib.sha256(f"{FORMAT} {fingerprint()}".encode())
    h.update(repr(name).encode())
    h.update(xml)
    return h.hexdigest()[:32]


def _save(model: Model, path: Path) -> None:
    arrays, meta = {}, {}
    for f in dataclasses.fields(Model):
        value = getattr(model, f.name)
        if isinstance(value, np.ndarray):
            arrays[f.name] = value
        else:
            meta[f.name] = value
    arrays["__meta__"] = np.array(json.dumps(meta))
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".npz")
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _read(path: Path) -> Model:
    with np.load(path, allow_pickle=False) as data:
        fields = {k: data[k] for k in data.files if k != "__meta__"}
        meta = json.loads(str(data["__meta__"]))
    meta["mimic"] = tuple(tuple(m) if m is not None else None for m in meta["mimic"])
    return Model(**fields, **meta)


def cached(xml: bytes, name: str | None, build: Callable[[], Model]) -> Model:
    """The model of ``xml`` from the cache, or ``build()`` stored for next time."""
    path = cache_dir() / "models" / f"{_key(xml, name)}.npz"
    try:
        if path.is_file():
            return _read(path)
    except Exception:  # noqa: BLE001 - any unreadable entry (EOFError, BadZipFile, ...)
        pass  # is rebuilt and rewritten below
    model = build()
    try:
        _save(model, path)
    except OSError:
        pass  # read-only or full disk: caching is only an optimisation
    return model
