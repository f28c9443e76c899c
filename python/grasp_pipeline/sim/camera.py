"""The eye-in-hand RGB-D camera: rendering (GL or ray casting), noise, world point clouds.

Backends (chosen once, logged at INFO):

* ``gl`` — MuJoCo's offscreen renderer with the headless context picked by
  :mod:`.gl_backend` (``MUJOCO_GL`` = ``egl`` or ``osmesa``), one render pass per frame read
  back as depth and colour (:mod:`.rgbd_renderer`); the depth buffer is linearised as
  ``mujoco.Renderer`` does it into metres along the optical axis.
* ``raycast`` — :func:`mujoco.mj_multiRay`, one ray per pixel through the pixel centre, for
  machines without any GL; it produces the same frame format (and, up to the depth buffer's
  precision, the same depths). See :meth:`DepthCamera._clean_depth_raycast` for how it is made
  fast (per-tile frustum culling into small private ray-cast models, 1-2 threads) without
  changing a single depth value.

Per frame, on the *clean* depth: pixels nearer than ``min_range_m`` or farther than
``max_range_m`` (including "no surface"), and pixels whose surface is seen at more than
``grazing_max_deg`` from its normal, become NaN. Then (``add_noise``) the sensor's Gaussian
noise along the optical axis, ``sigma(z) = depth_noise_sigma_m * (z / depth_noise_ref_range_m)
** depth_noise_exponent`` (``config/depth_noise.yaml``, the model perception expects too; 2 mm
at 0.4 m by default; one standard normal draw per pixel, from the C++ core's seeded stream,
its seed drawn per frame from a generator of ``camera.seed``), and the back-projection
``p_cam = z * ((u - cx)/fx, (v - cy)/fy, 1)``, ``p_world = T_world_camera p_cam``. While no
geom and not the camera moved more than ``still_tolerance_m`` since the last render, a frame
reuses that render's clean images (:mod:`.still_scene`) and draws its own noise.

Colour (``camera.rgb``, on by default): ``Frame.rgb`` is rendered by the same camera at the
same instant as the depth, so pixel (u, v) of both shows the same surface. GL: colour and depth
are read from one render pass (:class:`~.rgbd_renderer.RgbdRenderer`; shadows, reflections and
skybox off: in software GL they cost several times a whole frame). Ray cast: the hit
geom's colour (its material's, times the mean texel of the material's texture, when it has a
material and no colour of its own) with Lambert shading by a light at the camera,
``ambient + (1 - ambient) |n . r|`` for the hit surface normal ``n`` and unit ray ``r``; no hit
is black. The colour image is not masked where the depth is invalid.

Labels (``camera.labels``, off by default; **evaluation only**): per pixel, the geom the pixel
shows (GL: MuJoCo's segmentation rendering, a third pass; ray cast: the hit geom), -1 where
there is none or the depth is invalid. They are never put in the frame: the camera keeps the
image of its latest frame privately and :mod:`.ground_truth` turns it into object labels.

The surface angle comes from the depth image itself: with ``g_u = fx dz/du`` and
``g_v = fy dz/dv`` (one-sided differences, the smaller of the two, so an object's outline
pixels are kept), the surface normal is ``(-g_u, -g_v, g_u x + g_v y + z)`` and
``cos(angle) = z / (|n| |r|)`` for the pixel ray ``r = (x, y, 1)``.

The per-pixel passes (invalid pixels and the grazing mask; the final NaN and the world points)
run in the C++ core (``_core.mask_invalid_and_grazing``, ``_core.depth_to_world_points``): the
float32 operations of the plain numpy formulation in its order, so the frames are the same bit
for bit (the camera tests compare them with that formulation), in a single pass each instead
of some thirty numpy passes over the image. The noise stays in numpy (its draws are numpy's
generator's).
"""

from __future__ import annotations

import itertools
import logging
import math
import os
import threading
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor

import mujoco
import numpy as np

from .. import _core
from .config import CameraConfig
from .exceptions import RenderError, RenderUnavailable
from ..robot.frame import Frame
from ..robot.depth_noise import DepthNoiseConfig, load_depth_noise_config
from ..robot.description import CAMERA_NAME
from .gl_backend import gl_in_effect, new_renderer
from .rgbd_renderer import RgbdRenderer
from .still_scene import CleanImages, StillSceneCache

