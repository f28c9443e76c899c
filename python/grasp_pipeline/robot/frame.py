"""One RGB-D frame of the eye-in-hand camera, as perception receives it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Frame:
    """What one capture delivers.

    Attributes:
        points_world: (H*W, 3) float32 world points, **organized**: row ``v*W + u`` is pixel
            (u, v) of ``depth``; invalid pixels (no return, out of range, grazing) are NaN rows.
            Drop them with ``points_world[np.isfinite(points_world[:, 0])]``.
        depth: (H, W) float32 depth along the optical axis [m] (not the ray length), noise
            included; NaN where invalid. Row 0 is the top of the image.
        time_s: simulated time of the capture [s].
        T_world_camera: (4, 4) float64 pose of the camera *optical* frame (z forward, x right,
            y down) at the instant of capture — never a later pose.
        K: (3, 3) float64 pinhole intrinsics (fx, fy, cx, cy in pixels; pixel centres at
            integer coordinates): ``u = fx x/z + cx``, ``v = fy y/z + cy``.
        backend: which renderer produced it: ``"egl"``, ``"osmesa"`` (GL) or ``"raycast"``.
        index: running number of the frame from this camera (0, 1, ...).
        rgb: (H, W, 3) uint8 colour image from the same camera at the same instant, aligned
            pixel for pixel with ``depth`` (pixel (u, v) of both shows the same surface; it is
            not masked where the depth is NaN), or None when the camera delivers no colour.
    """

    points_world: np.ndarray
    depth: np.ndarray
    time_s: float
    T_world_camera: np.ndarray
    K: np.ndarray
    backend: str
    index: int = 0
    rgb: np.ndarray | None = None

    @property
    def height(self) -> int:
        return int(self.depth.shape[0])

    @property
    def width(self) -> int:
        return int(self.depth.shape[1])

    @property
    def camera_position(self) -> np.ndarray:
        """Camera centre in world at capture [m]."""
        return self.T_world_camera[:3, 3].copy()

    def valid_mask(self) -> np.ndarray:
        """(H*W,) bool: rows of ``points_world`` that are finite."""
        return np.isfinite(self.points_world[:, 0])

    def valid_points(self) -> np.ndarray:
        """The finite rows of ``points_world`` (M, 3) float32."""
        return self.points_world[self.valid_mask()]
