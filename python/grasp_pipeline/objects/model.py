"""One object as the world builder needs it: convex collision parts, a visual mesh, a name.

All geometry is in metres in the object's own frame: z up, origin at the centre of the
bottom face of its axis-aligned bounding box (the object stands on z = 0 upright).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..exceptions import InputError


class MeshError(InputError):
    """A mesh or object description cannot be used (the message names the file or shape)."""


@dataclass(frozen=True)
class ObjectModel:
    """An object: ``parts`` are convex ``trimesh.Trimesh`` collision pieces whose union is the
    object; ``visual`` is the mesh drawn (and seen by the depth camera), by default the parts
    together; ``rgba`` its colour; ``category`` a word a user recognises ("mug", "bottle");
    ``source`` where it came from (a file path or ``"builtin:<name>"``); ``notes`` how the
    loader made it, and ``warnings`` (also among the notes) where its model is cruder than its
    files (a mesh that is not watertight, a skipped part, a convex hull instead of a
    decomposition, a cache file that did not fit)."""

    name: str
    parts: tuple
    rgba: tuple[float, float, float, float] = (0.6, 0.6, 0.6, 1.0)
    category: str = ""
    visual: Optional[object] = None
    source: str = ""
    color_name: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)
    warnings: tuple[str, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        if not self.parts:
            raise MeshError(f"object {self.name!r} ({self.source or 'no source'}): no collision parts")

    def bounds_m(self) -> np.ndarray:
        """(2, 3) axis-aligned bounds of all parts [m]."""
        lo = np.min([p.bounds[0] for p in self.parts], axis=0)
        hi = np.max([p.bounds[1] for p in self.parts], axis=0)
        return np.array([lo, hi])

    def extents_m(self) -> np.ndarray:
        b = self.bounds_m()
        return b[1] - b[0]

    def volume_m3(self) -> float:
        """Volume of the visual mesh when it is watertight, else the sum of the parts."""
        v = self.visual
        if v is not None and getattr(v, "is_watertight", False):
            return float(abs(v.volume))
        return float(sum(abs(p.volume) for p in self.parts))

    def mass_kg(self, density_kg_m3: float) -> float:
        return self.volume_m3() * float(density_kg_m3)

    def scaled(self, factor: float) -> "ObjectModel":
        """The same object scaled uniformly about its origin."""
        if not factor > 0:
            raise MeshError(f"object {self.name!r}: scale must be > 0, got {factor}")
        parts = tuple(p.copy().apply_scale(factor) for p in self.parts)
        visual = None if self.visual is None else self.visual.copy().apply_scale(factor)
        return ObjectModel(self.name, parts, self.rgba, self.category, visual, self.source,
                           self.color_name, self.notes, self.warnings)
