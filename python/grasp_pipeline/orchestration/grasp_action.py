"""The grasp action (SPEC 7): PRE_GRASP → APPROACH → CLOSE → LIFT → DONE, then PLACE (ours).

Input: a :class:`_core.BestGrasp` (position = contact point, column 0 = approach into
the object, column 2 = closing axis) — the latest published one by default (refused with
"no best grasp yet" when there is none), or an explicit pose with the same convention.
The executor never learns who produced the grasp, so a learned detector can replace the
geometric one.

- PRE_GRASP: open to width + margin, move (planned around the perceived scene, the target
  being no obstacle) to ``pre_grasp_distance_m`` back along the approach axis.
- APPROACH: straight line to the contact point; only the fingers may touch objects. When a
  candidate cannot be planned (a neighbour under the hand), the same grasp a little higher
  (``approach_backoffs_m``, still within the finger pads' reach), then the alternatives
  (closing across the other side when it fits the gripper) are tried — all planned before any motion.
- CLOSE: command a gap of ``2 · close_command_fraction · width − close_squeeze_m`` with the
  effort limit; success by *stalling*: finger speed < ``stall_speed_mps`` for
  ``stall_time_s`` (the commanded gap is narrower than the object, so waiting for it would
  time out); ``close_timeout_s`` overall; fully closed (gap < ``fully_closed_gap_m``) or the
  commanded gap reached = a miss. The object geoms the pads touch now are the held object
  (touch sensing, not ground truth).
- LIFT: straight line up by ``lift_height_m``; then hold ``hold_check_s`` and check the gap
  never fell more than ``held_gap_drop_m`` below the stall gap (the object came up with the
  fingers; if it slipped out they would close to the commanded gap).
- PLACE: carry to one of the tray's drop slots, open, retreat, back to the start joints.
Any stage failure: open, retreat upward, report which stage failed and why.
"""

from __future__ import annotations

import enum
import logging
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .. import _core
from ..exceptions import GraspPipelineError
from ..motion.exceptions import MotionError
from ..sim.robot_model import GRIPPER_MAX_WIDTH_M
from .config import GraspConfig
from .runtime import Runtime, Task, wait_s
from .scene_model import snapshot, without_fragments

log = logging.getLogger("grasp_pipeline.grasp")

OBJECT_GEOM_PREFIX = "obj_"
FINGER_GEOM_MARK = "finger"


class GraspStage(enum.Enum):
    PRE_GRASP = "PRE_GRASP"
    APPROACH = "APPROACH"
    CLOSE = "CLOSE"
    LIFT = "LIFT"
    DONE = "DONE"
    PLACE = "PLACE"


class StageFailure(GraspPipelineError):
    """A stage could not complete (the message says why)."""


@dataclass
class GraspOutcome:
    success: bool = False
    failed_stage: Optional[str] = None
    message: str = ""
    stall_gap_m: Optional[float] = None
    placed: bool = False
    stages: list = field(default_factory=list)  # (stage, sim time at entry [s])
    width_m: Optional[float] = None
    release_time_s: Optional[float] = None  # when the gripper opened to place / recover


