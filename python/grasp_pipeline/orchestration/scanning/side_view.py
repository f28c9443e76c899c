"""The side view (ours): before grasps are asked for, look at a target whose sides were never seen.

The frames the arm takes accumulate in the perception loop's scene volume
(:mod:`grasp_pipeline.perception.scene_volume`). Before the grasp source is asked for a
target, :func:`look_at_sides` measures how much of the shell beside the target's box is
UNKNOWN (:mod:`~grasp_pipeline.perception.side_coverage`). When the worst face is at least
``side_view_unknown_fraction`` unknown, the candidate views around the target are ranked by
the unknown shell voxels each would see (:mod:`~grasp_pipeline.perception.view_planner`); the
best one that reveals at least ``side_view_min_gain_fraction`` of them and that the arm
reaches — an IK solution of the flange pose (camera pose times the camera's mount), for the
image upright, upside down or on either side, that the planner's state validator accepts on
the perceived scene; at most ``side_view_max_ik_checks`` candidates are tried, those that reveal
about as much (within 10 %) nearest the robot's base first, and none as far out from the base
as one that had no IK solution — is visited:
move there (planned on the perceived scene), look for ``side_view_dwell_frames`` frames (they
are integrated by the loop), and come back to where the arm started (``side_view_return``,
on by default: the grasp is then chosen from the start view, whose frame also gives the
planner its environment points). Frames are requested for the dwell only.

The outcome (:class:`~grasp_pipeline.results.SideViewResult`) records the coverage before
and after, the view, and its cost in simulated and CPU seconds.
"""

from __future__ import annotations

import logging
import time
from typing import Optional

import numpy as np

from ...exceptions import GraspPipelineError
from ...motion.poses import pose_inverse
from ...perception.side_coverage import SideCoverage, side_coverage
from ...perception.view_planner import ViewCandidate, rank_views
from ...perception.volume_config import VolumeConfig
from ...results import SideViewResult
from ..config import ScanConfig
from ..events import StageEvent
from ..runtime import Runtime, then_cleanup
from ..scene.scene_model import snapshot

log = logging.getLogger("grasp_pipeline.side_view")

#: Camera rolls about its optical axis tried for reachability [deg]; the flange position
#: nearest the robot's base (the world origin) is tried first.
ROLLS_DEG = (0.0, 180.0, 90.0, -90.0)
#: A forced side view (no grasp without it) is taken when a face is at least this unknown.
FORCED_MIN_UNKNOWN = 0.05
#: Views revealing within this fraction of each other count as equally good (then nearest the
#: base first: :meth:`SideView._reach_order`).
GAIN_STEP = 0.1


