"""A picture of where a failed attempt's object went (evaluation code: it reads the ground
truth, for the picture only).

A failure after the grasp (PLACE, or VERIFY: reported placed but not in the tray) happens over
the tray or on the way there, so the table view of the failure PNGs does not show it. This
view looks at the object's true position at the time of the failure: with the tray in the
picture when the object lies within :data:`TRAY_NEAR_M` of it (the camera aims between them
and backs off to hold both), else at the object alone.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..sim.ground_truth import object_truths

#: An object this near the tray centre [m] is shown together with the tray.
TRAY_NEAR_M = 0.6
#: The view: from above, a little from the far side of the table (steep enough that the
#: camera stays in front of the wall behind the table).
AZIMUTH_DEG, ELEVATION_DEG = 180.0, -75.0
CLOSE_DISTANCE_M = 0.5


def view_of(world, name: Optional[str]) -> Optional[dict]:
    """``SceneView.render_from`` arguments aimed at object ``name`` (None: unknown object)."""
    pos = next((t.position_m for t in object_truths(world) if t.name == name), None)
    if pos is None:
        return None
    pos = np.asarray(pos, float)
    tray = world.work_cell.tray_center_m
    if tray is not None and float(np.linalg.norm(pos - tray)) <= TRAY_NEAR_M:
        lookat = 0.5 * (pos + np.asarray(tray, float))
        distance = max(CLOSE_DISTANCE_M + 0.2, 1.3 * float(np.linalg.norm(pos - tray)) + 0.45)
    else:
        lookat, distance = pos, CLOSE_DISTANCE_M
    return {"lookat_m": lookat, "distance_m": distance, "azimuth_deg": AZIMUTH_DEG,
            "elevation_deg": ELEVATION_DEG}


class ObjectView:
    """``render(row) -> (H, W, 3) uint8`` of where ``row.object`` is now, or None when the row
    names no object of the scene; ``view``: a :class:`~grasp_pipeline.sim.scene_view.SceneView`."""

    def __init__(self, world, view) -> None:
        self.world, self.view = world, view

    def render(self, row) -> Optional[np.ndarray]:
        args = view_of(self.world, getattr(row, "object", None))
        return None if args is None else self.view.render_from(**args)
