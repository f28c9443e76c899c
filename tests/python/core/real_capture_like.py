"""A real-capture-like synthetic cloud: a floor seen 3 m deep by a camera 0.8 m
above it, a few real objects near the camera and, 1.6-2.1 m away, patches where the depth
noise is spatially correlated and lifts the floor by 11-13 mm (what a real capture reported
as 7 graspable "objects"). On top, independent per-point noise along the ray growing with the
square of the range (0.5 mm at 0.4 m: a quarter of the perception's default noise model,
``scene_filter.depth_noise_sigma_m`` = 2 mm, whose rest is the correlated part)."""

from __future__ import annotations

import numpy as np

CAMERA = np.array([0.0, 0.0, 0.8])
NEAR_BOXES = [((0.55, -0.10), (0.06, 0.05, 0.05)), ((0.60, 0.12), (0.05, 0.07, 0.08))]
FAR_PATCH_CENTRES = [(1.6, -0.5), (1.8, 0.3), (2.0, -0.2), (1.9, 0.7), (2.1, 0.1)]


def floor_capture(seed: int = 0, spacing_m: float = 0.004) -> np.ndarray:
    """(N, 3) float32 world points (z up, the floor at z = 0)."""
    rng = np.random.default_rng(seed)
    g = np.arange(0.25, 2.4, spacing_m)
    xx, yy = np.meshgrid(g, np.arange(-1.0, 1.0, spacing_m))
    floor = np.c_[xx.ravel(), yy.ravel(), np.zeros(xx.size)]
    for (cx, cy) in FAR_PATCH_CENTRES:  # correlated noise: a 12 mm bump, 10 cm across
        inside = (np.abs(floor[:, 0] - cx) < 0.05) & (np.abs(floor[:, 1] - cy) < 0.05)
        floor[inside, 2] += rng.uniform(0.011, 0.013)
    parts = [floor]
    for (cx, cy), (sx, sy, h) in NEAR_BOXES:
        a, b = np.meshgrid(np.arange(cx - sx / 2, cx + sx / 2, 0.002),
                           np.arange(cy - sy / 2, cy + sy / 2, 0.002))
        parts.append(np.c_[a.ravel(), b.ravel(), np.full(a.size, h)])
        inside = (np.abs(floor[:, 0] - cx) < sx / 2) & (np.abs(floor[:, 1] - cy) < sy / 2)
        floor[inside, 2] = np.nan  # hidden under the box
    pts = np.vstack(parts)
    pts = pts[np.isfinite(pts[:, 2])]
    ray = pts - CAMERA
    r = np.linalg.norm(ray, axis=1)
    sigma = 0.0005 * (r / 0.4) ** 2
    pts = pts + ray / r[:, None] * rng.normal(0.0, 1.0, len(r))[:, None] * sigma[:, None]
    return pts.astype(np.float32)
