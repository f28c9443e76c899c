"""Depth images of boxes on a table, ray-cast with numpy (tests only)."""

from __future__ import annotations

import numpy as np

WIDTH_PX, HEIGHT_PX = 160, 120
#: A 160 x 120 pinhole camera with the field of view of the simulated one (58 deg vertical).
K = np.array([[108.0, 0.0, 79.5], [0.0, 108.0, 59.5], [0.0, 0.0, 1.0]])


def look_at(eye, target, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Optical frame (x right, y down, z forward) at ``eye`` looking at ``target``."""
    z = np.asarray(target, float) - np.asarray(eye, float)
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    if np.linalg.norm(x) < 1e-9:
        x = np.cross(z, [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, eye
    return T


def render(T: np.ndarray, boxes=(), table_z: float | None = None, K: np.ndarray = K,
           size=(WIDTH_PX, HEIGHT_PX)) -> np.ndarray:
    """(H, W) float32 depth along the optical axis of axis-aligned ``boxes`` ((lo, hi) each)
    and the plane z = ``table_z``; NaN where a ray hits nothing."""
    w, h = size
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    d_cam = np.stack([(u - K[0, 2]) / K[0, 0], (v - K[1, 2]) / K[1, 1], np.ones_like(u, float)], -1)
    d = d_cam.reshape(-1, 3) @ T[:3, :3].T  # world directions, t = depth
    o = T[:3, 3]
    t = np.full(len(d), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for lo, hi in boxes:
            ta, tb = (np.asarray(lo) - o) / d, (np.asarray(hi) - o) / d
            t0 = np.nanmax(np.minimum(ta, tb), axis=1)
            t1 = np.nanmin(np.maximum(ta, tb), axis=1)
            hit = (t0 <= t1) & (t1 > 0)
            t = np.where(hit, np.minimum(t, np.maximum(t0, 0.0)), t)
        if table_z is not None:
            tt = (table_z - o[2]) / d[:, 2]
            t = np.where((tt > 0) & np.isfinite(tt), np.minimum(t, tt), t)
    t[~np.isfinite(t)] = np.nan
    return t.reshape(h, w).astype(np.float32)
