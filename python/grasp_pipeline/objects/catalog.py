"""Object sets by name, as the command line gives them: ``builtin`` or a path.

``object_set("builtin")`` is the procedural set that ships with the product
(:mod:`.builtin`); a folder is read as VGN/GIGA's layout (one URDF per object) or as mesh
files; a single OBJ/STL/URDF file is a set of one.
"""

from __future__ import annotations

from pathlib import Path

from .model import MeshError, ObjectModel

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
    return models
