"""The recording's camera views: a fixed scene camera and the wrist camera, at the dataset's size.

Both are :class:`~grasp_pipeline.sim.scene_view.SceneView` renderers of their own (the
pipeline's eye-in-hand camera renders only when perception looks, at its own size): the
``scene`` view is a fixed agent view of the table and the tray (``record.yaml``'s
``scene_*``); the ``wrist`` view is the eye-in-hand camera's pose and field of view.
"""

from __future__ import annotations

import numpy as np

from ..robot.description import CAMERA_NAME
from .config import RecordConfig

#: Camera names, as in the dataset's feature keys ``observation.images.<name>``.
CAMERAS = ("wrist", "scene")


class RecordingViews:
    """``views()`` → (images, depths): camera name -> RGB (H, W, 3) uint8, and with
    ``depth`` camera name -> (H, W) float32 [m] (0 where nothing lies within
    ``depth_max_m``). Raises :class:`~grasp_pipeline.sim.exceptions.RenderUnavailable` at
    construction where no GL context can exist."""

    def __init__(self, world, config: RecordConfig, depth: bool = False) -> None:
        from ..sim.scene_view import SceneView

        w, h = config.image_width_px, config.image_height_px
        self.depth, self.depth_max_m = depth, config.depth_max_m
        look = {"shadows": config.render_shadows, "reflections": config.render_reflections}
        self.views = {}
        self.views["wrist"] = SceneView(world, w, h, camera=CAMERA_NAME, **look)
        self.views["scene"] = SceneView(world, w, h, lookat_m=config.scene_lookat_m,
                                        distance_m=config.scene_distance_m,
                                        azimuth_deg=config.scene_azimuth_deg,
                                        elevation_deg=config.scene_elevation_deg, **look)

    def __call__(self) -> tuple[dict, dict]:
        images, depths = {}, {}
        for name, view in self.views.items():
            images[name] = view.render()
            if self.depth:
                d = view.render_depth()
                depths[name] = np.where((d > 0) & (d <= self.depth_max_m), d, 0.0).astype(np.float32)
        return images, depths

    def close(self) -> None:
        for view in self.views.values():
            view.close()
