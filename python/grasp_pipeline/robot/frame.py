"""One RGB-D frame of the eye-in-hand camera, as perception receives it.

A robot adapter builds its frames with :meth:`Frame.from_depth` (depth in metres, intrinsics,
the camera pose at capture); every frame is checked against the contract of
:mod:`.frame_contract` where it enters the pipeline.
"""

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
        time_s: time of the capture on the robot's clock [s] (simulated time in the simulator).
        T_world_camera: (4, 4) float64 pose of the camera *optical* frame (z forward, x right,
            y down) at the instant of capture — never a later pose.
        K: (3, 3) float64 pinhole intrinsics (fx, fy, cx, cy in pixels; pixel centres at
            integer coordinates): ``u = fx x/z + cx``, ``v = fy y/z + cy``.
        backend: which renderer produced it: ``"egl"``, ``"osmesa"`` (GL) or ``"raycast"``;
            a real camera's adapter names its sensor (e.g. ``"realsense"``).
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

    @classmethod
    def from_depth(cls, depth_m: np.ndarray, K: np.ndarray, T_world_camera: np.ndarray, time_s: float,
                   rgb: np.ndarray | None = None, index: int = 0, backend: str = "camera") -> "Frame":
        """A frame from a depth image in metres: every pixel back-projected to world points
        (``p_cam = z ((u - cx)/fx, (v - cy)/fy, 1)``, then ``T_world_camera``); pixels without a
        return (NaN, or 0 as sensors report them) become NaN. Checked against the frame contract
        (:func:`~.frame_contract.check_frame`): raw integer depth, a missing pose or intrinsics
        of another resolution raise :class:`~grasp_pipeline.exceptions.CameraFrameError`."""
        from .frame_contract import check_frame, checked_depth, checked_intrinsics, checked_pose, checked_time

        depth = checked_depth(None if depth_m is None else np.asarray(depth_m))  # before converting
        K = checked_intrinsics(K, depth.shape[1], depth.shape[0])
        T = checked_pose(T_world_camera)
        t = checked_time(time_s)
        with np.errstate(invalid="ignore"):
            z = np.where(depth > 0, depth, np.nan).astype(np.float32)
        x = ((np.arange(z.shape[1]) - K[0, 2]) / K[0, 0]).astype(np.float32)[None, :]
        y = ((np.arange(z.shape[0]) - K[1, 2]) / K[1, 1]).astype(np.float32)[:, None]
        pts = np.empty(z.shape + (3,), dtype=np.float32)
        for i in range(3):  # world = R (x z, y z, z) + t, one coordinate at a time
            R = T[i, :3].astype(np.float32)
            pts[..., i] = (R[0] * x + R[1] * y + R[2]) * z + np.float32(T[i, 3])
        pts = pts.reshape(-1, 3)
        return check_frame(cls(points_world=pts, depth=z, time_s=t, T_world_camera=T.copy(), K=K.copy(),
                               backend=backend, index=int(index), rgb=rgb))

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

