"""Objects from mesh files: OBJ/STL files and VGN/GIGA URDF folders, as :class:`ObjectModel`.

* :func:`load_mesh_object` — one OBJ or STL file, drawn as it is and collided as convex parts
  (:mod:`.convex`: one hull per body, or a cached CoACD decomposition of a non-convex body).
* :func:`load_urdf_object` — one URDF (:mod:`.urdf`) naming a visual and a collision mesh
  (relative paths, metres, z up), or box / cylinder / sphere primitives.
* :func:`load_object_dir` — every URDF of a folder (else every OBJ/STL), sorted by file name.
* :func:`load_object` / :func:`load_objects` — dispatch on what a path is.

Every object is put in the frame of :mod:`.model`: origin at the centre of the bottom face of the
collision parts' bounding box, z up, so it stands on z = 0; the visual mesh gets the same
transform. Unusable input raises :class:`MeshError` naming the file and what is wrong.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path
from typing import Optional, Sequence

import numpy as np
import trimesh

from .. import signals
from .convex import DecompositionParams, convex_parts, limit_parts
from .model import MeshError, ObjectModel
from .urdf import UrdfGeometry, parse_urdf

log = logging.getLogger(__name__)

#: An object whose largest extent (after scaling) is below this is refused [m] (wrong units?).
MIN_EXTENT_M = 0.005
#: An object whose largest extent (after scaling) is above this is refused [m] (millimetres?).
MAX_EXTENT_M = 1.0
#: Mesh files this module reads.
MESH_SUFFIXES = (".obj", ".stl")
#: Largest mesh file read [bytes], checked before reading (a household object's mesh is well
#: under it; larger ones take minutes and gigabytes to load — decimate them first).
MAX_MESH_BYTES = 32_000_000
DEFAULT_RGBA = (0.6, 0.6, 0.6, 1.0)

__all__ = ["MIN_EXTENT_M", "MAX_EXTENT_M", "MESH_SUFFIXES", "MAX_MESH_BYTES", "read_mesh_bodies", "load_mesh_object",
           "load_urdf_object", "load_object_dir", "load_object", "load_objects"]


# ----------------------------------------------------------------------------------- reading


def _missing(path: Path, role: str, urdf: Optional[Path]) -> MeshError:
    if urdf is not None:
        return MeshError(f"{urdf}: names the {role} mesh {path}, which does not exist")
    return MeshError(f"{path}: mesh file not found")


def _load_raw(path: Path, where: str) -> list:
    """The triangle meshes of a file as trimesh reads them (one per OBJ ``o``/``g`` group)."""
    try:
        loaded = trimesh.load(str(path), file_type=path.suffix[1:].lower(), process=False,
                              split_objects=True, split_groups=True, group_material=False,
                              skip_materials=True)
    except Exception as exc:  # trimesh raises many types on malformed files
        raise MeshError(f"{where}: cannot be read as {path.suffix[1:].upper()} "
                        f"({type(exc).__name__}: {exc})") from None
    geoms = list(loaded.geometry.values()) if isinstance(loaded, trimesh.Scene) else [loaded]
    return [g for g in geoms if isinstance(g, trimesh.Trimesh) and len(g.faces)]


def read_mesh_bodies(path: "str | os.PathLike", *, role: str = "mesh",
                     urdf: Optional[Path] = None) -> list:
    """The bodies of an OBJ/STL file: its ``o``/``g`` groups, else its connected pieces.

    :class:`MeshError` names the file (and the URDF naming it) when it is missing, not an OBJ/STL
    file, empty, has no triangles or has non-finite vertices."""
    path = Path(path)
    where = str(path) if urdf is None else f"{path} ({role} mesh of {urdf})"
    if not path.is_file():
        raise _missing(path, role, urdf)
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise MeshError(f"{where}: not a mesh file (expected {' or '.join(MESH_SUFFIXES)})")
    size = path.stat().st_size
    if size == 0:
        raise MeshError(f"{where}: the file is empty")
    if size > MAX_MESH_BYTES:
        raise MeshError(f"{where}: {size / 1e6:.0f} MB is more than a mesh file may be "
                        f"({MAX_MESH_BYTES / 1e6:.0f} MB); simplify it (e.g. decimate it to under "
                        "200k triangles) and try again")
    raw = _load_raw(path, where)
    if not raw:
        raise MeshError(f"{where}: no triangles in the file (an empty mesh, or not really "
                        f"{path.suffix[1:].upper()})")
    for g in raw:
        if not np.isfinite(g.vertices).all():
            bad = int((~np.isfinite(g.vertices).all(axis=1)).sum())
            raise MeshError(f"{where}: {bad} vertices are not finite (NaN or inf)")
    bodies = [trimesh.Trimesh(g.vertices, g.faces, process=True) for g in raw]
    bodies = [b for b in bodies if len(b.faces)]
    if not bodies:
        raise MeshError(f"{where}: all triangles are degenerate (no faces with an area)")
    if len(bodies) == 1:
        bodies = list(bodies[0].split(only_watertight=False, repair=False)) or bodies
    return bodies


def _primitive(geom: UrdfGeometry) -> trimesh.Trimesh:
    if geom.kind == "box":
        return trimesh.creation.box(extents=geom.size)
    if geom.kind == "cylinder":
        return trimesh.creation.cylinder(radius=geom.size[0], height=geom.size[1], sections=32)
    return trimesh.creation.icosphere(subdivisions=3, radius=geom.size[0])


def _geometry_bodies(geom: UrdfGeometry, role: str, urdf: Path) -> tuple[list, np.ndarray]:
    """Bodies in the mesh file's own frame and the transform (origin @ mesh scale) to the link."""
    if geom.kind != "mesh":
        return [_primitive(geom)], geom.transform
    tf = geom.transform @ np.diag(list(geom.scale) + [1.0])
    return read_mesh_bodies(geom.filename, role=role, urdf=urdf), tf


