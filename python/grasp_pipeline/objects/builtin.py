"""The built-in object set: procedurally generated household-sized objects, no download.

VGN's "blocks" (cubes, cuboids, cylinders, triangular prisms, circular segments), bottles
and cans, mugs with handles, small bowls, L-/T-/cross-shaped blocks, rounded boxes and
seeded irregular convex blobs. Every object is a union of convex parts (see :mod:`.shapes`)
standing on z = 0 with its bounding box's bottom-face centre at the origin.

Every object fits the 8 cm parallel gripper across at least one horizontal direction:
:func:`footprint_min_width_m` (the narrowest width of the object's top-view outline over
all yaw angles) is between 1 cm and 7 cm. A mug's narrowest width is its body (the handle
sticks out across the other direction); bowls are therefore small (<= 7 cm across).

>>> builtin_object("red_mug").category
'mug'
"""

from __future__ import annotations

import zlib
from functools import partial

import numpy as np
import trimesh
from scipy.spatial import ConvexHull

from . import shapes
from .model import MeshError, ObjectModel

#: Colour names (for language prompts) and their RGBA.
COLORS: dict[str, tuple[float, float, float, float]] = {
    "red": (0.85, 0.15, 0.13, 1.0), "green": (0.20, 0.65, 0.25, 1.0),
    "blue": (0.15, 0.35, 0.85, 1.0), "yellow": (0.95, 0.85, 0.20, 1.0),
    "orange": (0.95, 0.55, 0.10, 1.0), "purple": (0.55, 0.25, 0.70, 1.0),
    "pink": (0.95, 0.55, 0.70, 1.0), "cyan": (0.20, 0.75, 0.80, 1.0),
    "white": (0.92, 0.92, 0.90, 1.0), "grey": (0.55, 0.55, 0.55, 1.0),
    "brown": (0.55, 0.35, 0.20, 1.0), "silver": (0.76, 0.77, 0.80, 1.0),
}

_S = shapes
#: name -> (category, colour name, generator of the parts); the order is BUILTIN_NAMES.
#: Blob generators receive their seed from the name (see _build).
_RECIPES: dict = {
    # VGN-style blocks
    "red_cube": ("cube", "red", partial(_S.box_parts, 0.045, 0.045, 0.045)),
    "small_blue_cube": ("cube", "blue", partial(_S.box_parts, 0.03, 0.03, 0.03)),
    "green_cube": ("cube", "green", partial(_S.box_parts, 0.055, 0.055, 0.055)),
    "yellow_cuboid": ("cuboid", "yellow", partial(_S.box_parts, 0.07, 0.04, 0.03)),
    "orange_bar": ("cuboid", "orange", partial(_S.box_parts, 0.10, 0.03, 0.03)),
    "purple_tall_cuboid": ("cuboid", "purple", partial(_S.box_parts, 0.035, 0.035, 0.11)),
    "red_cylinder": ("cylinder", "red", partial(_S.cylinder_parts, 0.025, 0.06)),
    "blue_flat_cylinder": ("cylinder", "blue", partial(_S.cylinder_parts, 0.032, 0.025)),
    "green_tall_cylinder": ("cylinder", "green", partial(_S.cylinder_parts, 0.015, 0.11)),
    "yellow_prism": ("triangular_prism", "yellow",
                     partial(_S.triangular_prism_parts, 0.05, 0.09, lying=True)),
    "cyan_standing_prism": ("triangular_prism", "cyan",
                            partial(_S.triangular_prism_parts, 0.055, 0.06, lying=False)),
    "orange_segment": ("circular_segment", "orange",
                       partial(_S.circular_segment_parts, 0.045, 0.03, 0.03)),
    "purple_half_disk": ("circular_segment", "purple",
                         partial(_S.circular_segment_parts, 0.035, 0.035, 0.04)),
    # bottles and cans
    "tall_bottle": ("bottle", "cyan", partial(_S.bottle_parts, 0.032, 0.155, 0.013, 0.03, 0.03)),
    "small_bottle": ("bottle", "brown", partial(_S.bottle_parts, 0.022, 0.095, 0.010, 0.02, 0.018)),
    "green_bottle": ("bottle", "green", partial(_S.bottle_parts, 0.027, 0.14, 0.011, 0.04, 0.03)),
    "soda_can": ("can", "red", partial(_S.can_parts, 0.033, 0.122)),
    "short_can": ("can", "silver", partial(_S.can_parts, 0.034, 0.06)),
    "slim_can": ("can", "yellow", partial(_S.can_parts, 0.027, 0.135)),
    # mugs and bowls
    "red_mug": ("mug", "red", partial(_S.mug_parts, 0.034, 0.09)),
    "blue_mug": ("mug", "blue", partial(_S.mug_parts, 0.031, 0.10)),
    "white_cup": ("mug", "white", partial(_S.mug_parts, 0.028, 0.062, wall_m=0.004,
                                          handle_reach_m=0.016, handle_thickness_m=0.007)),
    "green_bowl": ("bowl", "green", partial(
        _S.bowl_parts, [(0.022, 0.0), (0.031, 0.012), (0.035, 0.032)])),
    "orange_bowl": ("bowl", "orange", partial(
        _S.bowl_parts, [(0.02, 0.0), (0.029, 0.01), (0.034, 0.024)])),
    # flat composite blocks
    "red_l_block": ("l_block", "red", partial(_S.l_block_parts, 0.07, 0.05, 0.02, 0.025)),
    "blue_l_block": ("l_block", "blue", partial(_S.l_block_parts, 0.06, 0.06, 0.025, 0.02)),
    "green_t_block": ("t_block", "green", partial(_S.t_block_parts, 0.07, 0.065, 0.02, 0.025)),
    "yellow_t_block": ("t_block", "yellow", partial(_S.t_block_parts, 0.06, 0.05, 0.018, 0.03)),
    "purple_cross_block": ("cross_block", "purple", partial(_S.cross_block_parts, 0.065, 0.02, 0.025)),
    # rounded boxes
    "pink_soap_bar": ("rounded_box", "pink", partial(_S.rounded_box_parts, 0.085, 0.055, 0.028, 0.01)),
    "yellow_sponge": ("rounded_box", "yellow", partial(_S.rounded_box_parts, 0.095, 0.062, 0.03, 0.005)),
    "grey_rounded_cube": ("rounded_box", "grey", partial(_S.rounded_box_parts, 0.05, 0.05, 0.05, 0.01)),
    # irregular convex blobs (seeded by name)
    "grey_stone": ("blob", "grey", partial(_S.blob_parts, (0.035, 0.026, 0.016))),
    "brown_potato": ("blob", "brown", partial(_S.blob_parts, (0.045, 0.03, 0.025), roughness=0.12)),
    "orange_blob": ("blob", "orange", partial(_S.blob_parts, (0.03, 0.028, 0.026))),
    "cyan_blob": ("blob", "cyan", partial(_S.blob_parts, (0.04, 0.022, 0.02), points=36)),
}

