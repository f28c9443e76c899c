"""The eye-in-hand depth camera: rendering (GL or ray casting), noise, world point clouds.

Backends (chosen once, logged at INFO):

* ``gl`` — MuJoCo's offscreen renderer with the headless context picked by
  :mod:`.gl_backend` (``MUJOCO_GL`` = ``egl`` or ``osmesa``); the depth buffer is linearised
  by MuJoCo into metres along the optical axis.
* ``raycast`` — :func:`mujoco.mj_multiRay`, one ray per pixel through the pixel centre, for
  machines without any GL; it produces the same frame format (and, up to the depth buffer's
  precision, the same depths).

Per frame, on the *clean* depth: pixels nearer than ``min_range_m`` or farther than
``max_range_m`` (including "no surface"), and pixels whose surface is seen at more than
``grazing_max_deg`` from its normal, become NaN. Then Gaussian noise along the optical axis,
``sigma(z) = noise_sigma_m * (z / noise_ref_range_m) ** noise_exponent`` (2 mm at 0.4 m by
default), and the back-projection ``p_cam = z * ((u - cx)/fx, (v - cy)/fy, 1)``,
``p_world = T_world_camera p_cam``.

The surface angle comes from the depth image itself: with ``g_u = fx dz/du`` and
``g_v = fy dz/dv`` (one-sided differences, the smaller of the two, so an object's outline
pixels are kept), the surface normal is ``(-g_u, -g_v, g_u x + g_v y + z)`` and
``cos(angle) = z / (|n| |r|)`` for the pixel ray ``r = (x, y, 1)``.
"""

from __future__ import annotations

import logging
import math
import os

import mujoco
import numpy as np

from .config import CameraConfig
from .exceptions import RenderError
from .frame import Frame
from .robot_model import CAMERA_NAME

log = logging.getLogger(__name__)

#: MuJoCo camera frame (looks along -z, y up) -> optical frame (z forward, y down).
MJCAM_R_OPTICAL = np.diag([1.0, -1.0, -1.0])
#: Geom groups a depth frame sees (MuJoCo's renderer shows groups 0-2 by default).
VISIBLE_GEOM_GROUPS = np.array([1, 1, 1, 0, 0, 0], dtype=np.uint8)
_GL_OFF_VALUES = ("disable", "disabled", "off", "false", "0")


def intrinsics(width_px: int, height_px: int, vfov_deg: float) -> np.ndarray:
    """3x3 pinhole matrix of a MuJoCo camera (square pixels, centred principal point,
    pixel centres at integer coordinates)."""
    fy = 0.5 * height_px / math.tan(0.5 * math.radians(vfov_deg))
    return np.array([[fy, 0.0, 0.5 * (width_px - 1)],
                     [0.0, fy, 0.5 * (height_px - 1)],
                     [0.0, 0.0, 1.0]])


