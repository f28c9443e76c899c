"""Object sets by name, as the command line gives them: ``builtin`` or a path.

``object_set("builtin")`` is the procedural set that ships with the product
(:mod:`.builtin`); a folder is read as VGN/GIGA's layout (one URDF per object) or as mesh
files; a single OBJ/STL/URDF file is a set of one.

A process loads each set once: later calls return copies of the loaded models (a benchmark
worker runs many rounds of the same set; loading a folder of meshes costs seconds, a copy a
few milliseconds). The built-in set builds an object when a scene first takes it, once per
process (:mod:`.builtin_set`). A folder is loaded again when any of its files changed (name, size or
modification time).
"""

from __future__ import annotations

import copy
import logging
import os
from pathlib import Path
from typing import Iterable, Sequence

from .builtin_set import BuiltinSet
from .model import MeshError, ObjectModel

log = logging.getLogger(__name__)

BUILTIN = "builtin"


def object_set(source: str | Path) -> Sequence[ObjectModel]:
    """The objects of ``source`` (see the module doc), each call its own copies (callers may
    modify them); MeshError when there are none. The built-in set is a
    :class:`~.builtin_set.BuiltinSet` (an object is built when first indexed), a loaded one a
    list."""
    if str(source) == BUILTIN:
        return BuiltinSet()
    key = _set_key(source)
    models = _LOADED.get(key)
    if models is None:
        models = _load(source)
        _LOADED.clear()  # one set kept: a process runs one set at a time
        _LOADED[key] = models
    else:
        log_notes(models, str(source))
    return copy.deepcopy(models)


#: The set loaded last, by :func:`_set_key`.
_LOADED: dict[tuple, list[ObjectModel]] = {}


def _set_key(source: str | Path) -> tuple:
    """What identifies a loaded set's content: the path and every file under it with its
    size and modification time (a missing path: its name only, loaded to fail)."""
    path = Path(source).resolve()
    if not path.exists():
        return (str(path), None)
    if path.is_file():
        st = path.stat()
        return (str(path), ((path.name, st.st_size, st.st_mtime_ns),))
    files = []
    for root, dirs, names in os.walk(path):
        dirs.sort()
        for n in sorted(names):
            st = os.stat(os.path.join(root, n))
            files.append((os.path.relpath(os.path.join(root, n), path), st.st_size, st.st_mtime_ns))
    return (str(path), tuple(files))


def _load(source: str | Path) -> list[ObjectModel]:
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
