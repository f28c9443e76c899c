"""Where grasps come from: the :class:`GraspSource` protocol and two implementations.

The grasp action executes whatever ``_core.BestGrasp`` poses a source proposes (position =
contact point, rotation column 0 = approach into the object, column 2 = closing axis,
``width_m``, ``score``), trying them in order until one can be planned. It never learns who
produced them, so a learned grasp detector replaces the geometric one by implementing
:meth:`GraspSource.propose` — nothing in motion or execution changes.

* :class:`GeometricGraspSource` — SPEC 3's top-down grasp from the target's box (the grasp
  the selection publishes every frame), then closing across the other side when it fits.
* :class:`FixedGraspSource` — a fixed list of poses (known grasps, a replay, a test).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Protocol, Sequence, runtime_checkable

import numpy as np

from .. import _core
from ..motion.perceived_scene import PerceivedScene
from .selection import perpendicular_grasp


@dataclass(frozen=True)
class GraspRequest:
    """What a source may use to propose grasps of one object.

    ``anchor_xy``: where the user (or the default target list) pointed [m, world];
    ``target``: the selected track (``_core.Track``) or None; ``published``: the best grasp
    the selection published for it (SPEC 5) or None; ``scene``: the perceived scene (points,
    boxes); ``max_width_m``: the widest object the gripper can close on with its margin."""

    anchor_xy: tuple[float, float]
    target: Optional[object]
    published: Optional[object]
    scene: PerceivedScene
    max_width_m: float


@runtime_checkable
class GraspSource(Protocol):
    """Proposes grasps for one object, best first (an empty list: no grasp)."""

    name: str

    def propose(self, request: GraspRequest) -> list:
        """``_core.BestGrasp`` candidates, best first."""


class GeometricGraspSource:
    """The published SPEC 3 grasp, then the perpendicular one when that side fits."""

    name = "geometric"

    def propose(self, request: GraspRequest) -> list:
        out = [] if request.published is None else [request.published]
        if request.target is not None and request.scene.plane is not None:
            alt = perpendicular_grasp(request.target, request.scene.plane, request.max_width_m)
            if alt is not None:
                out.append(alt)
        return out


class FixedGraspSource:
    """Grasps given up front; proposes those within ``radius_m`` of the anchor, nearest first."""

    name = "fixed"

    def __init__(self, grasps: Sequence, radius_m: float = 0.05) -> None:
        self.grasps = list(grasps)
        if radius_m <= 0:
            raise ValueError(f"FixedGraspSource radius_m must be > 0, got {radius_m}")
        self.radius_m = float(radius_m)

    @classmethod
    def from_poses(cls, poses: Sequence[tuple[np.ndarray, np.ndarray, float]],
                   radius_m: float = 0.05) -> "FixedGraspSource":
        """From (R 3x3, position (3,), width_m) triples in the BestGrasp convention."""
        return cls([_core.BestGrasp(np.asarray(R, float), np.asarray(p, float), float(w))
                    for R, p, w in poses], radius_m)

    def propose(self, request: GraspRequest) -> list:
        ax, ay = request.anchor_xy
        near = [(float(np.hypot(g.position[0] - ax, g.position[1] - ay)), k, g)
                for k, g in enumerate(self.grasps)]
        return [g for d, _, g in sorted(near) if d <= self.radius_m]