# ----------------------------------------------------------------------------------- building


def _check_scale(scale: float, where: str) -> float:
    try:
        scale = float(scale)
    except (TypeError, ValueError):
        raise MeshError(f"{where}: scale must be a number, got {scale!r}") from None
    if not (np.isfinite(scale) and scale > 0):
        raise MeshError(f"{where}: scale must be a finite number > 0, got {scale}")
    return scale


def _check_rgba(rgba, where: str) -> tuple[float, float, float, float]:
    try:
        values = tuple(float(c) for c in rgba)
    except (TypeError, ValueError):
        values = ()
    if len(values) != 4 or not all(0.0 <= c <= 1.0 for c in values):
        raise MeshError(f"{where}: rgba must be 4 numbers in [0, 1], got {rgba!r}")
    return values


def _check_extent(points: np.ndarray, where: str, scale: float) -> None:
    extent = float(np.max(points.max(axis=0) - points.min(axis=0)))
    if extent < MIN_EXTENT_M or extent > MAX_EXTENT_M:
        hint = ("is the file in millimetres? pass scale=0.001" if extent > MAX_EXTENT_M
                else "is the file in metres? check the scale")
        raise MeshError(f"{where}: absurd size: largest extent {extent:.4g} m after scale {scale:g} "
                        f"(allowed {MIN_EXTENT_M:g} .. {MAX_EXTENT_M:g} m; {hint})")


def _transformed(meshes: Sequence[trimesh.Trimesh], tf: np.ndarray) -> list:
    return [m.copy().apply_transform(tf) for m in meshes]


def _visual_mesh(visuals: list, parts: Sequence[trimesh.Trimesh], warnings: list) -> trimesh.Trimesh:
    """The visual mesh (the parts together when there is none); a closed one faces outwards."""
    if not visuals:
        return trimesh.util.concatenate(list(parts))
    visual = visuals[0] if len(visuals) == 1 else trimesh.util.concatenate(visuals)
    if visual.is_watertight:
        if not visual.is_winding_consistent or visual.volume < 0:
            trimesh.repair.fix_normals(visual)
    else:
        warnings.append("visual mesh is not watertight: the volume (mass) comes from the collision parts")
    return visual


def _normalised(parts: Sequence[trimesh.Trimesh], visual: trimesh.Trimesh) -> tuple[tuple, trimesh.Trimesh]:
    """Translate so the parts' bounding box has its bottom-face centre at the origin."""
    lo = np.min([p.bounds[0] for p in parts], axis=0)
    hi = np.max([p.bounds[1] for p in parts], axis=0)
    shift = np.eye(4)
    shift[:3, 3] = [-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]]
    return tuple(p.apply_transform(shift) for p in parts), visual.apply_transform(shift)


def _assemble(collision: list, visual: list, *, where: str, scale: float,
              params: DecompositionParams, cache_dir) -> tuple[tuple, trimesh.Trimesh, list, list]:
    """collision / visual: (bodies in file frame, transform to the link frame) pairs.

    Returns normalised (parts, visual mesh, notes, warnings); the warnings are also notes."""
    s = np.diag([scale, scale, scale, 1.0])
    vis = [m for bodies, tf in visual for m in _transformed(bodies, s @ tf)]
    col_points = [trimesh.transform_points(b.vertices, s @ tf) for bodies, tf in collision for b in bodies]
    _check_extent(np.vstack(col_points + [m.vertices for m in vis]), where, scale)
    parts, notes, warnings = [], [], []
    for bodies, tf in collision:
        res = convex_parts(bodies, params, cache_dir=cache_dir, source=where)
        parts += _transformed(res.parts, s @ tf)
        notes += res.notes
        warnings += res.warnings
    if len(parts) > params.max_parts:
        parts, extra = limit_parts(parts, params)
        notes += extra
    visual_warnings: list = []
    visual_mesh = _visual_mesh(vis, parts, visual_warnings)
    parts, visual_mesh = _normalised(parts, visual_mesh)
    return parts, visual_mesh, notes + visual_warnings, warnings + visual_warnings


# ----------------------------------------------------------------------------------- loaders


