"""The camera frame contract, checked on every frame that enters the pipeline from a robot.

A frame (:class:`~.frame.Frame`) must carry

* ``depth``: an (H, W) float image in **metres** along the optical axis, NaN where there is no
  return (a raw sensor image — uint16 millimetres — is refused, and so is a float image whose
  values are typical of millimetres);
* ``K``: the 3x3 pinhole intrinsics of that image (fx, fy > 0, no skew, last row (0, 0, 1),
  principal point near the image centre — intrinsics of another resolution are refused);
* ``T_world_camera``: the pose of the optical frame (z forward, x right, y down) **at
  capture**, a rigid 4x4 transform;
* ``points_world``: (H*W, 3), organized like ``depth`` and agreeing with it and the pose;
* ``rgb``: None, or (H, W, 3) uint8 aligned with the depth.

:func:`check_frame` raises :class:`~grasp_pipeline.exceptions.CameraFrameError` with one line
that says what to fix. It reads a strided sample of the pixels (about two thousand of a 640x480
frame), so it costs a few tenths of a millisecond and runs on every frame.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from ..exceptions import CameraFrameError

#: A wrist camera sees no farther than a few metres: a larger median is not metres [m].
MAX_MEDIAN_DEPTH_M = 10.0
#: Every this many rows and columns one pixel is sampled for the value checks.
SAMPLE_STRIDE_PX = 12
#: Largest deviation of the pose's rotation from orthonormal (float32 poses pass).
ROTATION_TOL = 1e-4
#: The principal point must lie within this fraction of the image size from its centre.
PRINCIPAL_POINT_TOL = 0.25
#: Largest median disagreement of ``points_world`` with depth, intrinsics and pose [m].
POINTS_TOL_M = 0.01

_HOW = "see docs/real_robot.md"


def check_frame(frame: Any) -> Any:
    """Raise :class:`CameraFrameError` when ``frame`` breaks the contract; else return it."""
    depth = checked_depth(getattr(frame, "depth", None))
    h, w = depth.shape
    K = checked_intrinsics(getattr(frame, "K", None), w, h)
    T = checked_pose(getattr(frame, "T_world_camera", None))
    checked_time(getattr(frame, "time_s", None))
    _check_rgb(getattr(frame, "rgb", None), h, w)
    rows, cols, flat = _sample_pixels(h, w)
    z = depth[rows, cols].astype(np.float64)
    _check_depth_values(z)
    _check_points(getattr(frame, "points_world", None), h, w, rows, cols, flat, z, K, T)
    return frame


@lru_cache(maxsize=8)
def _sample_pixels(h: int, w: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sampled pixels of an ``h`` x ``w`` image (every ``SAMPLE_STRIDE_PX`` rows and
    columns, row by row): their rows, columns and flat indices (read-only, shared)."""
    rows, cols = np.mgrid[0:h:SAMPLE_STRIDE_PX, 0:w:SAMPLE_STRIDE_PX]
    out = (rows.ravel(), cols.ravel(), (rows * w + cols).ravel())
    for a in out:
        a.flags.writeable = False
    return out


def _all_close(values: np.ndarray, expected: tuple[float, ...]) -> bool:
    """``np.allclose(values, expected)`` of a few finite floats (its default tolerances, the
    same comparisons), without its array machinery."""
    return all(abs(a - b) <= 1e-8 + 1e-5 * abs(b) for a, b in zip(values.tolist(), expected))


def checked_depth(depth: Any) -> np.ndarray:
    """``depth`` if it is an (H, W) float image, else :class:`CameraFrameError`."""
    if depth is None:
        raise CameraFrameError("the camera frame has no depth image: deliver an (H, W) float32 depth "
                               f"in metres, NaN where there is no return ({_HOW})")
    if not isinstance(depth, np.ndarray) or depth.ndim != 2 or min(depth.shape) < 1:
        shape = getattr(depth, "shape", type(depth).__name__)
        raise CameraFrameError(f"the camera frame's depth must be an (H, W) image, got {shape} ({_HOW})")
    if not np.issubdtype(depth.dtype, np.floating):
        raise CameraFrameError(
            f"the camera frame's depth is {depth.dtype} (raw sensor units, millimetres?): convert it to "
            "float32 metres (depth * depth scale; pyrealsense2: depth_sensor.get_depth_scale()) with "
            f"NaN where the sensor gave 0 ({_HOW})")
    return depth


def _check_depth_values(z: np.ndarray) -> None:
    finite = z[np.isfinite(z)]
    if finite.size and float(finite.min()) <= 0.0:
        raise CameraFrameError("the camera frame's depth has values <= 0: mark pixels without a return "
                               f"NaN (Frame.from_depth does) ({_HOW})")
    # (the median is at most the largest value: no median unless that is too large)
    if finite.size and float(finite.max()) > MAX_MEDIAN_DEPTH_M and float(np.median(finite)) > MAX_MEDIAN_DEPTH_M:
        raise CameraFrameError(
            f"the camera frame's depth has a median of {float(np.median(finite)):.0f} — millimetres? "
            "The pipeline needs metres: multiply the raw depth by the sensor's depth scale "
            f"(e.g. 0.001) ({_HOW})")