def _roll(deg: float) -> np.ndarray:
    a = np.radians(deg)
    T = np.eye(4)
    T[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    return T


def _reach_m(view: ViewCandidate, camera_T_flange: np.ndarray) -> float:
    """Horizontal distance of the view's flange (upright image) from the robot's base (the
    world origin, z up) [m]: the farther out, the likelier the arm cannot reach it."""
    flange = view.T_world_camera @ camera_T_flange
    return float(np.hypot(flange[0, 3], flange[1, 3]))


class SideView:
    """Plans and takes the extra view of one target (see the module doc)."""

    def __init__(self, runtime: Runtime, loop, motion, camera_in_flange: np.ndarray,
                 config: Optional[VolumeConfig] = None, scan_config: Optional[ScanConfig] = None) -> None:
        self.rt, self.loop, self.motion = runtime, loop, motion
        self.flange_T_camera = np.asarray(camera_in_flange, float)
        self.camera_T_flange = pose_inverse(self.flange_T_camera)
        self._out_of_reach_m = float("inf")  # a view's flange this far out had no IK solution
        self.config = config or VolumeConfig()
        self.scan_config = scan_config or ScanConfig()

    # ---- judging ------------------------------------------------------------------
    def coverage(self, track, interior: bool = False) -> Optional[SideCoverage]:
        """The unknown shell of ``track``'s box (``interior``: and inside it; None: no volume
        or no plane yet)."""
        volume, plane = getattr(self.loop, "volume", None), self.loop.plane
        if volume is None or plane is None:
            return None
        e, cfg = track.smoothed, self.config
        others = [(t.smoothed.center, t.smoothed.R_box, t.smoothed.extents)
                  for t in self.loop.tracks() if t.tid != track.tid]
        return side_coverage(volume, e.center, e.R_box, e.extents, plane, cfg.side_view_shell_m,
                             cfg.side_view_table_clearance_m, others, interior)

    def choose(self, track, coverage: SideCoverage) -> tuple[Optional[ViewCandidate], Optional[np.ndarray], str]:
        """(view, flange pose, why) of the best reachable view that reveals enough; (None, None,
        why not) otherwise. Sets the planner's scene to the perceived one."""
        cfg, volume = self.config, self.loop.volume
        centre = np.asarray(track.smoothed.center, float)
        ready = self.loop.ready_camera_pose
        views = rank_views(volume, coverage.unknown_points, centre, cfg,
                           None if ready is None else np.asarray(ready)[:3, 3])
        good = self._reach_order([v for v in views if v.seen_fraction >= cfg.side_view_min_gain_fraction])
        if not good:
            best = views[0].seen_fraction if views else 0.0
            return None, None, (f"no view reveals {cfg.side_view_min_gain_fraction:.0%} of the unknown "
                                f"shell (best {best:.0%} of {len(views)} seeing any)")
        self.motion.set_scene(snapshot(self.loop))
        checked = 0
        for view in good:
            if checked >= cfg.side_view_max_ik_checks:
                break
            if _reach_m(view, self.camera_T_flange) >= self._out_of_reach_m:
                continue
            checked += 1
            T_flange = self.reachable(view)
            if T_flange is not None:
                return view, T_flange, ""
        return None, None, f"none of the {len(good)} views revealing enough is reachable ({checked} checked)"

    def _reach_order(self, views: list) -> list:
        """``views`` by what they reveal in steps of :data:`GAIN_STEP`, and within a step
        nearest the robot's base first (:func:`_reach_m`)."""
        return sorted(views, key=lambda v: (-int(v.seen_fraction / GAIN_STEP + 1e-9),
                                            _reach_m(v, self.camera_T_flange)))

    def reachable(self, view: ViewCandidate) -> Optional[np.ndarray]:
        """The flange pose of ``view`` (some roll of ROLLS_DEG, the flange nearest the base
        first) with a collision-free IK solution on the planner's current scene, or None. When
        no roll has any IK solution, views at least as far out (:func:`_reach_m`) are not
        tried again (each unreachable view costs ~0.1 s of IK)."""
        planner = self.motion.planner
        poses = [view.T_world_camera @ _roll(roll) @ self.camera_T_flange for roll in ROLLS_DEG]
        poses.sort(key=lambda T: float(np.linalg.norm(T[:3, 3])))
        solved = False
        for T_flange in poses:
            try:
                ik = planner.solve_ik(T_flange, self.motion.q_cmd, "flange")
            except GraspPipelineError:
                continue
            solved = True
            if np.any(planner.validator.check_batch(ik.solutions)):
                return T_flange
        if not solved:
            self._out_of_reach_m = min(self._out_of_reach_m, _reach_m(view, self.camera_T_flange))
        return None

    # ---- looking ------------------------------------------------------------------
    def task(self, T_flange: np.ndarray, tid: int, out: SideViewResult):
        """Task: move the camera to the view, look, come back (module doc)."""
        start_q = np.asarray(self.motion.q_cmd, float).copy()
        yield from then_cleanup(self._look(T_flange, tid, out),
                                lambda: self._return(start_q, out) if self.config.side_view_return else None)

    def _look(self, T_flange: np.ndarray, tid: int, out: SideViewResult):
        try:
            yield from self.motion.to_pose(T_flange, frame="flange", kind="side_view")
            out.moved = True
            yield from self._dwell(tid)
        except GraspPipelineError as exc:
            out.message = f"side view failed to move: {exc}"
            log.warning("%s", out.message)
            self.motion.sync()

    def _dwell(self, tid: int):
        loop, world = self.loop, self.rt.world
        with self.rt.looking():
            self.rt.events.publish(StageEvent(float(world.time_s), "side_view_arrived", str(tid), perception=loop))
            frames0, t_end = loop.frames, world.time_s + self.scan_config.dwell_timeout_s
            while loop.frames - frames0 < self.config.side_view_dwell_frames and world.time_s < t_end:
                yield

    def _return(self, start_q: np.ndarray, out: SideViewResult):
        try:
            yield from self.motion.to_joints(start_q, kind="side_view_return")
        except GraspPipelineError as exc:
            out.message = (out.message + "; " if out.message else "") + f"return failed: {exc}"
            log.error("side view: return failed: %s", exc)
            self.motion.sync()


def look_at_sides(side_view: SideView, track, timeout_s: float, force: bool = False) -> SideViewResult:
    """Judge ``track``'s sides and take the side view when they are unknown enough (module
    doc; ``force``: the grasp source found no grasp without it — look whenever any of the
    shell or the space inside the target's box is unknown); returns what happened."""
    c0, sim0 = time.thread_time(), float(side_view.rt.world.time_s)
    out = SideViewResult(tid=int(track.tid))
    before = side_view.coverage(track, interior=force)
    if before is None:
        out.message = "no scene volume"
        return out
    out.unknown_before, out.faces_before = before.worst, before.summary()
    if (before.overall if force else before.worst) < (FORCED_MIN_UNKNOWN if force
                                                      else side_view.config.side_view_unknown_fraction):
        out.message = "sides known"
    else:
        _visit(side_view, track, before, out, timeout_s)
        after = side_view.coverage(track, interior=force)
        out.unknown_after, out.faces_after = after.worst, after.summary()
    out.cpu_s = time.thread_time() - c0
    out.sim_s = float(side_view.rt.world.time_s) - sim0
    log.info("side view of #%d: %s (worst face unknown %.0f%%%s)", out.tid, out.message or "looked",
             100 * out.unknown_before, "" if out.unknown_after is None else f" -> {100 * out.unknown_after:.0f}%")
    return out


def _visit(side_view: SideView, track, before: SideCoverage, out: SideViewResult, timeout_s: float) -> None:
    view, T_flange, why = side_view.choose(track, before)
    if view is None:
        out.message = why
        return
    out.view = {"azimuth_deg": view.azimuth_deg, "elevation_deg": view.elevation_deg,
                "distance_m": view.distance_m, "expected_fraction": round(view.seen_fraction, 3)}
    rt = side_view.rt
    try:
        rt.run(rt.start("side_view", side_view.task(T_flange, int(track.tid), out)), timeout_s)
    except TimeoutError as exc:
        rt.world.hold()
        out.message = f"side view did not finish: {exc}"
        log.warning("%s", out.message)
