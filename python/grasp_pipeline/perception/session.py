"""One camera session of perception: the Python face of the C++ per-frame path.

``PerceptionSession.process(points, camera_position, time_s)`` makes exactly one call
into C++ per frame (scene filter → two-pass estimates → view quality → tracker),
forwards the core's events to :mod:`logging` and returns a :class:`FrameResult`
that gives numpy views of the object / environment points without copying the
labels. The locked plane and the band are latched: readable at any time, also by
a consumer that starts late.

Threads: one session may be shared by several threads. Every call into the core object
(``process``, ``reset``, and the reads behind ``plane``, ``plane_locked``, ``tracks()``,
``tracker``) is serialised by a mutex in the C++ binding; the GIL is released while a
call waits for that mutex and while a frame is processed, so other Python threads keep
running and no deadlock can occur. Frames from concurrent ``process`` calls are applied
one after the other, in the order the mutex is taken; ``time_s`` must still not go
backwards in that order (``ValueError`` otherwise), so a producer that wants a defined
frame order must keep one thread per camera.

Points with a NaN/Inf or a coordinate beyond ``max_abs_coordinate_m`` (scene filter
config) are dropped and labelled invalid; the frame's ``num_invalid`` counts both and
``num_out_of_range`` the latter.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .. import _core
from ..array_rows import rows_where
from ..robot.depth_noise import DepthNoiseConfig
from .config import ObbConfig, SceneFilterConfig
from .workspace import WorkspaceConfig

log = logging.getLogger("grasp_pipeline.perception")

_LEVELS = {
    _core.EventLevel.DEBUG: logging.DEBUG,
    _core.EventLevel.INFO: logging.INFO,
    _core.EventLevel.WARNING: logging.WARNING,
    _core.EventLevel.ERROR: logging.ERROR,
}


@dataclass
class FrameResult:
    """Perception output of one frame (``raw`` is the core's PerceptionFrame)."""

    raw: "_core.PerceptionFrame"
    points: np.ndarray  # the caller's (N, 3) array, not copied (a copy with NaN rows when a
    #                     workspace dropped some, see :mod:`.workspace`)
    outside_workspace: int = 0  # rows dropped by the workspace (counted in num_invalid too)

    @property
    def labels(self) -> np.ndarray:
        """One int per input row: -2 invalid, -1 environment, >= 0 object group id."""
        return self.raw.filter.labels

    @property
    def table(self) -> Optional["_core.Plane"]:
        return self.raw.filter.table

    @property
    def estimates(self) -> list:
        return self.raw.estimates

    @property
    def object_mask(self) -> np.ndarray:
        return self.labels >= 0

    @property
    def environment_emitted(self) -> bool:
        """Whether the scene filter emits the environment rows (from the first lock on)."""
        return bool(self.raw.filter.environment_emitted)

    @property
    def environment_mask(self) -> np.ndarray:
        """Environment rows; empty before the first lock (method.md §1.5: nothing is emitted)."""
        if not self.environment_emitted:
            return np.zeros(len(self.labels), dtype=bool)
        return self.labels == _core.LABEL_ENVIRONMENT

    def object_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(M, 3) object points and their (M,) group ids."""
        m = self.object_mask
        return rows_where(self.points, m), self.labels[m]

    def environment_points(self) -> np.ndarray:
        return rows_where(self.points, self.environment_mask)


class PerceptionSession:
    """Scene filter + estimates + tracker for one camera session.

    Thread-safe: calls from several threads are serialised (see the module docstring).
    """

    def __init__(self, filter_config: SceneFilterConfig | None = None,
                 obb_config: ObbConfig | None = None,
                 workspace: WorkspaceConfig | None = None,
                 depth_noise: DepthNoiseConfig | None = None) -> None:
        """``workspace``: drop points outside it before the scene filter (default: none);
        ``depth_noise``: the camera's noise model (default: ``config/depth_noise.yaml``'s
        defaults; give the settings' ``depth_noise``, the one the camera has)."""
        self.filter_config = filter_config or SceneFilterConfig()
        self.obb_config = obb_config or ObbConfig()
        self.workspace = workspace or WorkspaceConfig()
        self.depth_noise = depth_noise or DepthNoiseConfig()
        self._core = _core.Perception(self.filter_config.to_core(self.depth_noise),
                                      self.obb_config.to_core(self.depth_noise))

    @property
    def frames(self) -> int:
        """Frames processed since the start or the last ``reset()`` (the core's count, so
        it is exact also when several threads process frames)."""
        return self._core.scene_filter.frame_index

    # ---- latched session constants -------------------------------------------------
    @property
    def plane(self) -> Optional["_core.Plane"]:
        """The locked table plane (None before the first lock)."""
        return self._core.scene_filter.persistence.state.lock

    @property
    def band_m(self) -> float:
        return self.filter_config.band

    @property
    def plane_locked(self) -> bool:
        return self._core.scene_filter.persistence.locked

    @property
    def tracker(self) -> "_core.Tracker":
        return self._core.tracker

    def tracks(self) -> list:
        """Tracks sorted by tid."""
        return list(self._core.tracker.tracks)

    # ---- per frame ---------------------------------------------------------------
    def process(self, points: np.ndarray, camera_position, time_s: float,
                image_width_px: int = 0, rgb: Optional[np.ndarray] = None) -> FrameResult:
        """One frame: (N, 3) float32/float64 world points, camera position at capture, time.

        ``image_width_px`` > 0: the frame is organized (row ``v*W + u`` is pixel (u, v), as
        :class:`~grasp_pipeline.robot.frame.Frame` delivers it) and the object candidates are
        segmented over the image (``scene_filter.segment_*``); 0: an unorganized cloud
        (Euclidean clustering, method.md §1.4). ``rgb``: None or the (H, W, 3) uint8 colour image
        aligned with the rows, read in place (its colour boundaries separate touching objects)."""
        points, outside = self.workspace.apply(points, camera_position)
        raw = self._core.process(points, camera_position, float(time_s), int(image_width_px), rgb)
        if outside:
            log.debug("workspace: dropped %d point(s) outside it", outside)
        for ev in raw.filter.events:
            log.log(_LEVELS.get(ev.level, logging.INFO), "%s", ev.message)
        if raw.filter.num_invalid:
            log.debug("dropped %d invalid rows (%d NaN/Inf, %d beyond +-%g m)",
                      raw.filter.num_invalid, raw.filter.num_invalid - raw.filter.num_out_of_range,
                      raw.filter.num_out_of_range, raw.filter.max_abs_coordinate_m)
        for label, why in zip(raw.failed_labels, raw.failures):
            log.debug("cluster %d: no estimate (%s)", label, why)
        if raw.tids:
            log.debug("views: %s", ", ".join(
                f"#{tid} {v.quality.name.lower()}" for tid, v in zip(raw.tids, raw.views)))
        return FrameResult(raw=raw, points=points, outside_workspace=outside)

    def view_labels(self, frame: FrameResult) -> str:
        """``#0 nadir, #1 oblique`` for the log lines users know."""
        return ", ".join(f"#{tid} {v.quality.name.lower()} ({v.angle_deg:.1f} deg)"
                         for tid, v in zip(frame.raw.tids, frame.raw.views))

    def reset(self) -> None:
        """Forget the plane lock, the tracks and the frame count (a new session)."""
        self._core.reset()
