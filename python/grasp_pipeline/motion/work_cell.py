"""The work cell's fixed furniture as the robot's set-up knows it: the table top objects are
picked from, the fixtures (the tray) they are placed into, and where the tray is.

Geometry fixed at installation (a work-cell description), never an object's pose. The motion
layer plans around ``fixtures``; the orchestration decides from ``table`` and ``fixtures``
which perceived tracks are objects *to pick*. ``grasp_pipeline.sim.work_cell`` reads one
from the simulated model; a real cell loads it from its work-cell file
(``grasp_pipeline.app.work_cell_file``; ``config/work_cell.yaml`` is the simulated cell's).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .occupancy import OrientedBox


def footprint_distance_m(box: OrientedBox, xy: np.ndarray) -> float:
    """Signed horizontal distance [m] from ``xy`` to the box's footprint (< 0: inside)."""
    local = box.R.T @ np.array([xy[0] - box.center[0], xy[1] - box.center[1], 0.0])
    # the footprint of an upright box: its local x/y extents (the box's z is vertical)
    over = np.abs(local[:2]) - 0.5 * np.asarray(box.extents)[:2]
    outside = np.linalg.norm(np.maximum(over, 0.0))
    return float(outside if outside > 0.0 else over.max())


@dataclass(frozen=True)
class WorkCell:
    """The table top, the fixtures (obstacles) and the tray, in the world frame.

    ``tray_center_m``: (3,) centre of the tray's floor surface [m]; ``tray_floor``: the tray
    floor's box (its footprint is the area counted as "in the tray")."""

    table: OrientedBox
    fixtures: tuple[OrientedBox, ...]
    tray_center_m: Optional[np.ndarray] = None
    tray_floor: Optional[OrientedBox] = None

    def pick_target_note(self, xy: Sequence[float], fixture_margin_m: float) -> Optional[str]:
        """Why a track centred at ``xy`` [m] is not an object to pick (None: it is one)."""
        p = np.asarray(xy, dtype=float)[:2]
        if footprint_distance_m(self.table, p) > 0.0:
            return f"({p[0]:.3f}, {p[1]:.3f}) is not over the table top"
        for box in self.fixtures:
            if footprint_distance_m(box, p) <= fixture_margin_m:
                return (f"({p[0]:.3f}, {p[1]:.3f}) is over a work-cell fixture (the tray) "
                        f"or within {fixture_margin_m * 1e3:.0f} mm of it")
        return None
