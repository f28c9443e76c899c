"""The scene as perception delivers it to the motion layer (the one perceived-scene type).

:class:`PerceivedScene` is what planning may use: environment points (table, floor, walls —
everything that is not an accepted object), one oriented box per tracked object (with the
track's id), each object's points in the latest frame (for modelling neighbours by their
points, :mod:`.object_points`), the arm joints at capture (for removing the robot's own points)
and the camera pose. It never holds simulator ground truth.
``grasp_pipeline.orchestration.scene.scene_model`` builds one from the perception loop.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from .object_points import (PointModel, column_tops, footprint_cells, footprint_overlap, seen_cells_among,
                            seen_fraction, seen_through)
from .occupancy import OrientedBox


@dataclass(frozen=True)
class PerceivedScene:
    """Perceived obstacles frozen at one instant.

    ``environment_points`` (N, 3) world [m]; ``boxes`` one :class:`OrientedBox` per object,
    ``tids`` the track id of each (same order); ``object_points`` the (N, 3) world points of
    each in the latest frame (same order; empty or missing: not seen); ``capture_q`` (7,) arm
    joints at capture or None; ``T_world_camera`` (4, 4) camera pose at capture or None;
    ``plane`` the table plane (``_core.Plane``) or None; ``band_m`` the scene filter's band
    above it (``scene_filter.band``): environment points lower than this are the table's (0:
    none known)."""

    environment_points: np.ndarray
    boxes: list[OrientedBox] = field(default_factory=list)
    tids: list[int] = field(default_factory=list)
    capture_q: Optional[np.ndarray] = None
    T_world_camera: Optional[np.ndarray] = None
    plane: object = None
    object_points: list[np.ndarray] = field(default_factory=list)
    band_m: float = 0.0

    def index_of(self, tid: Optional[int]) -> Optional[int]:
        return self.tids.index(tid) if tid is not None and tid in self.tids else None

    def keep(self, indices) -> "PerceivedScene":
        """The same scene with only the boxes at ``indices``."""
        idx = list(indices)
        pts = [self.object_points[i] for i in idx] if self.object_points else []
        return replace(self, boxes=[self.boxes[i] for i in idx], tids=[self.tids[i] for i in idx],
                       object_points=pts)

    def object_tops(self, model: PointModel) -> list[Optional[np.ndarray]]:
        """Per object (same order as ``boxes``), as ``model`` models it
        (:mod:`~.object_points`): its column tops when its points cover at least
        ``model.min_seen_fraction`` of its box's footprint; empty when they do not but the frame
        saw through that footprint (no obstacle of its own); else None (modelled by its box)."""
        if model.boxes_only:
            return [None] * len(self.boxes)
        out: list[Optional[np.ndarray]] = []
        for i, box in enumerate(self.boxes):
            pts = self.object_points[i] if i < len(self.object_points) else np.zeros((0, 3))
            top = column_tops(pts, model.cell_m)
            seen = len(top) and seen_fraction(top, box, model.cell_m) >= model.min_seen_fraction
            out.append(top if seen else None)
        unseen = [i for i, t in enumerate(out) if t is None]
        if unseen:
            # only the unseen footprints' cells are looked up (seen_through)
            needed = np.concatenate([footprint_cells(self.boxes[i], model.cell_m) for i in unseen])
            cells = seen_cells_among([self.environment_points, *self.object_points], needed, model.cell_m)
            seen_boxes = [b for b, t in zip(self.boxes, out) if t is not None]
            for i in unseen:
                if self._no_obstacle_of_its_own(self.boxes[i], cells, seen_boxes, model):
                    out[i] = np.zeros((0, 3))
        return out

    @staticmethod
    def _no_obstacle_of_its_own(box: OrientedBox, cells: np.ndarray, seen_boxes: list,
                                model: PointModel) -> bool:
        """An unseen object's box holds nothing of its own: the frame saw through its
        footprint, or it overlaps a seen object's (a duplicate track; :mod:`.object_points`)."""
        if seen_through(box, cells, model.cell_m) >= model.seen_through_fraction:
            return True
        return any(footprint_overlap(box, b, model.cell_m) >= model.duplicate_overlap for b in seen_boxes)

    def obstacles(self, target_tid: Optional[int], model: PointModel) -> tuple[list[OrientedBox], np.ndarray]:
        """Every object but ``target_tid`` as an obstacle, as :meth:`object_tops` models it:
        (the boxes of those modelled by their box, (M, 3) the column tops of the others)."""
        boxes, tops = [], []
        for box, tid, top in zip(self.boxes, self.tids, self.object_tops(model)):
            if tid == target_tid:
                continue
            if top is None:
                boxes.append(box)
            else:
                tops.append(top)
        return boxes, (np.vstack(tops) if tops else np.zeros((0, 3)))

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
