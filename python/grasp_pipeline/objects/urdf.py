"""The part of URDF an object needs: its visual and collision geometry (VGN/GIGA layout).

A VGN/GIGA object is one URDF with one link naming a visual and a collision OBJ by relative path
(metres, z up)::

    <robot name="mug"><link name="base_link">
      <visual><geometry><mesh filename="mug_visual.obj"/></geometry></visual>
      <collision><geometry><mesh filename="mug_collision.obj"/></geometry></collision>
    </link></robot>

:func:`parse_urdf` reads ``<visual>``/``<collision>`` elements: ``<mesh filename= scale=>``, the
primitives ``<box size>``, ``<cylinder radius length>``, ``<sphere radius>``, their ``<origin xyz
rpy>`` and a visual ``<material><color rgba>``. Inertial, contact and mass are ignored (mass
comes from volume and density). Only single-link URDFs are objects. Nothing is loaded here.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from .model import MeshError


@dataclass(frozen=True)
class UrdfGeometry:
    """One ``<visual>`` or ``<collision>``: ``kind`` is ``mesh``, ``box``, ``cylinder`` or ``sphere``;
    ``transform`` the 4x4 ``<origin>`` in the link frame; ``scale`` the mesh's (sx, sy, sz)."""

    kind: str
    transform: np.ndarray
    filename: Optional[Path] = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    size: tuple[float, ...] = ()


@dataclass(frozen=True)
class UrdfObject:
    path: Path
    name: str
    visuals: tuple[UrdfGeometry, ...]
    collisions: tuple[UrdfGeometry, ...]
    rgba: Optional[tuple[float, float, float, float]] = None


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll-pitch-yaw: R = Rz(yaw) @ Ry(pitch) @ Rx(roll)."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _floats(path: Path, element: ET.Element, attr: str, n: int, default=None) -> tuple[float, ...]:
    text = element.get(attr)
    if text is None:
        if default is None:
            raise MeshError(f"{path}: <{element.tag}> has no {attr!r} attribute")
        return tuple(default)
    try:
        values = tuple(float(x) for x in text.split())
    except ValueError:
        values = ()
    if len(values) != n or not all(np.isfinite(values)):
        raise MeshError(f"{path}: <{element.tag} {attr}={text!r}> must be {n} finite numbers")
    return values


def _origin(path: Path, parent: ET.Element) -> np.ndarray:
    tf = np.eye(4)
    origin = parent.find("origin")
    if origin is not None:
        tf[:3, :3] = rpy_matrix(*_floats(path, origin, "rpy", 3, (0.0, 0.0, 0.0)))
        tf[:3, 3] = _floats(path, origin, "xyz", 3, (0.0, 0.0, 0.0))
    return tf


def resolve_mesh_path(urdf_path: Path, filename: str) -> Path:
    """A mesh ``filename`` as a path: relative to the URDF's folder; ``file://`` stripped;
    ``package://<pkg>/rest`` looked up as ``rest`` next to the URDF, then one folder up."""
    if filename.startswith("file://"):
        filename = filename[len("file://"):]
    base = urdf_path.parent
    if filename.startswith("package://"):
        rest = filename[len("package://"):].partition("/")[2]
        for candidate in (base / rest, base.parent / rest):
            if candidate.exists():
                return candidate
        return base / rest
    p = Path(filename)
    return p if p.is_absolute() else base / p


def _geometry(path: Path, element: ET.Element) -> Optional[UrdfGeometry]:
    geom = element.find("geometry")
    shape = None if geom is None else next(iter(geom), None)
    if shape is None:
        return None
    tf = _origin(path, element)
    if shape.tag == "mesh":
        name = shape.get("filename")
        if not name:
            raise MeshError(f"{path}: a <mesh> in <{element.tag}> has no filename")
        scale = _floats(path, shape, "scale", 3, (1.0, 1.0, 1.0))
        if min(scale) <= 0:
            raise MeshError(f"{path}: <mesh scale={shape.get('scale')!r}> must be positive")
        return UrdfGeometry("mesh", tf, resolve_mesh_path(path, name), scale)
    sizes = {"box": ("size", 3), "cylinder": None, "sphere": ("radius", 1)}
    if shape.tag not in sizes:
        raise MeshError(f"{path}: <{element.tag}> geometry <{shape.tag}> is not supported "
                        "(mesh, box, cylinder or sphere)")
    if shape.tag == "cylinder":
        size = _floats(path, shape, "radius", 1) + _floats(path, shape, "length", 1)
    else:
        size = _floats(path, shape, *sizes[shape.tag])
    if min(size) <= 0:
        raise MeshError(f"{path}: <{shape.tag}> dimensions must be positive, got {size}")
    return UrdfGeometry(shape.tag, tf, size=size)


def _rgba(path: Path, link: ET.Element) -> Optional[tuple[float, float, float, float]]:
    color = link.find("visual/material/color")
    if color is None or color.get("rgba") is None:
        return None
    rgba = _floats(path, color, "rgba", 4)
    return tuple(float(np.clip(c, 0.0, 1.0)) for c in rgba)


#: Largest URDF read [bytes] (an object's URDF is about 1 kB), checked before reading.
MAX_URDF_BYTES = 1_000_000


def _read_root(path: Path) -> ET.Element:
    if not path.is_file():
        raise MeshError(f"{path}: URDF file not found")
    size = path.stat().st_size
    if size > MAX_URDF_BYTES:
        raise MeshError(f"{path}: {size / 1e6:.0f} MB is more than an object's URDF may be "
                        f"({MAX_URDF_BYTES / 1e6:.0f} MB); is it the right file?")
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise MeshError(f"{path}: unreadable URDF (not well-formed XML: {exc})") from None
    except OSError as exc:
        raise MeshError(f"{path}: cannot read the URDF ({exc})") from None
    if root.tag != "robot":
        raise MeshError(f"{path}: not a URDF (the root element is <{root.tag}>, expected <robot>)")
    return root


def parse_urdf(path: "str | Path") -> UrdfObject:
    """The object described by a single-link URDF; :class:`MeshError` names the file if it is
    missing, not XML, not a URDF, has several links or no geometry at all."""
    path = Path(path)
    root = _read_root(path)
    links = root.findall("link")
    if len(links) != 1:
        raise MeshError(f"{path}: an object URDF must have exactly one <link>, found {len(links)} "
                        "(articulated objects are not supported)")
    link = links[0]
    visuals = tuple(g for g in (_geometry(path, e) for e in link.findall("visual")) if g is not None)
    collisions = tuple(g for g in (_geometry(path, e) for e in link.findall("collision")) if g is not None)
    if not visuals and not collisions:
        raise MeshError(f"{path}: the URDF has no mesh (no <visual> or <collision> geometry)")
    name = root.get("name") or path.stem
    return UrdfObject(path, name, visuals, collisions, _rgba(path, link))
