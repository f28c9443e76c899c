"""The fixed third-person view of the work cell that the run's video shows.

:class:`SceneView` renders the simulated world from a free camera (robot, table and tray in
view) — or from one of the model's cameras (``camera="wrist_depth_camera"``: a view that
moves with the hand, e.g. for a dataset's wrist images) — through
:func:`~.gl_backend.new_renderer`, as RGB or depth; where no GL context can exist it raises
:class:`~.exceptions.RenderUnavailable` at construction, and the caller skips the video.
"""

from __future__ import annotations

import mujoco
import numpy as np

from .gl_backend import new_renderer

VIEW_LOOKAT_M = (0.35, 0.2, 0.3)
VIEW_DISTANCE_M = 2.1
VIEW_AZIMUTH_DEG = 35.0   # from the robot's right-front: arm, table and tray in view
VIEW_ELEVATION_DEG = -28.0
#: A close view of the table's clutter square, from the far side of the table (failure PNGs).
TABLE_VIEW = {"lookat_m": (0.52, 0.0, 0.22), "distance_m": 0.55, "azimuth_deg": 200.0,
              "elevation_deg": -50.0}


class SceneView:
    """``render()`` → (H, W, 3) uint8 image of the world now; ``render_depth()`` → (H, W)
    float32 distances along the view axis [m]. ``camera``: a model camera's name instead of
    the free view (its pose and field of view; the other view arguments are ignored);
    ``shadows``/``reflections``: MuJoCo's render flags.

    Rendering reads the world and never changes its state: the images show the kinematics
    of the last physics step, as the run's video does."""

    def __init__(self, world, width_px: int = 640, height_px: int = 480,
                 lookat_m=VIEW_LOOKAT_M, distance_m: float = VIEW_DISTANCE_M,
                 azimuth_deg: float = VIEW_AZIMUTH_DEG,
                 elevation_deg: float = VIEW_ELEVATION_DEG, camera: str | None = None,
                 shadows: bool = True, reflections: bool = True) -> None:
        self.world = world
        self.renderer = new_renderer(world.model, height_px, width_px)
        # (software GL: shadows and reflections cost most of a small image's render time)
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = bool(shadows)
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = bool(reflections)
        if camera is not None:
            self.cam = world.model.camera(camera).id
            return
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = lookat_m
        cam.distance = distance_m
        cam.azimuth = azimuth_deg
        cam.elevation = elevation_deg
        self.cam = cam

    def render(self) -> np.ndarray:
        if self.renderer is None:
            raise RuntimeError("SceneView is closed")
        self.renderer.update_scene(self.world.data, camera=self.cam)
        return np.asarray(self.renderer.render())

    def render_from(self, lookat_m, distance_m: float, azimuth_deg: float,
                    elevation_deg: float) -> np.ndarray:
        """One image from another free view (the view itself is kept)."""
        if isinstance(self.cam, int):
            raise RuntimeError("render_from needs a free view, not a model camera")
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = lookat_m
        cam.distance, cam.azimuth, cam.elevation = distance_m, azimuth_deg, elevation_deg
        keep, self.cam = self.cam, cam
        try:
            return self.render()
        finally:
            self.cam = keep

    def render_depth(self) -> np.ndarray:
        """The depth image of the same view [m] (call after :meth:`render` for the same
        instant: the scene is not updated again)."""
        if self.renderer is None:
            raise RuntimeError("SceneView is closed")
        self.renderer.enable_depth_rendering()
        try:
            return np.asarray(self.renderer.render(), dtype=np.float32)
        finally:
            self.renderer.disable_depth_rendering()

    def close(self) -> None:
        if self.renderer is not None:
            self.renderer.close()
            self.renderer = None


class DeferredSceneView:
    """A :class:`SceneView` made at its first picture, for views that are rarely used (the
    pictures of a failed pick): creating one costs a GL context and a renderer (about 0.1 s
    in software GL), most runs never need it. Takes :class:`SceneView`'s arguments; a missing
    GL raises :class:`~.exceptions.RenderUnavailable` at the first picture instead of here
    (check :func:`~.gl_backend.gl_unavailable_reason` first to know sooner)."""

    def __init__(self, world, **view_args) -> None:
        self.world, self.view_args = world, dict(view_args)
        self._view: SceneView | None = None

    @property
    def made(self) -> bool:
        """Whether the view exists yet (a picture was asked for)."""
        return self._view is not None

    def _made(self) -> SceneView:
        if self._view is None:
            self._view = SceneView(self.world, **self.view_args)
        return self._view

    def render(self) -> np.ndarray:
        return self._made().render()

    def render_from(self, lookat_m, distance_m: float, azimuth_deg: float,
                    elevation_deg: float) -> np.ndarray:
        return self._made().render_from(lookat_m, distance_m, azimuth_deg, elevation_deg)

    def close(self) -> None:
        if self._view is not None:
            self._view.close()
            self._view = None