class DepthCamera:
    """Renders depth frames of the camera :data:`~.robot_model.CAMERA_NAME` of a model.

    Args:
        model, data: the simulation the camera lives in (``data`` is read, never stepped).
        config: image size, field of view, valid range, noise, backend.

    The vertical field of view in ``config`` is written into ``model.cam_fovy`` so the model
    and the intrinsics agree. Call :meth:`close` (or use ``with``) to free the GL context.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, config: CameraConfig):
        self.model = model
        self.data = data
        self.config = config
        self.cam_id = model.camera(CAMERA_NAME).id
        model.cam_fovy[self.cam_id] = config.vfov_deg
        self.K = intrinsics(config.width_px, config.height_px, config.vfov_deg)
        h, w = config.height_px, config.width_px
        fx, fy, cx, cy = self.K[0, 0], self.K[1, 1], self.K[0, 2], self.K[1, 2]
        self._x = ((np.arange(w, dtype=np.float32) - np.float32(cx)) / np.float32(fx))[None, :]
        self._y = ((np.arange(h, dtype=np.float32) - np.float32(cy)) / np.float32(fy))[:, None]
        self._ray_norm = np.sqrt(1.0 + self._x**2 + self._y**2).astype(np.float32)  # |(x, y, 1)|
        self._ray_norm2 = self._ray_norm**2
        self._cos_grazing = np.float32(math.cos(math.radians(config.grazing_max_deg)))
        self._fx = np.float32(fx)
        self._fy = np.float32(fy)
        self._rng = np.random.default_rng(config.seed)
        self._renderer: mujoco.Renderer | None = None
        self._frame_index = 0
        self.backend = self._start_backend()
        log.info("depth camera backend: %s (%dx%d px, vfov %.1f deg, %.0f Hz)",
                 self.backend, w, h, config.vfov_deg, config.rate_hz)

    # ------------------------------------------------------------------ backends
    def _start_backend(self) -> str:
        cfg = self.config
        gl_name = os.environ.get("MUJOCO_GL", "").strip().lower()
        if cfg.backend == "raycast":
            return "raycast"
        if gl_name in _GL_OFF_VALUES:
            if cfg.backend == "gl":
                raise RenderError(f"camera backend 'gl' requested but MUJOCO_GL={gl_name!r}")
            log.warning("MUJOCO_GL=%s: no GL rendering, depth frames are ray-cast", gl_name)
            return "raycast"
        try:
            vis = self.model.vis.global_
            vis.offwidth = max(int(vis.offwidth), cfg.width_px)
            vis.offheight = max(int(vis.offheight), cfg.height_px)
            self._renderer = mujoco.Renderer(self.model, cfg.height_px, cfg.width_px)
            self._renderer.enable_depth_rendering()
            # Depth needs none of these; they cost 2-3x the render time in software GL.
            for flag in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION,
                         mujoco.mjtRndFlag.mjRND_SKYBOX):
                self._renderer.scene.flags[flag] = 0
        except Exception as exc:  # any GL failure: missing library, no device, ...
            self._renderer = None
            if cfg.backend == "gl":
                raise RenderError(
                    f"GL depth rendering failed with MUJOCO_GL={gl_name or '(unset)'}: {exc}. "
                    "Install libegl1/libosmesa6 or use camera backend 'raycast'.") from exc
            log.warning("GL rendering unavailable (MUJOCO_GL=%s: %s); depth frames are ray-cast",
                        gl_name or "(unset)", exc)
            return "raycast"
        return gl_name or "gl"

    def close(self) -> None:
        """Free the GL context (needed with OSMesa to avoid an error message at exit)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __enter__(self) -> "DepthCamera":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ geometry
    def pose(self) -> np.ndarray:
        """World pose of the optical frame for the kinematics currently in ``data``."""
        T = np.eye(4)
        T[:3, :3] = self.data.cam_xmat[self.cam_id].reshape(3, 3) @ MJCAM_R_OPTICAL
        T[:3, 3] = self.data.cam_xpos[self.cam_id]
        return T

    def _clean_depth_gl(self) -> np.ndarray:
        assert self._renderer is not None
        self._renderer.update_scene(self.data, camera=self.cam_id)
        return np.asarray(self._renderer.render(), dtype=np.float32)

    def _clean_depth_raycast(self, T_world_camera: np.ndarray) -> np.ndarray:
        h, w = self.config.height_px, self.config.width_px
        n = h * w
        vec = np.empty((h, w, 3), dtype=np.float64)
        for i, d in enumerate(self._world_directions(T_world_camera[:3, :3])):
            vec[..., i] = d / self._ray_norm  # unit rays
        geomid = np.empty(n, dtype=np.int32)
        dist = np.empty(n, dtype=np.float64)
        mujoco.mj_multiRay(self.model, self.data, T_world_camera[:3, 3].copy(), vec.reshape(-1),
                           VISIBLE_GEOM_GROUPS, 1, -1, geomid, dist, None, n,
                           float(self.config.max_range_m) * float(self._ray_norm.max()))
        dist[geomid < 0] = np.inf
        return (dist.reshape(h, w) / self._ray_norm).astype(np.float32)

    def _world_directions(self, R: np.ndarray) -> list[np.ndarray]:
        """Per pixel, the world direction of the camera-frame vector (x, y, 1), as three
        (H, W) float32 arrays. (Written out per component: a float32 ``(N, 3) @ (3, 3)``
        matmul is an order of magnitude slower with some BLAS builds.)"""
        R32 = R.astype(np.float32)
        return [R32[i, 0] * self._x + R32[i, 1] * self._y + R32[i, 2] for i in range(3)]

    def _grazing_mask(self, z: np.ndarray) -> np.ndarray:
        """True where the surface is seen at more than ``grazing_max_deg`` from its normal.

        Interior pixels only (the 1-pixel image border is never marked); a pixel next to a
        NaN takes the NaN-free side or, with NaN on both sides, is kept.
        """
        gu = np.zeros_like(z)
        gv = np.zeros_like(z)
        with np.errstate(invalid="ignore", over="ignore"):
            d = np.diff(z, axis=1)
            back, fwd = d[:, :-1], d[:, 1:]
            gu[:, 1:-1] = np.where(np.abs(fwd) <= np.abs(back), fwd, back)
            d = np.diff(z, axis=0)
            back, fwd = d[:-1], d[1:]
            gv[1:-1] = np.where(np.abs(fwd) <= np.abs(back), fwd, back)
            gu *= self._fx
            gv *= self._fy
            nz = gu * self._x
            nz += gv * self._y
            nz += z
            n2 = gu * gu
            n2 += gv * gv
            n2 += nz * nz
            # cos = z / (|n| |r|) < cos_max  <=>  z^2 < cos_max^2 |n|^2 |r|^2  (z > 0)
            return z * z < (self._cos_grazing**2) * n2 * self._ray_norm2

    # ------------------------------------------------------------------ capture
    def capture(self) -> Frame:
        """One frame of the state currently in ``data`` (kinematics must be up to date)."""
        cfg = self.config
        T = self.pose()
        if self.backend == "raycast":
            z = self._clean_depth_raycast(T)
        else:
            z = self._clean_depth_gl()
        invalid = ~((z >= cfg.min_range_m) & (z <= cfg.max_range_m))
        z = np.where(invalid, np.float32(np.nan), z)
        invalid |= self._grazing_mask(z)
        if cfg.noise_sigma_m > 0:
            sigma = np.float32(cfg.noise_sigma_m) * (
                z / np.float32(cfg.noise_ref_range_m)) ** np.float32(cfg.noise_exponent)
            z = z + sigma * self._rng.standard_normal(z.shape, dtype=np.float32)
        z[invalid] = np.nan
        pts_world = np.empty(z.shape + (3,), dtype=np.float32)
        for i, d in enumerate(self._world_directions(T[:3, :3])):
            pts_world[..., i] = z * d + np.float32(T[i, 3])
        pts_world = pts_world.reshape(-1, 3)
        frame = Frame(points_world=pts_world, depth=z, time_s=float(self.data.time),
                      T_world_camera=T, K=self.K.copy(), backend=self.backend,
                      index=self._frame_index)
        self._frame_index += 1
        return frame