def checked_intrinsics(K: Any, w: int, h: int) -> np.ndarray:
    """``K`` as a (3, 3) float array if it is sane for a ``w`` x ``h`` image, else
    :class:`CameraFrameError`."""
    if K is None:
        raise CameraFrameError("the camera frame has no intrinsics K: pass the 3x3 pinhole matrix of the "
                               "depth image (pyrealsense2: the stream profile's get_intrinsics(); "
                               f"fx, fy, ppx, ppy) ({_HOW})")
    K = np.asarray(K, dtype=float)
    if K.shape != (3, 3) or not np.all(np.isfinite(K)):
        raise CameraFrameError(f"the camera frame's intrinsics K must be a finite 3x3 matrix, got shape "
                               f"{K.shape} ({_HOW})")
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    if not (fx > 0 and fy > 0 and K[0, 1] == 0 and K[1, 0] == 0 and _all_close(K[2], (0.0, 0.0, 1.0))):
        raise CameraFrameError("the camera frame's intrinsics K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] "
                               f"with fx, fy > 0 [px], got {np.round(K, 3).tolist()} ({_HOW})")
    if abs(cx - 0.5 * (w - 1)) > PRINCIPAL_POINT_TOL * w or abs(cy - 0.5 * (h - 1)) > PRINCIPAL_POINT_TOL * h:
        raise CameraFrameError(
            f"the intrinsics' principal point ({cx:.0f}, {cy:.0f}) px is far from the centre of the "
            f"{w}x{h} depth image: K belongs to another resolution or stream (take the intrinsics of the "
            f"stream the depth is aligned to) ({_HOW})")
    return K


def checked_pose(T: Any, what: str = "the camera frame's pose T_world_camera") -> np.ndarray:
    """``T`` as a (4, 4) float array, or :class:`CameraFrameError` unless it is a rigid transform."""
    if T is None:
        raise CameraFrameError(
            f"{what} is missing: set it to the arm's flange pose at capture times the hand-eye "
            f"calibration (FK(q at capture) @ flange_T_camera) ({_HOW})")
    T = np.asarray(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise CameraFrameError(f"{what} must be a finite 4x4 transform, got shape {T.shape} ({_HOW})")
    if not _all_close(T[3], (0.0, 0.0, 0.0, 1.0)):
        raise CameraFrameError(f"{what} must be a 4x4 homogeneous transform with last row (0, 0, 0, 1), "
                               f"got {np.round(T[3], 4).tolist()} ({_HOW})")
    R = T[:3, :3]
    err = float(np.max(np.abs(R.T @ R - np.eye(3))))
    if err > ROTATION_TOL or np.linalg.det(R) < 0:
        raise CameraFrameError(
            f"{what} is not a rigid transform (rotation off orthonormal by {err:.1e}, det "
            f"{np.linalg.det(R):.3f}): pass a proper rotation, in metres ({_HOW})")
    return T


def checked_time(time_s: Any) -> float:
    """``time_s`` as a float if it is a finite number, else :class:`CameraFrameError`."""
    try:
        t = float(time_s)
    except (TypeError, ValueError):
        t = float("nan")
    if not np.isfinite(t):
        raise CameraFrameError(f"the camera frame's time_s must be a finite number of seconds on the "
                               f"robot's clock, got {time_s!r} ({_HOW})")
    return t


def _check_rgb(rgb: Any, h: int, w: int) -> None:
    if rgb is None:
        return
    shape = getattr(rgb, "shape", None)
    if shape != (h, w, 3) or getattr(rgb, "dtype", None) != np.uint8:
        raise CameraFrameError(
            f"the camera frame's colour image is {shape} {getattr(rgb, 'dtype', type(rgb).__name__)} but "
            f"the depth is {h}x{w}: deliver (H, W, 3) uint8 aligned to the depth pixel for pixel "
            f"(pyrealsense2: rs.align), or rgb=None ({_HOW})")


def _check_points(points: Any, h: int, w: int, rows: np.ndarray, cols: np.ndarray, flat: np.ndarray,
                  z: np.ndarray, K: np.ndarray, T: np.ndarray) -> None:
    """``points_world`` is (H*W, 3), organized like the depth, and agrees with it: the sampled
    pixels' points lie where depth, intrinsics and pose put them."""
    if getattr(points, "shape", None) != (h * w, 3):
        raise CameraFrameError(
            f"the camera frame's points_world must be ({h * w}, 3), organized like the {w}x{h} depth, got "
            f"{getattr(points, 'shape', type(points).__name__)}: build the frame with Frame.from_depth ({_HOW})")
    p = np.asarray(points[flat], dtype=np.float64)
    ok = np.isfinite(z) & np.isfinite(p[:, 0])
    if not np.any(ok):
        return
    zc = z[ok]
    cam = np.c_[(cols[ok] - K[0, 2]) / K[0, 0] * zc, (rows[ok] - K[1, 2]) / K[1, 1] * zc, zc]
    expected = cam @ T[:3, :3].T + T[:3, 3]
    errs = np.linalg.norm(p[ok] - expected, axis=1)
    # (the median is at most the largest error: no median unless that is too large)
    err = float(errs.max())
    if err > POINTS_TOL_M:
        err = float(np.median(errs))
    if err > POINTS_TOL_M:
        raise CameraFrameError(
            f"the camera frame's points_world disagree with its depth, K and T_world_camera (median "
            f"{err * 1e3:.0f} mm off): back-project the depth with the pose at capture — Frame.from_depth "
            f"does ({_HOW})")
