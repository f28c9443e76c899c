"""An MP4 of the run from a fixed viewpoint (a runtime observer)."""

from __future__ import annotations

import logging
from typing import Optional

import numpy as np

from ..report.video import VideoWriter

log = logging.getLogger("grasp_pipeline.recorder")

VIEW_LOOKAT_M = (0.35, 0.2, 0.3)
VIEW_DISTANCE_M = 2.1
VIEW_AZIMUTH_DEG = 35.0   # from the robot's right-front: arm, table and tray in view
VIEW_ELEVATION_DEG = -28.0


class RunRecorder:
    """Renders the scene every ``1/fps`` simulated seconds into a :class:`VideoWriter`."""

    def __init__(self, world, path, fps: float = 10.0, width_px: int = 640, height_px: int = 480) -> None:
        import mujoco

        self.world = world
        self.period_s = 1.0 / fps
        self.next_s = world.time_s
        self.writer = VideoWriter(path, fps=fps)
        self.renderer: Optional[object] = mujoco.Renderer(world.model, height_px, width_px)
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = VIEW_LOOKAT_M
        cam.distance = VIEW_DISTANCE_M
        cam.azimuth = VIEW_AZIMUTH_DEG
        cam.elevation = VIEW_ELEVATION_DEG
        self.cam = cam

    def __call__(self, world) -> None:
        if world.time_s + 1e-9 < self.next_s or self.renderer is None:
            return
        self.next_s += self.period_s
        self.renderer.update_scene(world.data, camera=self.cam)
        self.writer.append(np.asarray(self.renderer.render()))

    def close(self) -> Optional[str]:
        self.writer.close()
        if self.renderer is not None:
            self.renderer.close()
            self.renderer = None
        return None if self.writer.path is None else str(self.writer.path)