log = logging.getLogger(__name__)

#: MuJoCo camera frame (looks along -z, y up) -> optical frame (z forward, y down).
MJCAM_R_OPTICAL = np.diag([1.0, -1.0, -1.0])
#: Geom groups a depth frame sees (MuJoCo's renderer shows groups 0-2 by default).
VISIBLE_GEOM_GROUPS = np.array([1, 1, 1, 0, 0, 0], dtype=np.uint8)

#: Ray-cast threads never exceed this by default (the caller's thread counts as one).
RAYCAST_MAX_THREADS = 2
#: Ray-cast tile size (rows, columns) [px]; each tile is culled against its own frustum.
RAYCAST_TILE_PX = (60, 160)
#: Geom types the culled ray cast handles (pure primitives: ``mju_rayGeom``); a model with any
#: other visible geom (mesh, hfield, SDF) or a flex is ray-cast the plain way.
_PRIMITIVE_GEOMS = frozenset(int(t) for t in (
    mujoco.mjtGeom.mjGEOM_PLANE, mujoco.mjtGeom.mjGEOM_SPHERE, mujoco.mjtGeom.mjGEOM_CAPSULE,
    mujoco.mjtGeom.mjGEOM_ELLIPSOID, mujoco.mjtGeom.mjGEOM_CYLINDER, mujoco.mjtGeom.mjGEOM_BOX))
#: Frustum-culling slack: angular [rad] (float32 ray directions are off by ~1e-7) and linear [m].
_CULL_MARGIN_RAD = 1e-4
_CULL_MARGIN_M = 1e-6
#: Private ray-cast models kept (one per distinct set of geoms a tile can see).
_RAY_SCENE_CACHE = 256
#: Unit cube corners, for the geoms' local bounding boxes.
_BOX_CORNERS = np.array([[sx, sy, sz] for sx in (-1.0, 1.0) for sy in (-1.0, 1.0)
                         for sz in (-1.0, 1.0)])
#: Ray-cast colour: share of a surface's colour lit regardless of its angle to the ray.
RGB_AMBIENT = 0.3
#: MuJoCo's default geom colour; a geom with a material and this colour shows the material's.
_DEFAULT_GEOM_RGBA = np.array([0.5, 0.5, 0.5, 1.0], dtype=np.float32)


class _RayHits:
    """Per-pixel by-products of a ray cast: the hit geom (scene model ids, -1 for none) and,
    when ``shade`` is requested, ``|cos|`` of the angle between the ray and the surface."""

    def __init__(self, h: int, w: int, shade: bool):
        self.geom = np.full((h, w), -1, dtype=np.int32)
        self.cos = np.zeros((h, w), dtype=np.float32) if shade else None


def default_raycast_threads() -> int:
    """Threads of the ray-cast backend: the usable cores, at most :data:`RAYCAST_MAX_THREADS`,
    and at most ``OMP_NUM_THREADS`` when that is set (the benchmarks' one-thread workers)."""
    try:
        n = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        n = os.cpu_count() or 1
    omp = os.environ.get("OMP_NUM_THREADS", "").strip()
    if omp.isdigit() and int(omp) > 0:
        n = min(n, int(omp))
    return max(1, min(RAYCAST_MAX_THREADS, n))


