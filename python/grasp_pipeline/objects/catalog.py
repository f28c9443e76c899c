"""Object sets by name, as the command line gives them: ``builtin`` or a path.

``object_set("builtin")`` is the procedural set that ships with the product
(:mod:`.builtin`); a folder is read as VGN/GIGA's layout (one URDF per object) or as mesh
files; a single OBJ/STL/URDF file is a set of one.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Iterable

from .model import MeshError, ObjectModel

log = logging.getLogger(__name__)

BUILTIN = "builtin"


def object_set(source: str | Path) -> list[ObjectModel]:
    """The objects of ``source`` (see the module doc); MeshError when there are none."""
    if str(source) == BUILTIN:
        from .builtin import builtin_objects

        return builtin_objects()
    path = Path(source)
    if not path.exists():
        raise MeshError(f"object set {path}: no such file or folder (or use 'builtin')")
    from .mesh_object import load_objects

    models = load_objects(path)
    if not models:
        raise MeshError(f"object set {path}: no URDF, OBJ or STL objects found")
    log_notes(models, str(path))
    return models


def log_notes(models: Iterable[ObjectModel], where: str) -> None:
    """Each model's warnings at WARNING, its other notes at DEBUG, and a count at INFO."""
    models = list(models)
    for m in models:
        for w in m.warnings:
            log.warning("object %s (%s): %s", m.name, m.source, w)
        for n in m.notes:
            if n not in m.warnings:
                log.debug("object %s: %s", m.name, n)
    warned = sum(1 for m in models if m.warnings)
    log.info("loaded %d objects from %s%s", len(models), where,
             f" ({warned} with warnings)" if warned else "")


def model_notes(models: Iterable[ObjectModel]) -> dict:
    """For a report: model name -> its source, notes and warnings (each model once)."""
    out: dict = {}
    for m in models:
        out.setdefault(m.name, {"source": m.source, "notes": list(m.notes), "warnings": list(m.warnings)})
    return dict(sorted(out.items()))
