"""The perception loop: every camera frame → one core call → tracker → best grasp.

``PerceptionLoop.on_frame`` is registered as a frame listener of the simulated camera
(``SimWorld.add_frame_listener``), so perception runs at the camera rate whoever steps
the world. It keeps what a consumer needs at any time: the latched plane and band, the
tracks, the latest frame, the ready (start-up) camera pose, liveness (``stale``) and, after
a selection, the best grasp re-resolved from the anchor on every frame.

Liveness with frames on demand: the camera renders only while a consumer looks, so "no
frame for ``stale_timeout_s``" is measured on the camera's *looking clock*
(``looking_time_s``: simulated time during which frames were requested), not on the
wall of simulated time. A motion during which nobody looks does not make perception
stale; a camera that delivers nothing for ``stale_timeout_s`` while someone looks does.
With continuous frames the looking clock is the simulated clock (the old rule).

Tracks with frames on demand: tracks keep ageing on simulated time (``last_seen_s``), but
the core's tracker retires them only when a frame is processed, after that frame's
observations. So nothing retires while nobody looks, and the first frame of a look
refreshes every object in view before the rest (not seen for ``nadir_hold_s`` /
``max_age_s``) retire: an object out of view at the settle view loses its NADIR track and
the pick re-probes it, as before; an object in view keeps its NADIR estimate (an oblique
view never overwrites one). The old path differs where the camera, looking at the tray
while placing, retired a NADIR track of an object it then saw again at home (a re-probe
the new path does not need), and its frames during motions also fed the median windows
(estimates differ in their last digits); ``bench frames`` compares the outcomes.
"""

from __future__ import annotations

import logging
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Iterator, Optional

import numpy as np

from ... import _core
from ...perception import FrameResult, PerceptionSession
from ...perception.scene_volume import SceneVolume
from ..config import GraspFitConfig, ScanConfig
from ..events import EventBus, FrameEvent, PerceptionEvent
from ..grasping.support import judge_any_side, judge_graspable
from .scene_cloud import SceneCloud, cloud_from_frame
from .selection import Selector, SelectResult
from .tracks import nearest_track

log = logging.getLogger("grasp_pipeline.perception_loop")


@dataclass
class FrameInfo:
    """What the loop keeps of the latest frame."""

    time_s: float
    T_world_camera: np.ndarray
    result: FrameResult
    q: Optional[np.ndarray] = None  # arm joints at capture (for the planner's self-filter)