class _RayScene:
    """A private model holding copies of some geoms of the scene model, all in its world body,
    for :func:`mujoco.mj_multiRay` against just those geoms.

    Per ray, ``mj_multiRay`` visits every body of the model (a bounding-sphere test each) and
    every geom (the elimination flag and a bounding-angle test) before any real intersection;
    in the scene model that is ~16 bodies and 48 geoms for every pixel, most of which no pixel
    can see. Here there is one body whose bounding volume is made infinite (so its test always
    passes); each geom keeps the size, type, local bounding box and bounding radius of the
    original and is given its current world pose, so ``mju_rayGeom`` and the bounding-angle
    test get bit-identical inputs and return bit-identical distances.
    """

    def __init__(self, model: mujoco.MjModel, geoms: np.ndarray, n_workers: int):
        self.geoms = geoms
        spec = mujoco.MjSpec()
        spec.memory = 65536 + 128 * len(geoms)  # mj_multiRay's stack needs ~40 bytes a geom
        for g in geoms:
            spec.worldbody.add_geom(type=mujoco.mjtGeom(int(model.geom_type[g])),
                                    size=np.array(model.geom_size[g], dtype=float))
        self.model = spec.compile()
        self.sync(model)
        root = self.model.body_bvhadr[0]
        if root >= 0:  # compiled for the geoms at the origin: make it cover any pose
            self.model.bvh_aabb[root] = [0.0, 0.0, 0.0, 1e10, 1e10, 1e10]
        self.datas = [mujoco.MjData(self.model) for _ in range(n_workers)]

    def sync(self, model: mujoco.MjModel) -> None:
        """Take the original geoms' (possibly edited) sizes and bounds."""
        g = self.geoms
        self.model.geom_size[:] = model.geom_size[g]
        self.model.geom_aabb[:] = model.geom_aabb[g]
        self.model.geom_rbound[:] = model.geom_rbound[g]


def intrinsics(width_px: int, height_px: int, vfov_deg: float) -> np.ndarray:
    """3x3 pinhole matrix of a MuJoCo camera (square pixels, centred principal point,
    pixel centres at integer coordinates)."""
    fy = 0.5 * height_px / math.tan(0.5 * math.radians(vfov_deg))
    return np.array([[fy, 0.0, 0.5 * (width_px - 1)],
                     [0.0, fy, 0.5 * (height_px - 1)],
                     [0.0, 0.0, 1.0]])