BUILTIN_NAMES: tuple[str, ...] = tuple(_RECIPES)


def _seed(name: str) -> int:
    """A seed from the name that is the same in every process (unlike ``hash``)."""
    return zlib.crc32(name.encode("utf-8"))


def _build(name: str) -> ObjectModel:
    category, color, make = _RECIPES[name]
    raw = make(seed=_seed(name)) if category == "blob" else make()
    parts = tuple(shapes.standing_on_table(raw))
    visual = trimesh.util.concatenate(list(parts))
    return ObjectModel(name=name, parts=parts, rgba=COLORS[color], category=category,
                       visual=visual, source=f"builtin:{name}", color_name=color)


def builtin_object(name: str) -> ObjectModel:
    """The built-in object ``name`` (freshly built: callers may modify it)."""
    if name not in _RECIPES:
        raise MeshError(f"unknown built-in object {name!r}; known: {', '.join(BUILTIN_NAMES)}")
    return _build(name)


def builtin_objects() -> list[ObjectModel]:
    """All built-in objects in the order of :data:`BUILTIN_NAMES`."""
    return [_build(n) for n in BUILTIN_NAMES]


def footprint_min_width_m(model: ObjectModel) -> tuple[float, float]:
    """(width [m], yaw [rad]): the narrowest extent of the object's top-view outline (the
    convex hull of all part vertices projected on the table) and the direction in which it
    is measured (the gripper closes along that yaw). Rotating calipers: the minimum width of
    a convex polygon is attained perpendicular to one of its edges."""
    xy = np.vstack([p.vertices[:, :2] for p in model.parts])
    hull = xy[ConvexHull(xy).vertices]
    edges = np.roll(hull, -1, axis=0) - hull
    normals = np.column_stack([-edges[:, 1], edges[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    proj = hull @ normals.T  # (vertices, edges)
    widths = proj.max(axis=0) - proj.min(axis=0)
    k = int(np.argmin(widths))
    return float(widths[k]), float(np.arctan2(normals[k, 1], normals[k, 0]))