def load_mesh_object(path: "str | os.PathLike", *, name: Optional[str] = None, scale: float = 1.0,
                     rgba=None, cache_dir: Optional["str | os.PathLike"] = None, category: str = "",
                     params: Optional[DecompositionParams] = None) -> ObjectModel:
    """An object from one OBJ/STL file (metres, z up; ``scale`` multiplies it): the file is the
    visual mesh, its bodies give the convex collision parts (see :mod:`.convex`; decompositions
    are cached in ``cache_dir``, default :data:`.convex.DEFAULT_CACHE_DIR`)."""
    path = Path(path)
    scale = _check_scale(scale, str(path))
    colour = DEFAULT_RGBA if rgba is None else _check_rgba(rgba, str(path))
    bodies = read_mesh_bodies(path)
    merged = bodies[0] if len(bodies) == 1 else trimesh.util.concatenate(bodies)
    parts, visual, notes, warnings = _assemble([(bodies, np.eye(4))], [([merged], np.eye(4))],
                                               where=str(path), scale=scale,
                                               params=params or DecompositionParams(), cache_dir=cache_dir)
    return ObjectModel(name or path.stem, parts, colour, category, visual, str(path), notes=tuple(notes),
                       warnings=tuple(warnings))


def load_urdf_object(path: "str | os.PathLike", *, name: Optional[str] = None, scale: float = 1.0,
                     rgba=None, cache_dir: Optional["str | os.PathLike"] = None, category: str = "",
                     params: Optional[DecompositionParams] = None) -> ObjectModel:
    """An object from a single-link URDF (VGN/GIGA layout): its ``<visual>`` is drawn, its
    ``<collision>`` gives the convex parts (the visual does when there is no collision geometry).
    Name: ``name``, else the robot's name, else the file stem; colour: ``rgba``, else the URDF
    material's, else grey."""
    path = Path(path)
    scale = _check_scale(scale, str(path))
    desc = parse_urdf(path)
    colour = _check_rgba(rgba if rgba is not None else (desc.rgba or DEFAULT_RGBA), str(path))
    visual = [_geometry_bodies(g, "visual", path) for g in desc.visuals]
    collision = [_geometry_bodies(g, "collision", path) for g in desc.collisions] or visual
    notes = [] if desc.collisions else ["no collision geometry: the visual mesh collides"]
    parts, mesh, more, warnings = _assemble(collision, visual, where=str(path), scale=scale,
                                            params=params or DecompositionParams(), cache_dir=cache_dir)
    return ObjectModel(name or desc.name, parts, colour, category, mesh, str(path),
                       notes=tuple(notes + more), warnings=tuple(warnings))


def _dir_entries(folder: Path) -> list:
    if not folder.is_dir():
        raise MeshError(f"{folder}: object folder not found")
    files = sorted(p for p in folder.iterdir() if p.is_file())
    urdfs = [p for p in files if p.suffix.lower() == ".urdf"]
    return urdfs or [p for p in files if p.suffix.lower() in MESH_SUFFIXES]


def load_object_dir(folder: "str | os.PathLike", *, scale: float = 1.0,
                    cache_dir: Optional["str | os.PathLike"] = None,
                    params: Optional[DecompositionParams] = None, skip_bad: bool = False) -> list:
    """Every object of a folder, sorted by file name: its URDFs, or its OBJ/STL files if it has
    no URDF. A bad object raises :class:`MeshError`, or is logged and left out with ``skip_bad``."""
    folder = Path(folder)
    entries = _dir_entries(folder)
    if not entries:
        raise MeshError(f"{folder}: no object files (.urdf, {', '.join(MESH_SUFFIXES)}) in the folder")
    objects = []
    mark = signals.received()
    for entry in entries:
        try:
            objects.append(load_object(entry, scale=scale, cache_dir=cache_dir, params=params))
        except MeshError as exc:
            if not skip_bad:
                raise
            log.warning("skipping an object: %s", exc)
        signals.raise_if_received_since(mark, f"loading the objects of {folder}")  # (trimesh may swallow it)
    return objects


def load_object(path: "str | os.PathLike", **kwargs) -> ObjectModel:
    """One object from a path: an OBJ/STL file, a URDF, or a folder holding exactly one URDF.
    Keyword arguments go to :func:`load_mesh_object` / :func:`load_urdf_object`."""
    path = Path(path)
    if path.is_dir():
        urdfs = sorted(path.glob("*.urdf"))
        if len(urdfs) != 1:
            raise MeshError(f"{path}: a folder is one object only if it holds exactly one .urdf "
                            f"(found {len(urdfs)}); use load_object_dir / load_objects for a set")
        path = urdfs[0]
    if path.suffix.lower() == ".urdf":
        return load_urdf_object(path, **kwargs)
    if not path.exists():
        raise MeshError(f"{path}: object file not found")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise MeshError(f"{path}: not a mesh file (expected .urdf, {' or '.join(MESH_SUFFIXES)})")
    return load_mesh_object(path, **kwargs)


def load_objects(path: "str | os.PathLike", **kwargs) -> list:
    """A list of objects: every object of a folder (:func:`load_object_dir`), or the one file."""
    path = Path(path)
    if path.is_dir() and len(list(path.glob("*.urdf"))) != 1:
        return load_object_dir(path, **kwargs)
    kwargs.pop("skip_bad", None)
    return [load_object(path, **kwargs)]