class DepthCamera:
    """Renders RGB-D frames of the camera :data:`~grasp_pipeline.robot.description.CAMERA_NAME` (or ``camera_name``) of a model.

    Args:
        model, data: the simulation the camera lives in (``data`` is read, never stepped).
        config: image size, field of view, valid range, noise on/off, backend, colour, labels.
        depth_noise: the sensor's noise model (default: ``config/depth_noise.yaml``).

    The vertical field of view in ``config`` is written into ``model.cam_fovy`` so the model
    and the intrinsics agree. Call :meth:`close` (or use ``with``) to free the GL context and
    the ray-cast thread pool. ``raycast_threads``: threads of the ray-cast backend, the
    caller's included (default :func:`default_raycast_threads`, at most 2). ``camera_name``:
    the MJCF camera (default: the eye-in-hand camera).
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, config: CameraConfig,
                 raycast_threads: int | None = None, camera_name: str = CAMERA_NAME,
                 depth_noise: DepthNoiseConfig | None = None):
        self.model = model
        self.data = data
        self.config = config
        self.depth_noise = depth_noise if depth_noise is not None else load_depth_noise_config()
        self.camera_name = camera_name
        self.cam_id = model.camera(camera_name).id
        model.cam_fovy[self.cam_id] = config.vfov_deg
        self.K = intrinsics(config.width_px, config.height_px, config.vfov_deg)
        h, w = config.height_px, config.width_px
        fx, fy, cx, cy = self.K[0, 0], self.K[1, 1], self.K[0, 2], self.K[1, 2]
        self._x = ((np.arange(w, dtype=np.float32) - np.float32(cx)) / np.float32(fx))[None, :]
        self._y = ((np.arange(h, dtype=np.float32) - np.float32(cy)) / np.float32(fy))[:, None]
        self._ray_norm = np.sqrt(1.0 + self._x**2 + self._y**2).astype(np.float32)  # |(x, y, 1)|
        self._ray_norm2 = self._ray_norm**2
        self._x_row = np.ascontiguousarray(self._x.ravel())  # (W,) and (H,): for the C++ passes
        self._y_col = np.ascontiguousarray(self._y.ravel())
        self._cos_grazing = np.float32(math.cos(math.radians(config.grazing_max_deg)))
        self._fx = np.float32(fx)
        self._fy = np.float32(fy)
        self._rng = np.random.default_rng(config.seed)
        self._rgb = bool(config.rgb)
        # Evaluation only (read by the ground-truth module, never put in a frame): whether
        # labels are computed, the per-pixel geom ids of the latest frame and its identity.
        self._eval_labels = bool(config.labels)
        self._eval_geoms: np.ndarray | None = None
        self._eval_frame_key: tuple | None = None
        self._mat_texel: np.ndarray | None = None  # (nmat, 3) mean texel of each material
        self._renderer: RgbdRenderer | None = None
        self._frame_index = 0
        self._still = StillSceneCache(config.still_tolerance_m)
        self._pool: ThreadPoolExecutor | None = None
        self._ray_scenes: OrderedDict[tuple, _RayScene] = OrderedDict()
        self._raycast_threads = 1
        self.raycast_threads = (default_raycast_threads() if raycast_threads is None
                                else raycast_threads)
        th, tw = RAYCAST_TILE_PX
        self._tiles = [(r, min(r + th, h), c, min(c + tw, w))
                       for r in range(0, h, th) for c in range(0, w, tw)]
        self.backend = self._start_backend()
        log.info("depth camera backend: %s (%dx%d px, vfov %.1f deg, %.0f Hz)",
                 self.backend, w, h, config.vfov_deg, config.rate_hz)

    # ------------------------------------------------------------------ backends
    def _start_backend(self) -> str:
        """``"raycast"`` or the GL backend in effect; GL only through
        :func:`~.gl_backend.new_renderer`, which refuses where no context can exist."""
        cfg = self.config
        if cfg.backend == "raycast":
            return "raycast"
        try:
            self._renderer = new_renderer(self.model, cfg.height_px, cfg.width_px, RgbdRenderer)
            # The frame needs none of these; they cost 2-3x the render time in software GL.
            for flag in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION,
                         mujoco.mjtRndFlag.mjRND_SKYBOX):
                self._renderer.scene.flags[flag] = 0
        except RenderUnavailable as exc:
            self._renderer = None
            if cfg.backend == "gl":
                raise RenderError(f"camera backend 'gl' requested, but {exc}. Install "
                                  "libegl1/libosmesa6 or use camera backend 'raycast'.") from exc
            log.warning("%s; depth frames are ray-cast", exc)
            return "raycast"
        return gl_in_effect() or "gl"

    def close(self) -> None:
        """Free the GL context (needed with OSMesa to avoid an error message at exit) and stop
        the ray-cast threads."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        self._stop_raycast_workers()

    @property
    def raycast_threads(self) -> int:
        """Threads of the ray-cast backend, the caller's included."""
        return self._raycast_threads

    @raycast_threads.setter
    def raycast_threads(self, n: int) -> None:
        n = max(1, int(n))
        if n != self._raycast_threads:  # pool size and per-thread MjData change
            self._stop_raycast_workers()
        self._raycast_threads = n

    def _stop_raycast_workers(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
        self._ray_scenes.clear()

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

    def _clean_images_gl(self, want_geoms: bool) -> tuple[np.ndarray, np.ndarray | None,
                                                          np.ndarray | None]:
        """Clean depth and (when ``rgb`` is on) colour from one render pass; with
        ``want_geoms`` also the geom per pixel of the same scene (MuJoCo's segmentation
        pass), -1 for anything else (background, non-geom decor)."""
        r = self._renderer
        assert r is not None
        r.update_scene(self.data, self.cam_id)
        z, rgb = r.render(rgb=self._rgb)
        return z, rgb, (r.segmentation() if want_geoms else None)

    def _clean_depth_raycast(self, T_world_camera: np.ndarray,
                             hits: _RayHits | None = None) -> np.ndarray:
        """Depth along the optical axis per pixel by ray casting, exactly as one
        ``mj_multiRay`` over all visible geoms of the scene model would give it
        (:meth:`_clean_depth_raycast_plain`), but 3-4x faster on one thread:

        * the image is cut into tiles of :data:`RAYCAST_TILE_PX`; a geom is culled from a
          tile when its oriented local bounding box lies entirely outside one plane of the
          tile's frustum (the pyramid of that tile's pixel-centre rays, widened by
          :data:`_CULL_MARGIN_RAD`) or behind the camera — no ray of the tile can reach it;
          planes are never culled;
        * each tile is cast against a :class:`_RayScene` holding only its geoms, so a ray
          pays for neither the scene model's bodies nor the culled geoms (removing a geom no
          ray can hit changes no distance: each geom's distance is computed independently and
          the nearest is kept);
        * tiles are shared out to :attr:`raycast_threads` threads (``mj_multiRay`` releases
          the GIL; each thread has its own ``MjData`` since ``mj_multiRay`` allocates on its
          stack).

        Each ray's direction, the cutoff and the final division are computed with the same
        float operations as in the plain ray cast, so the depths are bit-identical. The scene
        model and its data are only read. Models with a visible mesh / hfield / SDF geom or a
        flex take the plain path. ``hits``, when given, receives each pixel's hit geom (and
        shading).
        """
        cand = self._raycast_candidates()
        if cand is None:
            return self._clean_depth_raycast_plain(T_world_camera, hits)
        h, w = self.config.height_px, self.config.width_px
        z = np.empty((h, w), dtype=np.float32)
        scenes = self._tile_scenes(self._tile_geoms(T_world_camera, cand))
        pnt = T_world_camera[:3, 3].copy()
        R32 = T_world_camera[:3, :3].astype(np.float32)
        cutoff = float(self.config.max_range_m) * float(self._ray_norm.max())
        n_tiles = len(self._tiles)
        next_tile = itertools.count().__next__
        lock = threading.Lock()

        def work(worker: int) -> None:  # takes tiles until none is left
            while True:
                with lock:
                    t = next_tile()
                if t >= n_tiles:
                    return
                self._cast_tile(worker, self._tiles[t], scenes[t], R32, pnt, cutoff, z, hits)

        n_workers = min(self.raycast_threads, n_tiles)
        if n_workers <= 1:
            work(0)
            return z
        if self._pool is None:
            self._pool = ThreadPoolExecutor(max_workers=self.raycast_threads - 1,
                                            thread_name_prefix="depth-raycast")
        futures = [self._pool.submit(work, i) for i in range(1, n_workers)]
        try:
            work(0)
        finally:
            for f in futures:
                f.result()
        return z

    def _cast_tile(self, worker: int, tile: tuple[int, int, int, int],
                   scene: "_RayScene | None", R32: np.ndarray, pnt: np.ndarray, cutoff: float,
                   z: np.ndarray, hits: _RayHits | None = None) -> None:
        r0, r1, c0, c1 = tile
        norm = self._ray_norm[r0:r1, c0:c1]
        if scene is None:  # nothing the tile can see (hits are preset to "none")
            z[r0:r1, c0:c1] = np.inf
            return
        n = norm.size
        x, y = self._x[:, c0:c1], self._y[r0:r1]
        vec = np.empty(norm.shape + (3,), dtype=np.float64)
        for i in range(3):  # the per-element operations of _world_directions, then unit rays
            vec[..., i] = (R32[i, 0] * x + R32[i, 1] * y + R32[i, 2]) / norm
        data = scene.datas[worker]
        data.geom_xpos[:] = self.data.geom_xpos[scene.geoms]
        data.geom_xmat[:] = self.data.geom_xmat[scene.geoms]
        geomid = np.empty(n, dtype=np.int32)
        dist = np.empty(n, dtype=np.float64)
        normal = np.empty(3 * n, dtype=np.float64) if hits and hits.cos is not None else None
        mujoco.mj_multiRay(scene.model, data, pnt, vec.reshape(-1), None, 1, -1,
                           geomid, dist, normal, n, cutoff)
        dist[geomid < 0] = np.inf
        z[r0:r1, c0:c1] = dist.reshape(norm.shape) / norm
        if hits is not None:  # private-model geom index -> scene model geom id
            g = np.where(geomid >= 0, scene.geoms[np.maximum(geomid, 0)], -1)
            hits.geom[r0:r1, c0:c1] = g.reshape(norm.shape)
            if normal is not None:
                hits.cos[r0:r1, c0:c1] = _abs_cos(normal, vec, norm.shape)

    def _raycast_candidates(self) -> np.ndarray | None:
        """Geoms a ray can hit (visible group, not transparent), or None when the model needs
        the plain ray cast (a candidate that is not a primitive, or a flex)."""
        m = self.model
        if m.nflex > 0:
            return None
        vis = VISIBLE_GEOM_GROUPS[np.clip(m.geom_group, 0, len(VISIBLE_GEOM_GROUPS) - 1)] != 0
        alpha = m.geom_rgba[:, 3].copy()
        if m.nmat > 0:
            matid = m.geom_matid
            alpha = np.where(matid >= 0, m.mat_rgba[np.maximum(matid, 0), 3], alpha)
        cand = np.flatnonzero(vis & (alpha != 0))
        if not all(int(t) in _PRIMITIVE_GEOMS for t in m.geom_type[cand]):
            return None
        return cand

    def _tile_geoms(self, T_world_camera: np.ndarray, cand: np.ndarray) -> list[np.ndarray]:
        """Per tile of :attr:`_tiles`, the candidate geoms not provably outside its frustum."""
        m, d = self.model, self.data
        if len(cand) == 0:
            return [cand] * len(self._tiles)
        aabb = m.geom_aabb[cand]
        local = aabb[:, None, :3] + _BOX_CORNERS[None] * aabb[:, None, 3:]
        xmat = d.geom_xmat[cand].reshape(-1, 3, 3)
        world = np.einsum("gij,gkj->gki", xmat, local) + d.geom_xpos[cand][:, None, :]
        cam = (world - T_world_camera[:3, 3]) @ T_world_camera[:3, :3]  # (geom, corner, xyz)
        X, Y, Z = (cam[..., i, None] for i in range(3))  # (geom, corner, 1)
        eps, lin = _CULL_MARGIN_RAD, _CULL_MARGIN_M
        tiles = np.array(self._tiles)
        x_lo = self._x[0, tiles[:, 2]].astype(float) - eps
        x_hi = self._x[0, tiles[:, 3] - 1].astype(float) + eps
        y_lo = self._y[tiles[:, 0], 0].astype(float) - eps
        y_hi = self._y[tiles[:, 1] - 1, 0].astype(float) + eps
        out = ((Z < -lin).all(axis=1)  # (geom, tile)
               | (X - x_hi * Z > lin).all(axis=1) | (x_lo * Z - X > lin).all(axis=1)
               | (Y - y_hi * Z > lin).all(axis=1) | (y_lo * Z - Y > lin).all(axis=1))
        out &= (m.geom_type[cand] != mujoco.mjtGeom.mjGEOM_PLANE)[:, None]
        return [cand[~out[:, t]] for t in range(len(self._tiles))]

    def _tile_scenes(self, tile_geoms: list[np.ndarray]) -> list["_RayScene | None"]:
        """The (cached) private ray-cast model of each tile's geoms, synced to the scene."""
        scenes: list[_RayScene | None] = []
        synced: set[int] = set()
        for geoms in tile_geoms:
            if len(geoms) == 0:
                scenes.append(None)
                continue
            key = (geoms.tobytes(), self.model.geom_type[geoms].tobytes())
            scene = self._ray_scenes.get(key)
            if scene is None:
                scene = _RayScene(self.model, geoms, self.raycast_threads)
                self._ray_scenes[key] = scene
                if len(self._ray_scenes) > _RAY_SCENE_CACHE:
                    self._ray_scenes.popitem(last=False)
            else:
                self._ray_scenes.move_to_end(key)
                if id(scene) not in synced:
                    scene.sync(self.model)
            synced.add(id(scene))
            scenes.append(scene)
        return scenes

    def _clean_depth_raycast_plain(self, T_world_camera: np.ndarray,
                                   hits: _RayHits | None = None) -> np.ndarray:
        """One ``mj_multiRay`` over all visible geoms of the scene model, on this thread
        (``hits``: as in :meth:`_clean_depth_raycast`)."""
        h, w = self.config.height_px, self.config.width_px
        n = h * w
        vec = np.empty((h, w, 3), dtype=np.float64)
        for i, d in enumerate(self._world_directions(T_world_camera[:3, :3])):
            vec[..., i] = d / self._ray_norm  # unit rays
        geomid = np.empty(n, dtype=np.int32)
        dist = np.empty(n, dtype=np.float64)
        normal = np.empty(3 * n, dtype=np.float64) if hits and hits.cos is not None else None
        mujoco.mj_multiRay(self.model, self.data, T_world_camera[:3, 3].copy(), vec.reshape(-1),
                           VISIBLE_GEOM_GROUPS, 1, -1, geomid, dist, normal, n,
                           float(self.config.max_range_m) * float(self._ray_norm.max()))
        dist[geomid < 0] = np.inf
        if hits is not None:
            hits.geom[:] = geomid.reshape(h, w)
            if normal is not None:
                hits.cos[:] = _abs_cos(normal, vec, (h, w))
        return (dist.reshape(h, w) / self._ray_norm).astype(np.float32)

    # ------------------------------------------------------------------ ray-cast colour
    def _geom_colours(self) -> np.ndarray:
        """(ngeom + 1, 3) float32 colour of each geom as the renderer shows it (a geom with a
        material and MuJoCo's default colour takes the material's, times the mean texel of its
        texture); the extra last row, black, is "no hit" (geom id -1)."""
        m = self.model
        col = np.zeros((m.ngeom + 1, 3), dtype=np.float32)
        col[:-1] = m.geom_rgba[:, :3]
        if m.nmat > 0:
            if self._mat_texel is None:
                self._mat_texel = _mean_texels(m)
            use = (m.geom_matid >= 0) & np.all(m.geom_rgba == _DEFAULT_GEOM_RGBA, axis=1)
            mat = m.geom_matid[use]
            col[:-1][use] = m.mat_rgba[mat, :3] * self._mat_texel[mat]
        return col

    def _rgb_raycast(self, hits: _RayHits) -> np.ndarray:
        """(H, W, 3) uint8 colour from the hit geoms, Lambert-shaded; black where no hit."""
        assert hits.cos is not None
        shade = hits.cos * np.float32(255.0 * (1.0 - RGB_AMBIENT))
        shade += np.float32(255.0 * RGB_AMBIENT)
        # geom -1 wraps to the black last row (np.take is ~2x faster than fancy indexing here)
        rgb = np.take(self._geom_colours(), hits.geom, axis=0, mode="wrap")
        rgb *= shade[..., None]
        return rgb.astype(np.uint8)  # <= 255 by construction (colours and |cos| <= 1)

    def _world_directions(self, R: np.ndarray) -> list[np.ndarray]:
        """Per pixel, the world direction of the camera-frame vector (x, y, 1), as three
        (H, W) float32 arrays. (Written out per component: a float32 ``(N, 3) @ (3, 3)``
        matmul is an order of magnitude slower with some BLAS builds.)"""
        R32 = R.astype(np.float32)
        return [R32[i, 0] * self._x + R32[i, 1] * self._y + R32[i, 2] for i in range(3)]

    def _with_noise(self, z: np.ndarray) -> np.ndarray:
        """``z`` (H, W) float32 plus the sensor's noise: a normal draw per pixel (all of them,
        in order) times ``sigma (z / ref) ** exponent``. The draws are the C++ core's stream
        (``_core.fill_standard_normal``) of a seed taken per frame from the camera's generator
        (``camera.seed``): the same frames for the same seed, a few times cheaper than numpy's."""
        noise = self.depth_noise
        out = np.empty(z.shape, dtype=np.float32)
        _core.fill_standard_normal(out, int(self._rng.bit_generator.random_raw()))
        if float(noise.depth_noise_exponent) == 2.0:  # the quadratic law: one fused C++ pass
            _core.add_quadratic_depth_noise(z, out, float(np.float32(noise.depth_noise_ref_range_m)),
                                            float(np.float32(noise.depth_noise_sigma_m)))
            return out
        sigma = z / np.float32(noise.depth_noise_ref_range_m)
        sigma **= np.float32(noise.depth_noise_exponent)
        sigma *= np.float32(noise.depth_noise_sigma_m)
        out *= sigma
        out += z
        return out

    # ------------------------------------------------------------------ capture
    def _clean_images(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray | None,
                                                      np.ndarray | None]:
        """Clean depth, colour (None when off) and per-pixel geom ids (None unless labels are
        on) of the camera at pose ``T``, all of the same instant."""
        want_geoms = self._eval_labels
        if self.backend == "raycast":
            hits = _RayHits(*self._ray_norm.shape, shade=self._rgb) \
                if (self._rgb or want_geoms) else None
            z = self._clean_depth_raycast(T, hits)
            rgb = self._rgb_raycast(hits) if self._rgb else None
            geoms = hits.geom if want_geoms else None
        else:
            z, rgb, geoms = self._clean_images_gl(want_geoms)
        return z, rgb, geoms

    def _render_clean(self) -> CleanImages:
        """Render the scene now: clean depth with the invalid (out of range) pixels and the
        grazing ones masked, colour, labels, and the camera pose."""
        cfg = self.config
        T = self.pose()
        z, rgb, geoms = self._clean_images(T)
        invalid = ~((z >= cfg.min_range_m) & (z <= cfg.max_range_m))
        # NaN where invalid, then the grazing mask (in place: z is this render's own array)
        _core.mask_invalid_and_grazing(z, invalid, self._x_row, self._y_col, self._ray_norm2,
                                       float(self._fx), float(self._fy),
                                       float(self._cos_grazing**2))
        return CleanImages(T, z, invalid, rgb, geoms)

    def _clean_for_frame(self) -> CleanImages:
        """This frame's clean images: the kept render while nothing moved (``still``), else a
        new render; kept images are handed out as copies where a frame could change them."""
        still = self._still
        if not still.enabled:
            return self._render_clean()
        key = still.scene_key(self.data, self.cam_id, (self._eval_labels, self._rgb))
        kept = still.lookup(key)
        if kept is None:
            kept = self._render_clean()
            still.keep(key, kept)
        return CleanImages(kept.T_world_camera, kept.depth if self.config.add_noise else kept.depth.copy(),
                           kept.invalid, None if kept.rgb is None else kept.rgb.copy(),
                           None if kept.geoms is None else kept.geoms.copy())

    def capture(self) -> Frame:
        """One frame (depth, points and, unless ``rgb`` is off, colour) of the state currently
        in ``data`` (kinematics must be up to date): a new render, or the last one while
        nothing in view moved (:mod:`.still_scene`), with this frame's own noise. With labels
        on, the per-pixel geom ids of this frame replace those of the previous one (evaluation
        code reads them through the ground-truth module)."""
        clean = self._clean_for_frame()
        T, z, geoms = clean.T_world_camera, clean.depth, clean.geoms
        if self.config.add_noise:
            z = self._with_noise(z)  # a new array: the clean depth is left as it is
        pts_world = _core.depth_to_world_points(  # NaN where invalid, then the points
            z, clean.invalid, self._x_row, self._y_col,
            np.ascontiguousarray(T[:3, :3], dtype=np.float32), T[:3, 3].astype(np.float32))
        frame = Frame(points_world=pts_world, depth=z, time_s=float(self.data.time),
                      T_world_camera=T.copy(), K=self.K.copy(), backend=self.backend,
                      index=self._frame_index, rgb=clean.rgb)
        if geoms is not None:
            geoms[np.isnan(z)] = -1  # labels only where the frame has a point
        self._eval_geoms = geoms
        self._eval_frame_key = (frame.index, frame.time_s, T.tobytes())
        self._frame_index += 1
        return frame


def _abs_cos(normal: np.ndarray, vec: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """``|n . r|`` per ray from ``mj_multiRay``'s flat normals and unit rays, as float32."""
    n, r = normal.reshape(-1, 3), vec.reshape(-1, 3)
    c = n[:, 0] * r[:, 0]
    c += n[:, 1] * r[:, 1]
    c += n[:, 2] * r[:, 2]
    np.abs(c, out=c)
    np.minimum(c, 1.0, out=c)
    return c.astype(np.float32).reshape(shape)


def _mean_texels(model: mujoco.MjModel) -> np.ndarray:
    """(nmat, 3) float32: the mean texel (0..1) of each material's colour texture, 1 without
    one (a ray cast samples no texture; the mean keeps e.g. a checker floor grey, not white)."""
    col = np.ones((model.nmat, 3), dtype=np.float32)
    role = int(mujoco.mjtTextureRole.mjTEXROLE_RGB)
    texid = model.mat_texid[:, role] if model.mat_texid.ndim == 2 else model.mat_texid
    for mat in np.flatnonzero(texid >= 0):
        t = int(texid[mat])
        nch = int(model.tex_nchannel[t])
        n = int(model.tex_width[t]) * int(model.tex_height[t]) * nch
        texels = model.tex_data[model.tex_adr[t]:model.tex_adr[t] + n].reshape(-1, nch)
        if nch >= 3:
            col[mat] *= texels[:, :3].mean(axis=0) / 255.0
    return col