class PerceptionLoop:
    """Frames in, tracks and best grasps out (one instance per run)."""

    def __init__(self, session: PerceptionSession, scan_config: ScanConfig | None = None,
                 ready_camera_pose: Optional[np.ndarray] = None,
                 events: Optional[EventBus] = None, camera=None,
                 fit_config: Optional[GraspFitConfig] = None,
                 volume: Optional[SceneVolume] = None) -> None:
        """``camera``: the robot's camera (its ``looking_time_s`` clocks liveness); None:
        liveness on the frames' simulated time. ``fit_config``: the scene cloud's voxel and
        the support rule (:mod:`.support`) that judges which objects are graspable.
        ``volume``: the scene volume every frame is offered to (its policy decides which it
        integrates); None: no volume."""
        self.session = session
        self.volume = volume
        self.camera = camera
        self._looked_at_frame_s: Optional[float] = None  # looking clock at the latest frame
        self.events = events if events is not None else EventBus()
        self.config = scan_config or ScanConfig()
        self.fit_config = fit_config or GraspFitConfig()
        self.selector = Selector(fallback_limit_m=self.config.select_max_distance_m, judge=self.judge)
        self._cloud: Optional[tuple[int, Optional[SceneCloud]]] = None  # (frame count, cloud)
        self.latest: Optional[FrameInfo] = None
        self.frames = 0
        # The camera pose of the start-up ("ready") pose, recorded once: from the robot's
        # kinematics at start-up when given, else from the first frame's capture pose.
        self.ready_camera_pose: Optional[np.ndarray] = (
            None if ready_camera_pose is None else np.array(ready_camera_pose, dtype=float))
        self._last_labels = ""
        self.stale_reported = False
        #: method.md §2.6's width guard in :meth:`judge` (off for grasp sources that approach from
        #: any side; the composition root sets it from the source)
        self.width_guard = True
        self._elsewhere = 0  # open :meth:`looking_elsewhere` contexts

    @contextmanager
    def looking_elsewhere(self) -> Iterator[None]:
        """Frames delivered while this is open show something other than the table the loop
        tracks (the tray, looked into after a place): they keep perception alive and are
        published as :class:`~.events.FrameEvent` s, but are not processed — no tracks, no
        retirements, no best grasp from them. Whoever looks listens to the camera itself."""
        self._elsewhere += 1
        try:
            yield
        finally:
            self._elsewhere -= 1

    # ---- frames -------------------------------------------------------------------
    def on_frame(self, frame, q: Optional[np.ndarray] = None) -> None:
        """Process one camera frame (``sim.Frame``: points_world, time_s, T_world_camera);
        ``q``: the arm joints at capture, if known."""
        T = np.asarray(frame.T_world_camera)
        if self.events.wants(FrameEvent):
            self.events.publish(FrameEvent(float(frame.time_s), frame, None if q is None else np.array(q)))
        if self._elsewhere:
            self._looked_at_frame_s = self._looking_clock(float(frame.time_s))
            self.stale_reported = False
            return
        res = self.session.process(frame.points_world, T[:3, 3], frame.time_s,
                                   image_width_px=frame.width, rgb=frame.rgb)
        if self.volume is not None:
            self.volume.offer(frame)
        if self.ready_camera_pose is None:
            self.ready_camera_pose = T.copy()
        self.latest = FrameInfo(float(frame.time_s), T, res, None if q is None else np.array(q))
        self.frames += 1
        self._looked_at_frame_s = self._looking_clock(float(frame.time_s))
        self.stale_reported = False
        # Per-frame view labels ("#0 nadir, #1 oblique") are DEBUG, and only when they change;
        # the stages (scan probes, picks) log their own decisions at INFO.
        if log.isEnabledFor(logging.DEBUG):
            key = ", ".join(f"#{t} {v.quality.name.lower()}" for t, v in zip(res.raw.tids, res.raw.views))
            if key and key != self._last_labels:
                log.debug("views: %s", self.session.view_labels(res))
            self._last_labels = key
        tracks = self.tracks()
        self.selector.on_frame(tracks, self.gate_m, self.plane, float(frame.time_s))
        if self.events.wants(PerceptionEvent):
            self.events.publish(PerceptionEvent(float(frame.time_s), res, tuple(tracks)))

    # ---- latched state ------------------------------------------------------------
    @property
    def plane(self) -> Optional["_core.Plane"]:
        return self.session.plane

    @property
    def band_m(self) -> float:
        return self.session.band_m

    @property
    def plane_locked(self) -> bool:
        return self.session.plane_locked

    @property
    def gate_m(self) -> Optional[float]:
        return self.session.tracker.last_gate

    def tracks(self) -> list:
        return self.session.tracks()

    def scene_cloud(self) -> Optional[SceneCloud]:
        """The latest frame's points with their owners (track / environment), thinned on the
        ``fit_config.cloud_voxel_m`` grid; None before a frame with a locked plane. Built on
        demand, once per frame."""
        if self._cloud is not None and self._cloud[0] == self.frames:
            return self._cloud[1]
        cloud = None
        if self.latest is not None and self.plane is not None:
            cloud = cloud_from_frame(self.latest.result, self.plane, self.band_m,
                                     self.fit_config.cloud_voxel_m)
        self._cloud = (self.frames, cloud)
        return cloud

    def judge(self, track) -> tuple[bool, list]:
        """(graspable, notes) of a track: method.md §2.6's guards with the support rule on the
        latest scene cloud (:func:`~.support.judge_graspable`); without the width guard when
        :attr:`width_guard` is off (a grasp source that approaches from any side decides
        whether the hand fits, :func:`~.support.judge_any_side`)."""
        if not self.width_guard:
            return judge_any_side(track, self.scene_cloud, self.fit_config)
        e = track.smoothed
        if e.grasp_ok or e.resting or not (e.height_ok and e.width_ok):
            return bool(e.grasp_ok), list(e.notes)
        return judge_graspable(track, self.scene_cloud(), self.fit_config)

    def forget_tracks(self) -> None:
        """Forget every track but keep the plane lock and the liveness state: the next
        frames describe the table anew (after a pick attempt the objects may have moved).
        Drops the selection too (its anchor referred to the old tracks). The scene volume is
        kept: the pick forgot the attempted target's surroundings in it already
        (:meth:`~grasp_pipeline.perception.scene_volume.SceneVolume.forget_after_attempt`)
        and the next frames carve what moved elsewhere."""
        self.session.tracker.reset()
        self.selector.clear()

    def last_frame_time_s(self) -> Optional[float]:
        return None if self.latest is None else self.latest.time_s

    def _looking_clock(self, now_s: float) -> float:
        return now_s if self.camera is None else float(self.camera.looking_time_s)

    def unseen_looking_s(self, now_s: float) -> Optional[float]:
        """Looking-clock seconds since the latest frame (None: no frame yet)."""
        if self._looked_at_frame_s is None:
            return None
        return self._looking_clock(now_s) - self._looked_at_frame_s

    def stale(self, now_s: float) -> bool:
        """Upstream dead: no frame ever, or none for ``stale_timeout_s`` of *looking* time
        (simulated seconds during which frames were requested; see the module doc). Time
        in which nobody requested frames (a motion) does not count: no frame was due."""
        unseen = self.unseen_looking_s(now_s)
        return unseen is None or unseen > self.config.stale_timeout_s

    def report_if_stale(self, now_s: float) -> bool:
        """Log once and drop the published grasp when upstream is dead (method.md §6)."""
        if not self.stale(now_s):
            return False
        if not self.stale_reported:
            t = self.last_frame_time_s()
            unseen = self.unseen_looking_s(now_s)
            log.error("perception is stale: no camera frame for %s (limit %.1f s); "
                      "not acting on old estimates",
                      "ever" if t is None else f"{unseen:.2f} s of looking", self.config.stale_timeout_s)
            self.stale_reported = True
        self.selector.best_grasp = None
        return True

    # ---- selection ----------------------------------------------------------------
    def select(self, x: float, y: float) -> SelectResult:
        return self.selector.select(x, y, self.tracks(), self.gate_m, self.plane)


    def nearest_track(self, xy: np.ndarray, within_gate: bool = True):
        """Track nearest to a horizontal position (within the gate when one is defined)."""
        best, best_d = nearest_track(self.tracks(), xy)
        gate = self.gate_m
        if best is not None and within_gate and gate is not None and best_d > gate:
            return None
        return best
