"""Active scan (method.md §6): IDLE → ROUGH → PROBING(i) → RETURN, no way back.

``ActiveScan.trigger()`` checks the refusals (camera geometry unknown; no motion planner;
plane not locked; already scanning — saying which object i/N and stage; no objects seen),
then answers ``"scan started: probing N objects"`` and the scan runs as a runtime task:
ROUGH takes each track's rough centre and fixes the order (start joints are recorded at the
trigger); upstream liveness is checked once, before the first motion; each probe moves
the camera above object i (method.md §3 pose, planned on the perceived scene), waits for
``dwell_frames`` new frames, then up to ``dwell_timeout_s`` until *that* object has a NADIR
estimate produced after arrival, and logs every track's view angle. Camera frames are
requested for the dwell only (frames on demand): the probe motions and RETURN render
nothing. A planning or motion
failure stops probing (the rest are skipped). Closer look (ours): after a probe's
NADIR estimate, a segment that may be several objects (:func:`~.ambiguity.ambiguity`: wider
than the gripper in every direction, or a non-convex outline) is looked at again from
``closer_look_standoff_m`` above its top for ``dwell_frames`` frames; that view's segmentation
decides (a failed closer move is logged and the scan goes on). RETURN to the start joints runs whenever
``return_to_start`` is set and start joints were recorded, also after a failure. At the end:
stage IDLE, i/N = 0, the liveness flags reset. :attr:`status` is readable at any time.
"""

from __future__ import annotations

import enum
import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ... import _core
from ...exceptions import GraspPipelineError
from ...motion.work_cell import footprint_distance_m
from ...results import ProbeResult, ScanOutcome
from ..config import ScanConfig
from ..events import StageEvent
from ..runtime import Runtime, Task, then_cleanup
from ..scene.scene_model import snapshot
from ..scene.tracks import track_box
from .ambiguity import ambiguity

log = logging.getLogger("grasp_pipeline.scan")


class ScanStage(enum.Enum):
    IDLE = "idle"
    ROUGH = "rough"
    PROBING = "probing"
    RETURN = "return"


@dataclass(frozen=True)
class TriggerResult:
    accepted: bool
    message: str


