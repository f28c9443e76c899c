"""MuJoCo's offscreen renderer, one pass read back as colour and metric depth together.

``mujoco.Renderer`` returns either colour or depth per call, so an RGB-D frame took two full
renders (and, in software GL, rendering is most of a frame's cost). :class:`RgbdRenderer`
renders the scene once and reads both buffers of that pass: the depth buffer does not depend
on lighting or colour, so the depth is the one a depth-only pass gives, bit for bit (the
camera tests compare them); the colour is the one a colour pass gives.

Depth is linearised as ``mujoco.Renderer`` does it (reversed-Z depth map, near/far planes
from ``model.vis.map`` and the model's extent, float32 coefficients, float64 division, a
float32 result): metres along the optical axis. Segmentation (per pixel, the geom shown) is
MuJoCo's segmentation pass on the same scene, for evaluation labels.

Create renderers through :func:`~.gl_backend.new_renderer` (it refuses cleanly where no GL
context can exist); call :meth:`close` to free the GL context.
"""

from __future__ import annotations

from typing import Optional

import mujoco
import numpy as np
from mujoco import gl_context

from .. import _core
from .draw_order import DrawOrder
from .exceptions import RenderUnavailable


class RgbdRenderer:
    """Offscreen RGB-D rendering of a model's camera (perspective cameras).

    Args:
        model: the model to render (its ``vis.global_.offwidth/offheight`` must hold the size).
        height_px, width_px: image size.
        max_geom: capacity of the abstract scene.
    """

    def __init__(self, model: mujoco.MjModel, height_px: int, width_px: int,
                 max_geom: int = 10000):
        context_cls = _owned_context_class()
        self._gl: Optional[object] = None
        self._mjr: Optional[mujoco.MjrContext] = None
        self.model = model
        self.height, self.width = int(height_px), int(width_px)
        self.scene = mujoco.MjvScene(model, maxgeom=max_geom)
        self._option = mujoco.MjvOption()
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._rect = mujoco.MjrRect(0, 0, self.width, self.height)
        self._gl = context_cls(self.width, self.height)
        self._gl.make_current()
        self._mjr = _context_of_image_size(model, self.width, self.height)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr)
        self._mjr.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        self._draw = DrawOrder(model, self._option, self.width / self.height)

    def update_scene(self, data: mujoco.MjData, camera_id: int) -> None:
        """Take the geometry of ``data`` as seen from the model camera ``camera_id`` (the geoms
        that can reach a pixel, planes last: :mod:`.draw_order`)."""
        self._camera.fixedcamid = int(camera_id)
        self._draw.update_scene(data, self._camera, self.scene)

    def render(self, rgb: bool = True) -> tuple[np.ndarray, Optional[np.ndarray]]:
        """One pass: ``(depth, colour)`` — depth (H, W) float32 [m] along the optical axis,
        colour (H, W, 3) uint8 or None when ``rgb`` is False. Rows top to bottom."""
        self._current()
        mujoco.mjr_render(self._rect, self.scene, self._mjr)
        raw = np.empty((self.height, self.width), dtype=np.float32)
        colour = np.empty((self.height, self.width, 3), dtype=np.uint8) if rgb else None
        mujoco.mjr_readPixels(colour, raw, self._rect, self._mjr)
        depth = self._metric_depth(raw)
        return depth, None if colour is None else np.ascontiguousarray(colour[::-1])

    def segmentation(self) -> np.ndarray:
        """(H, W) int32: per pixel the id of the geom shown, -1 for none (background or a
        decor that is not a geom), from MuJoCo's segmentation pass of the current scene."""
        self._current()
        flags = self.scene.flags
        saved = flags.copy()
        flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = 1
        flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = 1
        try:
            mujoco.mjr_render(self._rect, self.scene, self._mjr)
            image = np.empty((self.height, self.width, 3), dtype=np.uint8)
            mujoco.mjr_readPixels(image, None, self._rect, self._mjr)
        finally:
            np.copyto(flags, saved)
        code = image[::-1].astype(np.int32)
        segid = code[..., 0] + code[..., 1] * 256 + code[..., 2] * 65536  # 0: nothing
        geom_of = np.full(self.scene.ngeom + 1, -1, dtype=np.int32)
        for g in self.scene.geoms[:self.scene.ngeom]:
            if g.segid != -1 and g.objtype == int(mujoco.mjtObj.mjOBJ_GEOM):
                geom_of[g.segid + 1] = g.objid
        return geom_of[segid]

    def close(self) -> None:
        """Free the MuJoCo rendering context and the GL context (idempotent)."""
        if self._mjr is not None:
            if self._gl is not None:
                self._gl.make_current()
            self._mjr.free()
            self._mjr = None
        if self._gl is not None:
            self._gl.free()
            self._gl = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: nothing left to free into
            pass

    # ------------------------------------------------------------------ internals
    def _current(self) -> None:
        if self._mjr is None or self._gl is None:
            raise RuntimeError("RgbdRenderer used after close()")
        self._gl.make_current()

    def _metric_depth(self, raw: np.ndarray) -> np.ndarray:
        """Reversed-Z depth-buffer values (rows bottom to top, as read) -> metres along the
        optical axis, rows top to bottom, with ``mujoco.Renderer``'s arithmetic."""
        extent = self.model.stat.extent
        zfar = np.float32(self.model.vis.map.zfar * extent)
        znear = np.float32(self.model.vis.map.znear * extent)
        c_coef = -(zfar + znear) / (zfar - znear)
        d_coef = -(np.float32(2) * zfar * znear) / (zfar - znear)
        c_coef = np.float32(-0.5) * c_coef - np.float32(0.5)
        d_coef = np.float32(-0.5) * d_coef
        if self.scene.camera[0].orthographic:  # linear depth map
            return (zfar - raw[::-1].astype(np.float64) * (zfar - znear)).astype(np.float32)
        # float(d / (raw + c)) in float64, rows flipped: one C++ pass
        return _core.metric_depth(raw, float(c_coef), float(d_coef))


def _context_of_image_size(model: mujoco.MjModel, width_px: int, height_px: int
                           ) -> mujoco.MjrContext:
    """A MuJoCo rendering context whose offscreen buffer is the image's size (the model's
    ``offwidth/offheight`` may be larger, for videos: a larger buffer is cleared and resolved
    whole on every frame). Its font is the smallest: no text is drawn into a depth frame, and
    the font textures of the default scale cost 30 ms at every creation."""
    vis = model.vis.global_
    saved = int(vis.offwidth), int(vis.offheight)
    vis.offwidth, vis.offheight = int(width_px), int(height_px)
    try:
        return mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_50)
    finally:
        vis.offwidth, vis.offheight = saved


_OWNED_CONTEXT: dict[type, type] = {}


def _owned_context_class() -> type:
    """MuJoCo's GL context class with its own finaliser switched off: the renderer frees the
    MuJoCo context first (with the GL context current), then the GL context."""
    cls = getattr(gl_context, "GLContext", None)
    if cls is None:
        raise RenderUnavailable("MuJoCo was imported without a GL platform (MUJOCO_GL)")
    if cls not in _OWNED_CONTEXT:
        _OWNED_CONTEXT[cls] = type(f"_Owned{cls.__name__}", (cls,), {"__del__": lambda self: None})
    return _OWNED_CONTEXT[cls]
