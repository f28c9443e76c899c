"""The work cell's fixed furniture as the robot's set-up knows it: the table top objects are
picked from and the fixtures (the tray) they are placed into.

Read from the model like a work-cell description (geometry fixed at installation), never an
object's pose. Used to decide which perceived tracks are objects *to pick* when the user
names none: a track over the tray is an object already placed (or a piece of the tray's
rim), a track off the table is a piece of the wall or the tray's far side — neither is a
pick target.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from ..motion.occupancy import OrientedBox
from ..sim.world import TABLE_TOP_GEOM
from .motion_client import fixture_boxes, geom_box


def _footprint_distance_m(box: OrientedBox, xy: np.ndarray) -> float:
    """Signed horizontal distance [m] from ``xy`` to the box's footprint (< 0: inside)."""
    local = box.R.T @ np.array([xy[0] - box.center[0], xy[1] - box.center[1], 0.0])
    # the footprint of an upright box: its local x/y extents (the box's z is vertical)
    over = np.abs(local[:2]) - 0.5 * np.asarray(box.extents)[:2]
    outside = np.linalg.norm(np.maximum(over, 0.0))
    return float(outside if outside > 0.0 else over.max())


@dataclass(frozen=True)
class WorkCell:
    """The table top and the fixtures, as oriented boxes in the world frame."""

    table: OrientedBox
    fixtures: tuple[OrientedBox, ...]

    @classmethod
    def from_world(cls, world) -> "WorkCell":
        return cls(geom_box(world, TABLE_TOP_GEOM), tuple(fixture_boxes(world)))

    def pick_target_note(self, xy: Sequence[float], fixture_margin_m: float) -> Optional[str]:
        """Why a track centred at ``xy`` [m] is not an object to pick (None: it is one)."""
        p = np.asarray(xy, dtype=float)[:2]
        if _footprint_distance_m(self.table, p) > 0.0:
            return f"({p[0]:.3f}, {p[1]:.3f}) is not over the table top"
        for box in self.fixtures:
            if _footprint_distance_m(box, p) <= fixture_margin_m:
                return (f"({p[0]:.3f}, {p[1]:.3f}) is over a work-cell fixture (the tray) "
                        f"or within {fixture_margin_m * 1e3:.0f} mm of it")
        return None