class ActiveScan:
    """The scan state machine; one instance per run."""

    def __init__(self, runtime: Runtime, loop, motion, camera_in_flange: Optional[np.ndarray],
                 config: ScanConfig | None = None, max_width_m: Optional[float] = None) -> None:
        """``max_width_m``: the widest object the gripper takes, its usable opening
        (:func:`~..grasping.opening.max_grasp_width_m`; the closer look's "wide" rule; None: only
        the outline rule)."""
        self.rt = runtime
        self.max_width_m = float("inf") if max_width_m is None else float(max_width_m)
        self.loop = loop
        self.motion = motion
        self.camera_in_flange = camera_in_flange
        self.config = config or ScanConfig()
        self.stage = ScanStage.IDLE
        self.index = 0
        self.total = 0
        self.task: Optional[Task] = None
        self.last_outcome: Optional[ScanOutcome] = None

    # ---- status -------------------------------------------------------------------
    @property
    def status(self) -> dict:
        return {"stage": self.stage.value, "i": self.index, "n": self.total}

    def status_text(self) -> str:
        if self.stage is ScanStage.PROBING:
            return f"probing object {self.index}/{self.total}"
        return f"stage {self.stage.value}" + (f" ({self.total} objects)" if self.total else "")

    # ---- trigger ------------------------------------------------------------------
    def trigger(self, centres=None) -> TriggerResult:
        """Check the refusals, then start the scan in the background.

        ``centres`` (ours): probe only these world positions (e.g. one object whose NADIR
        track has retired before its pick) instead of every track's rough centre."""
        if self.camera_in_flange is None or self.loop.ready_camera_pose is None:
            return self._refuse("scan refused: camera geometry unknown (no camera pose in the "
                                "flange frame or no frame seen yet)")
        if self.motion is None:
            return self._refuse("scan refused: no motion planner available")
        if not self.loop.plane_locked:
            return self._refuse("scan refused: table plane not locked yet; wait for perception "
                                "to see the table")
        if self.stage is not ScanStage.IDLE:
            return self._refuse(f"scan refused: already scanning ({self.status_text()}, stage "
                                f"{self.stage.value})")
        tracks = self.loop.tracks()
        if not tracks and centres is None:
            return self._refuse("scan refused: no objects seen")
        rough = ([np.asarray(t.smoothed.center, dtype=float).copy() for t in tracks] if centres is None
                 else [np.asarray(c, dtype=float).copy() for c in centres])
        start_q = np.asarray(self.rt.world.q, dtype=float).copy()
        self.stage, self.total, self.index = ScanStage.ROUGH, len(rough), 0
        self.task = self.rt.start("scan", self._run(start_q, rough))
        msg = f"scan started: probing {len(rough)} objects"
        log.info("%s", msg)
        return TriggerResult(True, msg)

    def _refuse(self, message: str) -> TriggerResult:
        log.warning("%s", message)
        return TriggerResult(False, message)

    # ---- the task -----------------------------------------------------------------
    def _run(self, start_q: np.ndarray, rough: list):
        out = ScanOutcome(start_q=start_q.tolist())
        try:
            yield from self._scan(start_q, rough, out)
        finally:
            self.stage, self.index, self.total = ScanStage.IDLE, 0, 0
            self.loop.stale_reported = False
            self.last_outcome = out
            log.info("scan finished: %d/%d objects NADIR, returned to start: %s%s",
                     sum(p.nadir for p in out.probes), len(out.probes), out.returned_to_start,
                     f" ({out.failure})" if out.failure else "")
        return out

    def _scan(self, start_q: np.ndarray, rough: list, out: ScanOutcome):
        # ROUGH: rough centres (taken at the trigger), fixed order (by tid: the order the
        # objects were first seen).
        out.probes = [ProbeResult(i + 1, c.tolist()) for i, c in enumerate(rough)]
        # Liveness, once, before the first motion: no motion and no RETURN when stale.
        if self.loop.report_if_stale(self.rt.world.time_s):
            out.failure = "perception stale before the first motion: no motion made"
            return
        self.motion.set_scene(snapshot(self.loop))
        probed: list[int] = []  # the probes that began to move (then the scan returns)
        yield from then_cleanup(self._probe_all(rough, out, probed),
                                lambda: self._return(start_q, out) if probed else None)

    def _probe_all(self, rough: list, out: ScanOutcome, probed: list):
        """Task: move above each rough centre in turn and look (``probed`` gets each probe's
        number as it begins to move); the first probe that cannot move ends the scan."""
        plane = self.loop.plane
        ready = _core.Pose.from_matrix(self.loop.ready_camera_pose)
        cam_in_flange = _core.Pose.from_matrix(self.camera_in_flange)
        for i, (centre, probe) in enumerate(zip(rough, out.probes), start=1):
            self.stage, self.index = ScanStage.PROBING, i
            target = _core.camera_above_flange_target(centre, plane, ready, cam_in_flange)
            try:
                probed.append(i)
                yield from self.motion.to_pose(target.matrix(), frame="flange", kind="scan_probe")
            except GraspPipelineError as exc:
                probe.message = f"probe {i}/{len(rough)} failed to move: {exc}"
                out.failure = probe.message
                log.error("%s; remaining objects skipped", probe.message)
                self.motion.sync()
                return
            yield from self._dwell(i, centre, probe)
            yield from self._closer_look(i, probe)
        out.completed = True

    def _dwell(self, i: int, centre: np.ndarray, probe: ProbeResult):
        """Task: look from above object ``i`` (frames requested from arrival to the end)."""
        with self.rt.looking():
            yield from self._dwell_looking(i, centre, probe)

    def _dwell_looking(self, i: int, centre: np.ndarray, probe: ProbeResult):
        world, cfg = self.rt.world, self.config
        arrival_s = world.time_s
        self.rt.events.publish(StageEvent(float(arrival_s), "probe_arrived",
                                          f"{i} {centre[0]:.6f} {centre[1]:.6f}", perception=self.loop))
        frames0 = self.loop.frames
        t_end = arrival_s + cfg.dwell_timeout_s
        while self.loop.frames - frames0 < cfg.dwell_frames:
            if world.time_s >= t_end:
                log.warning("probe %d: only %d of %d dwell frames within %.1f s; continuing", i,
                            self.loop.frames - frames0, cfg.dwell_frames, cfg.dwell_timeout_s)
                break
            yield
        t_end = world.time_s + cfg.dwell_timeout_s
        while True:
            track = self.loop.nearest_track(centre[:2], within_gate=True)
            if (track is not None and track.quality == _core.ViewQuality.NADIR
                    and track.last_seen_s >= arrival_s):
                probe.tid, probe.nadir = track.tid, True
                probe.message = f"#{track.tid} nadir"
                break
            if world.time_s >= t_end:
                probe.message = (f"probe {i}: no NADIR estimate of the object within "
                                 f"{cfg.dwell_timeout_s:.1f} s; it keeps its previous quality")
                log.warning("%s", probe.message)
                break
            yield
        latest = self.loop.latest
        if latest is not None:
            raw = latest.result.raw
            probe.view_angles_deg = {int(t): float(v.angle_deg) for t, v in zip(raw.tids, raw.views)}
            log.info("probe %d/%d: %s", i, self.total, ", ".join(
                f"#{t} {v.quality.name.lower()} ({v.angle_deg:.1f} deg)" for t, v in zip(raw.tids, raw.views)))

    def _closer_look(self, i: int, probe: ProbeResult):
        """Task: look again from closer above probe ``i``'s segment when it is ambiguous."""
        cfg = self.config
        track = next((t for t in self.loop.tracks() if t.tid == probe.tid), None)
        if not cfg.closer_look or not probe.nadir or track is None:
            return
        cloud = self.loop.scene_cloud()
        reason = ambiguity(track, None if cloud is None else cloud.of(track.tid), self.max_width_m, cfg)
        target = None if reason is None else self._closer_target(track)
        if target is None:
            return
        probe.closer_look = reason
        log.info("probe %d: #%d is ambiguous (%s): looking from closer above", i, track.tid, reason)
        try:
            self.motion.set_scene(snapshot(self.loop))
            yield from self.motion.to_pose(target.matrix(), frame="flange", kind="scan_closer_look")
        except GraspPipelineError as exc:
            probe.closer_look += f"; could not move closer: {exc}"
            log.warning("probe %d: closer look failed to move: %s", i, exc)
            self.motion.sync()
            return
        arrival_s = float(self.rt.world.time_s)
        with self.rt.looking():
            yield from self._closer_dwell(i, track)
        probe.closer_look += f"; then {self._segments_near(track, arrival_s)} segment(s) there"
        log.info("probe %d: closer look at #%d: %s", i, track.tid, probe.closer_look)

    def _closer_target(self, track) -> Optional["_core.Pose"]:
        """The flange pose with the camera ``closer_look_standoff_m`` above the top of
        ``track``'s box (None: that is not lower than the probe's view)."""
        e = track.smoothed
        centre = np.asarray(e.center, dtype=float)
        ready = np.array(self.loop.ready_camera_pose, dtype=float)
        camera_z = centre[2] + 0.5 * float(e.extents[2]) + self.config.closer_look_standoff_m
        if camera_z >= ready[2, 3]:
            return None
        ready[2, 3] = camera_z
        return _core.camera_above_flange_target(centre, self.loop.plane, _core.Pose.from_matrix(ready),
                                                _core.Pose.from_matrix(self.camera_in_flange))

    def _closer_dwell(self, i: int, track):
        world, cfg = self.rt.world, self.config
        c = np.asarray(track.smoothed.center, dtype=float)
        self.rt.events.publish(StageEvent(float(world.time_s), "closer_look_arrived",
                                          f"{i} {c[0]:.6f} {c[1]:.6f}", perception=self.loop))
        frames0, t_end = self.loop.frames, world.time_s + cfg.dwell_timeout_s
        while self.loop.frames - frames0 < cfg.dwell_frames and world.time_s < t_end:
            yield

    def _segments_near(self, track, since_s: float) -> int:
        """How many tracks seen since ``since_s`` have their centre inside ``track``'s former
        footprint."""
        box = track_box(track)
        return sum(t.last_seen_s >= since_s and footprint_distance_m(box, t.smoothed.center) <= 0.0
                   for t in self.loop.tracks())

    def _return(self, start_q: np.ndarray, out: ScanOutcome):
        if not self.config.return_to_start:
            log.warning("return_to_start is false: the arm stays at the last probe")
            return
        self.stage = ScanStage.RETURN
        try:
            yield from self.motion.to_joints(start_q, kind="scan_return")
        except GraspPipelineError as exc:
            out.failure = (out.failure + " | " if out.failure else "") + f"return to start failed: {exc}"
            log.error("return to start failed: %s", exc)
            self.motion.sync()
        world, cfg = self.rt.world, self.config
        t_end = world.time_s + cfg.return_settle_timeout_s
        while (float(np.max(np.abs(np.asarray(world.q) - start_q))) > cfg.return_settle_tol_rad
               and world.time_s < t_end):
            yield
        err = float(np.max(np.abs(np.asarray(world.q) - start_q)))
        out.joint_error_rad = err
        out.returned_to_start = err <= 1e-3
