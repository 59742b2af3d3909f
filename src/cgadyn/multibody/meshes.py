"""Where a model's geometry comes from: its source file (URDF or MJCF) and the mesh files a
URDF names. One rule for the viewer (``sim.html``, its ``<visual>``s) and the collision
shapes (``contact.model``, its ``<collision>``s)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["model_source", "package_roots", "resolve_mesh"]


def model_source(model, source=None) -> tuple[str, object, Path | None]:
    """What ``model`` was loaded from: ``("urdf", xml bytes, file or None)`` or
    ``("mjcf", path or text, None)``. ``source`` (a path, URDF or MJCF text, a registered
    name) if given, else the registry's file for the model's name."""
    from . import registry

    if source is None:
        try:
            source = registry.robot_path(model.name)
        except ValueError:
            raise ValueError(f"robot {model.name!r} is not a registered robot: give the file "
                             f"it was loaded from (urdf=path, source=path)") from None
    kind, value, _ = registry.resolve(source if isinstance(source, os.PathLike | str)
                                      else str(source))
    if kind == "mjcf":
        return "mjcf", value, None
    if kind == "text":
        return "urdf", value.encode("utf-8"), None
    if kind == "name":
        value = registry.robot_path(value)
    return "urdf", Path(value).read_bytes(), Path(value)


def package_roots(urdf_path: Path | None) -> list[Path]:
    """Directories under which ``package://PKG/...`` may live: example-robot-data's share
    directory and every ancestor of the URDF's directory."""
    from . import registry

    roots = []
    erd = registry.example_robot_data_dir()
    if erd is not None:
        roots += [erd.parent.parent, erd.parent, erd]  # share/, share/example-robot-data/
    if urdf_path is not None:
        roots += list(urdf_path.resolve().parents)
    return roots


def resolve_mesh(filename: str, urdf_path: Path | None) -> Path:
    """The file a URDF mesh ``filename`` names: ``package://PKG/REST`` is looked up as
    ``ROOT/PKG/REST`` (or ``ROOT/REST`` for the root of package PKG) under
    :func:`package_roots`; ``file://`` and plain paths are taken relative to the URDF."""
    tried = []
    if filename.startswith("package://"):
        pkg, _, rest = filename[len("package://"):].partition("/")
        for root in package_roots(urdf_path):
            for cand in (root / pkg / rest, root / rest if root.name == pkg else None):
                if cand is not None:
                    tried.append(cand)
                    if cand.is_file():
                        return cand
    else:
        name = filename[len("file://"):] if filename.startswith("file://") else filename
        cand = Path(name)
        if not cand.is_absolute() and urdf_path is not None:
            cand = urdf_path.parent / cand
        tried.append(cand)
        if cand.is_file():
            return cand
    raise FileNotFoundError(f"mesh {filename!r} of the URDF not found (looked in "
                            f"{', '.join(str(p) for p in tried[:4]) or 'no place'}"
                            f"{' ...' if len(tried) > 4 else ''})")
