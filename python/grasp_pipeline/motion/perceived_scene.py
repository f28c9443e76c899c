"""The scene as perception delivers it to the motion layer (the one perceived-scene type).

:class:`PerceivedScene` is what planning may use: environment points (table, floor, walls —
everything that is not an accepted object), one oriented box per tracked object (with the
track's id), the arm joints at capture (for removing the robot's own points) and the camera
pose. It never holds simulator ground truth. ``grasp_pipeline.orchestration.scene_model``
builds one from the perception loop.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from .occupancy import OrientedBox


@dataclass(frozen=True)
class PerceivedScene:
    """Perceived obstacles frozen at one instant.

    ``environment_points`` (N, 3) world [m]; ``boxes`` one :class:`OrientedBox` per object,
    ``tids`` the track id of each (same order); ``capture_q`` (7,) arm joints at capture or
    None; ``T_world_camera`` (4, 4) camera pose at capture or None; ``plane`` the table
    plane (``_core.Plane``) or None."""

    environment_points: np.ndarray
    boxes: list[OrientedBox] = field(default_factory=list)
    tids: list[int] = field(default_factory=list)
    capture_q: Optional[np.ndarray] = None
    T_world_camera: Optional[np.ndarray] = None
    plane: object = None

    def index_of(self, tid: Optional[int]) -> Optional[int]:
        return self.tids.index(tid) if tid is not None and tid in self.tids else None

    def keep(self, indices) -> "PerceivedScene":
        """The same scene with only the boxes at ``indices``."""
        idx = list(indices)
        return replace(self, boxes=[self.boxes[i] for i in idx], tids=[self.tids[i] for i in idx])

    def without_fragments(self, target_tid: int, margin_m: float) -> "PerceivedScene":
        """Drop boxes centred on the target's footprint (+ ``margin_m``): pieces of the
        target seen from another angle (a partly occluded view starts a track of its own),
        not neighbours — real objects cannot stand inside each other."""
        k = self.index_of(target_tid)
        if k is None:
            return self
        t = self.boxes[k]
        reach = 0.5 * float(np.hypot(t.extents[0], t.extents[1])) + margin_m
        return self.keep(i for i, b in enumerate(self.boxes)
                         if i == k or float(np.linalg.norm(b.center[:2] - t.center[:2])) > reach)