def tray_slot(k: int, dx_m: float, dy_m: float) -> np.ndarray:
    """Offset of the k-th drop slot from the tray centre: a 2 x 3 grid, then round again."""
    k = k % 6
    return np.array([dx_m * (1 if k % 2 == 0 else -1), dy_m * (k // 2 - 1), 0.0])


def _closing_along_x(reference_tcp: np.ndarray) -> np.ndarray:
    """Top-down TCP rotation whose closing axis (y) is world ±x, the sign nearer the reference."""
    best, best_d = None, np.inf
    for sign in (1.0, -1.0):
        y = np.array([sign, 0.0, 0.0])
        z = np.array([0.0, 0.0, -1.0])
        R = np.column_stack([np.cross(y, z), y, z])
        d = float(np.arccos(np.clip((np.trace(R @ reference_tcp[:3, :3].T) - 1.0) / 2.0, -1.0, 1.0)))
        if d < best_d:
            best, best_d = R, d
    return best


def tcp_pose_from_grasp(grasp: "_core.BestGrasp", reference_tcp: np.ndarray) -> np.ndarray:
    """TCP pose (z = approach, y = closing axis) of a BestGrasp; of the two closing signs, the
    one whose hand orientation is nearer ``reference_tcp`` (keeps joint 7 off its limits)."""
    R = np.asarray(grasp.R)
    z = R[:, 0]
    best, best_d = None, np.inf
    for sign in (1.0, -1.0):
        y = sign * R[:, 2]
        Rt = np.column_stack([np.cross(y, z), y, z])
        c = np.clip((np.trace(Rt @ reference_tcp[:3, :3].T) - 1.0) / 2.0, -1.0, 1.0)
        d = float(np.arccos(c))
        if d < best_d:
            best, best_d = Rt, d
    T = np.eye(4)
    T[:3, :3] = best
    T[:3, 3] = np.asarray(grasp.position)
    return T


class GraspAction:
    """Runs one grasp (and place) at a time as a runtime task, with stage feedback."""

    def __init__(self, runtime: Runtime, loop, motion, config: GraspConfig | None = None,
                 tray_center: Optional[np.ndarray] = None, home_q: Optional[np.ndarray] = None) -> None:
        self.rt = runtime
        self.loop = loop
        self.motion = motion
        self.config = config or GraspConfig()
        self.tray_center = None if tray_center is None else np.asarray(tray_center, float)
        self.home_q = None if home_q is None else np.asarray(home_q, float)
        self.stage: Optional[GraspStage] = None
        self.task: Optional[Task] = None
        self.placed_count = 0
        # tracks of objects already lifted off the table → where they were lifted from [m]
        self.picked_at: dict[int, np.ndarray] = {}
        self._held: set = set()
        self._target_tid: Optional[int] = None
        self._target_height_m: Optional[float] = None  # measured height of the object in hand
        self._backoff_m = 0.0

    # ---- goal -------------------------------------------------------------------
    def start(self, grasp: Optional["_core.BestGrasp"] = None, place: bool = True,
              alternatives=()):
        """Start a grasp of ``grasp`` (default: the latest published best grasp).

        ``alternatives``: further grasps of the same object, tried in order when the previous
        one cannot be planned (e.g. closing across the other side)."""
        if self.task is not None and not self.task.done:
            return False, f"grasp refused: a grasp is running (stage {self.stage.value})"
        if grasp is None:
            if self.loop.report_if_stale(self.rt.world.time_s):
                return False, "grasp refused: perception is stale (no recent camera frame)"
            grasp = self.loop.selector.best_grasp
        if grasp is None:
            return False, "no best grasp yet"
        self.task = self.rt.start("grasp", self._run(grasp, place, tuple(alternatives)))
        return True, "grasp started"

    # ---- the task ---------------------------------------------------------------
    def _enter(self, out: GraspOutcome, stage: GraspStage) -> None:
        self.stage = stage
        out.stages.append((stage.value, round(float(self.rt.world.time_s), 4)))
        log.info("grasp stage %s", stage.value)

    def _run(self, grasp, place: bool, alternatives=()):
        out = GraspOutcome(width_m=float(grasp.width_m))
        self._held = set()
        try:
            yield from self._grasp(grasp, out, alternatives)
            out.success = True
            self._enter(out, GraspStage.DONE)
            if place and self.tray_center is not None:
                self._enter(out, GraspStage.PLACE)
                yield from self._place(out)
                out.placed = True
        except GraspPipelineError as exc:
            out.failed_stage = self.stage.value if self.stage else None
            out.message = f"{out.failed_stage} failed: {exc}"
            log.error("grasp %s", out.message)
            out.release_time_s = float(self.rt.world.time_s)
            yield from self._recover()
        finally:
            self.stage = None
        return out

    def _lingering_tids(self) -> set:
        """Tracks of picked objects still standing where the object was (a NADIR track
        outlives its object by ``nadir_hold_s``): phantoms, not obstacles. A picked object's
        track that the tracker has since moved onto another object is that object now."""
        out = set()
        for t in self.loop.tracks():
            xy = self.picked_at.get(t.tid)
            if xy is not None and float(np.linalg.norm(np.asarray(t.smoothed.center[:2]) - xy)) \
                    <= self.config.fragment_margin_m:
                out.add(t.tid)
        return out

    def _finger_on_object(self, robot_geom: str, other: str) -> bool:
        return FINGER_GEOM_MARK in robot_geom and other.startswith(OBJECT_GEOM_PREFIX)

    def _holding(self, robot_geom: str, other: str) -> bool:
        """While carrying: the held object may touch any part of the hand (it can tilt
        against the palm); every other contact is unexpected."""
        return other in self._held

    def _opening(self, grasp) -> float:
        return min(GRIPPER_MAX_WIDTH_M, float(grasp.width_m) + self.config.open_margin_m)

    def _plan_approach(self, candidates):
        """Plan PRE_GRASP and APPROACH (without moving) for the first candidate grasp that
        works; returns (grasp, pre-grasp trajectory, approach trajectory, TCP grasp pose)."""
        world, motion = self.rt.world, self.motion
        errors = []
        tries = [(g, b) for g in candidates for b in self.config.approach_backoffs_m]
        for k, (g, backoff) in enumerate(tries):
            T_grasp = tcp_pose_from_grasp(g, world.tcp_pose())
            T_grasp[:3, 3] -= backoff * np.asarray(g.R)[:, 0]
            T_pre = T_grasp.copy()
            T_pre[:3, 3] -= self.config.pre_grasp_distance_m * np.asarray(g.R)[:, 0]
            motion.planner.set_finger_opening(max(self._opening(g), world.finger_gap_m))
            try:
                traj_pre = motion.plan_pose(T_pre)
                traj_app = motion.plan_line(T_grasp, q_from=traj_pre.q[-1], allow_target_contact=True)
            except MotionError as exc:
                errors.append(f"grasp {k + 1} (backoff {backoff * 1e3:.0f} mm): {exc}")
                log.info("grasp try %d of %d not plannable: %s", k + 1, len(tries), exc)
                continue
            if k:
                log.info("using grasp try %d: candidate %d, %.0f mm above the contact point",
                         k + 1, candidates.index(g) + 1, backoff * 1e3)
            self._backoff_m = backoff
            return g, traj_pre, traj_app, T_grasp
        raise StageFailure("no grasp candidate can be reached: " + " | ".join(errors))

    def _grasp(self, grasp, out: GraspOutcome, alternatives=()):
        cfg, world, motion = self.config, self.rt.world, self.motion
        candidates = [grasp, *alternatives]
        # Perceived scene at the moment of the grasp; the target box is no obstacle.
        scene = snapshot(self.loop, self.loop.latest.q if self.loop.latest else None,
                         exclude_tids=self._lingering_tids())
        target_tid = None
        if scene.boxes:  # the target is the tracked object under the grasp
            d = [np.linalg.norm(b.center[:2] - np.asarray(grasp.position)[:2]) for b in scene.boxes]
            target_tid = scene.tids[int(np.argmin(d))]
            scene = without_fragments(scene, target_tid, cfg.fragment_margin_m)
        motion.set_scene(scene.environment_points, scene.boxes, scene.capture_q,
                         target_index=scene.index_of(target_tid) if target_tid is not None else None)
        self._target_tid = target_tid
        idx = scene.index_of(target_tid) if target_tid is not None else None
        self._target_height_m = None if idx is None else float(scene.boxes[idx].extents[2])
        self._enter(out, GraspStage.PRE_GRASP)
        grasp, traj_pre, traj_app, T_grasp = self._plan_approach(candidates)
        approach = np.asarray(grasp.R)[:, 0]
        out.width_m = float(grasp.width_m)
        opening = self._opening(grasp)
        world.set_gripper(opening, effort_N=cfg.close_effort_N)
        yield from motion.execute("pre_grasp", traj_pre)
        yield from self._wait_gripper(opening)

        self._enter(out, GraspStage.APPROACH)
        yield from motion.execute("approach", traj_app, contact_ok=self._finger_on_object)

        self._enter(out, GraspStage.CLOSE)
        out.stall_gap_m = yield from self._close(float(grasp.width_m))
        self._held = {o for r, o in world.robot_contacts() if self._finger_on_object(r, o)}
        if not self._held:
            raise StageFailure(f"fingers stalled at {out.stall_gap_m * 1e3:.1f} mm but touch no object")
        motion.planner.set_finger_opening(out.stall_gap_m)
        if self._target_tid is not None:
            k = scene.index_of(self._target_tid)
            if k is not None:
                self.picked_at[self._target_tid] = np.asarray(scene.boxes[k].center[:2], float).copy()

        self._enter(out, GraspStage.LIFT)
        T_lift = T_grasp.copy()
        T_lift[:3, 3] -= cfg.lift_height_m * approach
        yield from motion.line(T_lift, kind="lift", allow_target_contact=True, contact_ok=self._holding)
        t_end = world.time_s + cfg.hold_check_s
        while world.time_s < t_end:
            gap = world.finger_gap_m
            if gap < out.stall_gap_m - cfg.held_gap_drop_m:
                raise StageFailure(f"object lost after lifting: finger gap fell from "
                                   f"{out.stall_gap_m * 1e3:.1f} to {gap * 1e3:.1f} mm")
            yield

    def _wait_gripper(self, gap_m: float):
        cfg, world = self.config, self.rt.world
        t_end = world.time_s + cfg.close_timeout_s
        while abs(world.finger_gap_m - gap_m) > cfg.gripper_goal_tolerance_m:
            if world.time_s >= t_end:
                raise StageFailure(f"gripper did not reach {gap_m * 1e3:.1f} mm "
                                   f"(at {world.finger_gap_m * 1e3:.1f} mm)")
            yield

    def _close(self, width_m: float):
        """Close until the fingers stall on the object; return the stall gap [m]."""
        cfg, world = self.config, self.rt.world
        cmd = max(0.0, 2.0 * cfg.close_command_fraction * width_m - cfg.close_squeeze_m)
        world.set_gripper(cmd, effort_N=cfg.close_effort_N)
        t0 = world.time_s
        slow_since = None
        while True:
            yield
            gap, speed = world.finger_gap_m, abs(world.finger_speed_mps)
            if abs(gap - cmd) <= cfg.gripper_goal_tolerance_m:
                raise StageFailure(f"fingers reached the commanded {cmd * 1e3:.1f} mm without "
                                   "stalling on the object (missed or much narrower)")
            if speed < cfg.stall_speed_mps and world.time_s - t0 > cfg.stall_time_s:
                slow_since = world.time_s if slow_since is None else slow_since
                if world.time_s - slow_since >= cfg.stall_time_s:
                    break
            else:
                slow_since = None
            if world.time_s - t0 > cfg.close_timeout_s:
                raise StageFailure(f"close timed out after {cfg.close_timeout_s} s "
                                   f"(gap {gap * 1e3:.1f} mm)")
        gap = world.finger_gap_m
        if gap < cfg.fully_closed_gap_m:
            raise StageFailure(f"gripper fully closed ({gap * 1e3:.1f} mm): missed the object")
        log.info("closed: stalled at %.1f mm (measured width %.1f mm)", gap * 1e3, width_m * 1e3)
        return gap

    def _place(self, out: GraspOutcome):
        """Carry above a tray slot, lower the object until its bottom is ``place_clearance_m``
        above the tray floor (its measured height tells where its bottom is), open, go up."""
        cfg, world, motion = self.config, self.rt.world, self.motion
        slot = self.tray_center + tray_slot(self.placed_count, cfg.place_slot_dx_m, cfg.place_slot_dy_m)
        # The fingers close along world x at the tray, so they stay clear of its walls.
        T_above = np.eye(4)
        T_above[:3, :3] = _closing_along_x(world.tcp_pose())
        T_above[:3, 3] = slot + np.array([0.0, 0.0, cfg.place_height_m])
        motion.set_target(None)
        # The planner does not model the object in the hand: first go straight up to the carry
        # height, so the object hangs well above its neighbours while the arm swings over.
        plane_z = self.loop.plane.height_m if self.loop.plane is not None else float(slot[2])
        T_up = world.tcp_pose().copy()
        if T_up[2, 3] < plane_z + cfg.carry_height_m:
            T_up[2, 3] = plane_z + cfg.carry_height_m
            try:
                yield from motion.line(T_up, kind="carry_up", allow_target_contact=True,
                                       contact_ok=self._holding)
            except GraspPipelineError as exc:  # e.g. a wrist joint near a singularity on the line
                log.warning("carry_up line not plannable (%s); planning a joint-space motion to "
                            "the same pose instead", exc)
                motion.sync()
                yield from motion.to_pose(T_up, frame="tcp", kind="carry_up",
                                          contact_ok=self._holding)
        yield from motion.to_pose(T_above, frame="tcp", kind="place", contact_ok=self._holding)
        if self._target_height_m is not None:
            z_release = (cfg.place_clearance_m + 0.5 * self._target_height_m + self._backoff_m)
            if z_release < cfg.place_height_m:
                T_down = T_above.copy()
                T_down[2, 3] = slot[2] + z_release
                try:
                    yield from motion.line(T_down, kind="place_down", contact_ok=self._holding)
                except GraspPipelineError as exc:  # a crowded tray: release from above instead
                    log.warning("could not lower the object into the tray (%s); releasing from "
                                "%.0f mm", exc, cfg.place_height_m * 1e3)
                    motion.sync()
        out.release_time_s = float(world.time_s)
        # Open only a little beyond the object: fully open fingers could reach the tray walls.
        release_gap = min(GRIPPER_MAX_WIDTH_M, (out.stall_gap_m or 0.0) + cfg.open_margin_m)
        world.set_gripper(release_gap, effort_N=cfg.close_effort_N)
        yield from wait_s(world, cfg.release_wait_s)
        self._held = set()
        self.placed_count += 1
        motion.planner.set_finger_opening(max(release_gap, world.finger_gap_m))
        if float(np.linalg.norm(world.tcp_pose()[:3, 3] - T_above[:3, 3])) > cfg.gripper_goal_tolerance_m:
            try:
                yield from motion.line(T_above, kind="place_up", contact_ok=self._finger_on_object)
            except GraspPipelineError as exc:
                log.warning("place_up not plannable (%s); escaping straight up", exc)
                motion.sync()
                yield from motion.escape_up(T_above[2, 3] - world.tcp_pose()[2, 3])
        if self.home_q is not None:
            yield from motion.to_joints(self.home_q, kind="home")

    def _recover(self):
        """Open, retreat upward, go home; each step best-effort (the arm is never left moving)."""
        cfg, world, motion = self.config, self.rt.world, self.motion
        world.set_gripper(GRIPPER_MAX_WIDTH_M, effort_N=cfg.close_effort_N)
        motion.sync()
        yield from wait_s(world, cfg.release_wait_s)
        self._held = set()
        motion.planner.set_finger_opening(GRIPPER_MAX_WIDTH_M)
        try:
            T = world.tcp_pose().copy()
            T[:3, 3] += cfg.retreat_height_m * np.asarray(self.loop.plane.n if self.loop.plane else [0, 0, 1.0])
            yield from motion.line(T, kind="retreat", allow_target_contact=True,
                                   contact_ok=self._finger_on_object)
        except GraspPipelineError as exc:
            log.warning("retreat not plannable (%s); escaping straight up", exc)
            motion.sync()
            try:
                yield from motion.escape_up(cfg.retreat_height_m)
            except GraspPipelineError as exc2:
                log.warning("escape failed: %s", exc2)
                motion.sync()
        if self.home_q is not None:
            try:
                yield from motion.to_joints(self.home_q, kind="home")
            except GraspPipelineError as exc:
                log.warning("return home failed: %s", exc)
                motion.sync()
