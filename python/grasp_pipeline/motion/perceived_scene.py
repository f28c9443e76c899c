"""The scene as perception delivers it to the motion layer.

:class:`PerceivedScene` is what planning may use: environment points (table, floor, walls —
everything that is not an accepted object) and one oriented box per object. It never holds
simulator ground truth. It is produced by the perception core (see
``grasp_pipeline.orchestration.scene_model`` and the planning benchmark).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .occupancy import OrientedBox


@dataclass(frozen=True)
class PerceivedScene:
    """Perceived obstacles: ``environment_points`` (N, 3) world, ``object_boxes`` (oriented
    boxes of the objects, index = object id within this scene), ``table_height_m`` (or None),
    ``capture_q`` (arm joints at capture, for filtering the robot's own points; or None)."""

    environment_points: np.ndarray
    object_boxes: list[OrientedBox] = field(default_factory=list)
    table_height_m: float | None = None
    capture_q: np.ndarray | None = None
    T_world_camera: np.ndarray | None = None
