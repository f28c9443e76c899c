"""Synthetic depth frames of a tabletop, ray-cast analytically with numpy.

Used by ``make demo`` before the simulator is wired in, by the perception
benchmark and by tests: a pin-hole depth camera (OpenCV convention: x right,
y down, z along the optical axis) looks at a scene of a floor, a table top, a
wall and a few objects (boxes with a yaw, upright cylinders). Every pixel's ray
is intersected with every primitive; the nearest hit gives the point, Gaussian
noise is added along the ray (σ in metres at the hit depth) and rays that hit
nothing become NaN — exactly the organized cloud a real sensor delivers.

This is not the simulator; it exists so perception can be exercised and timed
in isolation, with a known ground truth, in a few milliseconds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Box:
    """An axis-aligned-in-yaw box resting with its bottom at ``base_z_m``."""

    center_xy: tuple[float, float]
    size_m: tuple[float, float, float]  # (x-size, y-size, height) before the yaw
    yaw_deg: float = 0.0
    base_z_m: float = 0.2


@dataclass(frozen=True)
class Cylinder:
    """An upright cylinder resting with its bottom at ``base_z_m``."""

    center_xy: tuple[float, float]
    diameter_m: float
    height_m: float
    base_z_m: float = 0.2


@dataclass(frozen=True)
class Tabletop:
    """A floor (z = 0), a rectangular table top, an optional wall and objects."""

    table_height_m: float = 0.2
    table_x_m: tuple[float, float] = (0.25, 0.95)
    table_y_m: tuple[float, float] = (-0.45, 0.45)
    wall_x_m: float | None = 1.3
    objects: tuple = field(default_factory=tuple)


@dataclass(frozen=True)
class PinholeCamera:
    """Intrinsics of a pin-hole depth camera."""

    width_px: int = 640
    height_px: int = 480
    vfov_deg: float = 58.0
    max_range_m: float = 4.0

    def ray_directions(self) -> np.ndarray:
        """Unit ray directions in the camera frame, (H*W, 3), row-major pixel order."""
        f = (self.height_px / 2.0) / np.tan(np.radians(self.vfov_deg) / 2.0)
        u = np.arange(self.width_px) - (self.width_px - 1) / 2.0
        v = np.arange(self.height_px) - (self.height_px - 1) / 2.0
        uu, vv = np.meshgrid(u, v)
        d = np.stack([uu / f, vv / f, np.ones_like(uu)], axis=-1).reshape(-1, 3)
        return d / np.linalg.norm(d, axis=1, keepdims=True)


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray = np.array([0.0, 0.0, 1.0])) -> np.ndarray:
    """World pose (4×4) of a camera at ``eye`` looking at ``target`` (OpenCV axes)."""
    eye = np.asarray(eye, float)
    z = np.asarray(target, float) - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    if np.linalg.norm(x) < 1e-9:  # looking straight down: pick world -y as image x
        x = np.array([0.0, -1.0, 0.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, y, z])
    T[:3, 3] = eye
    return T


def _hit_plane_z(o, d, z):
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (z - o[2]) / d[:, 2]
    return np.where(np.isfinite(t) & (t > 0), t, np.inf)


def _hit_box(o, d, box: Box):
    yaw = np.radians(box.yaw_deg)
    c, s = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    center = np.array([box.center_xy[0], box.center_xy[1], box.base_z_m + box.size_m[2] / 2.0])
    half = np.asarray(box.size_m) / 2.0
    ol = R.T @ (o - center)
    dl = d @ R  # rows: R^T d
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (-half - ol) / dl
        t2 = (half - ol) / dl
    tmin = np.nanmax(np.minimum(t1, t2), axis=1)
    tmax = np.nanmin(np.maximum(t1, t2), axis=1)
    hit = (tmax >= tmin) & (tmax > 0)
    return np.where(hit, np.where(tmin > 0, tmin, np.inf), np.inf)


def _hit_cylinder(o, d, cyl: Cylinder):
    r = cyl.diameter_m / 2.0
    z0, z1 = cyl.base_z_m, cyl.base_z_m + cyl.height_m
    ox, oy = o[0] - cyl.center_xy[0], o[1] - cyl.center_xy[1]
    a = d[:, 0] ** 2 + d[:, 1] ** 2
    b = 2 * (ox * d[:, 0] + oy * d[:, 1])
    cc = ox**2 + oy**2 - r**2
    disc = b**2 - 4 * a * cc
    with np.errstate(divide="ignore", invalid="ignore"):
        t_side = (-b - np.sqrt(np.maximum(disc, 0))) / (2 * a)
    z_side = o[2] + t_side * d[:, 2]
    side_ok = (disc >= 0) & (t_side > 0) & (z_side >= z0) & (z_side <= z1)
    t_top = _hit_plane_z(o, d, z1)
    px = ox + t_top * d[:, 0]
    py = oy + t_top * d[:, 1]
    top_ok = np.isfinite(t_top) & (px**2 + py**2 <= r**2)
    return np.minimum(np.where(side_ok, t_side, np.inf), np.where(top_ok, t_top, np.inf))


def render_depth(
    scene: Tabletop,
    T_world_camera: np.ndarray,
    camera: PinholeCamera = PinholeCamera(),
    noise_sigma_m: float = 0.002,
    rng: np.random.Generator | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Ray-cast the scene.

    Returns ``(points_world, points_camera)``, both (H*W, 3) float32 organized in
    row-major pixel order, NaN where a ray hits nothing within ``max_range_m``.
    """
    rng = rng if rng is not None else np.random.default_rng(0)
    d_cam = camera.ray_directions()
    R, o = T_world_camera[:3, :3], T_world_camera[:3, 3]
    d = d_cam @ R.T
    t = _hit_plane_z(o, d, 0.0)  # floor
    t_table = _hit_plane_z(o, d, scene.table_height_m)
    p = o + t_table[:, None] * d
    on_table = (
        (p[:, 0] >= scene.table_x_m[0]) & (p[:, 0] <= scene.table_x_m[1])
        & (p[:, 1] >= scene.table_y_m[0]) & (p[:, 1] <= scene.table_y_m[1])
    )
    t = np.minimum(t, np.where(on_table, t_table, np.inf))
    if scene.wall_x_m is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            tw = (scene.wall_x_m - o[0]) / d[:, 0]
        t = np.minimum(t, np.where(np.isfinite(tw) & (tw > 0), tw, np.inf))
    for obj in scene.objects:
        t = np.minimum(t, _hit_box(o, d, obj) if isinstance(obj, Box) else _hit_cylinder(o, d, obj))
    valid = np.isfinite(t) & (t <= camera.max_range_m)
    depth = np.where(valid, t * d_cam[:, 2], np.nan)  # z-depth along the optical axis
    depth = depth + rng.normal(0.0, noise_sigma_m, depth.shape)
    pts_cam = d_cam / d_cam[:, 2:3] * depth[:, None]
    pts_world = pts_cam @ R.T + o
    return pts_world.astype(np.float32), pts_cam.astype(np.float32)


def reference_tabletop() -> Tabletop:
    """method.md §8's reference arrangement: blue cube, red cube, green cylinder on a 0.2 m table."""
    return Tabletop(
        objects=(
            Box(center_xy=(0.56, -0.03), size_m=(0.05, 0.05, 0.05), yaw_deg=20.0),
            Box(center_xy=(0.46, -0.10), size_m=(0.05, 0.05, 0.05), yaw_deg=-10.0),
            Cylinder(center_xy=(0.52, 0.09), diameter_m=0.05, height_m=0.06),
        )
    )


def reference_camera_pose() -> np.ndarray:
    """An oblique start view of the reference table from ≈0.45 m."""
    return look_at(eye=np.array([0.22, 0.0, 0.56]), target=np.array([0.52, 0.0, 0.2]))


def tabletop_frame(seed: int = 0, noise_sigma_m: float = 0.002) -> tuple[np.ndarray, np.ndarray]:
    """The reference synthetic frame: ``(points_world (307200, 3) float32, T_world_camera)``."""
    T = reference_camera_pose()
    pts, _ = render_depth(reference_tabletop(), T, noise_sigma_m=noise_sigma_m,
                          rng=np.random.default_rng(seed))
    return pts, T
