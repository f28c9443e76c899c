"""The grasp action (method.md §7): PRE_GRASP → APPROACH → CLOSE → LIFT → DONE, then PLACE (ours).

Input: a list of candidate grasps (``_core.BestGrasp``: position = contact point, column 0
= approach into the object, column 2 = closing axis) from any
:class:`~grasp_pipeline.orchestration.grasping.source.GraspSource` — by default the latest
published best grasp (refused with "no best grasp yet" when there is none). The action never
learns who produced them.

- PRE_GRASP: plan (before any motion) pre-grasp + approach for the first candidate that
  works (:mod:`.grasp_planning`), open to width + margin, move to the pre-grasp.
- APPROACH: straight line to the contact point; only the fingers may touch objects.
- CLOSE: close until the fingers stall (:mod:`.gripper_moves`); a miss, a full close or a
  stall without squeeze force fails. Whether an object is held is judged from the gripper's
  own signals (gap, stall, force) — never from simulator contacts.
- LIFT: straight line up by ``lift_height_m``, then hold ``hold_check_s`` watching the gap.
- PLACE (:mod:`.place`): carry to a free spot of the tray, lower, release low, go up, look
  whether the object arrived, back to the start joints; a drop while carrying fails PLACE.
Any stage failure: open, retreat upward, go home; the result says which stage failed and why.
Each stage entry is published as a :class:`~.events.StageEvent`; the candidates and the one
chosen at PRE_GRASP as a :class:`~.events.GraspEvent`.
"""

from __future__ import annotations

import logging
from typing import Optional, Sequence

import numpy as np

from ...exceptions import GraspPipelineError
from ...motion.exceptions import StartStateInvalidError
from ...motion.work_cell import WorkCell
from ...results import GraspOutcome
from ...robot.description import GRIPPER_MAX_WIDTH_M
from ...robot.protocols import ContactAllowance
from ..config import GraspConfig
from ..events import EventBus, GraspEvent, StageEvent
from ..grasping.grasp import Grasp
from ..runtime import Runtime, Task
from ..scene.scene_model import snapshot
from ..scene.tracks import nearest_track
from .grasp_planning import NoReachableGrasp, PlannedGrasp, opening_for, plan_grasp
from .gripper_moves import (ObjectDropped, StageFailure, close_until_stall, hold_lost, lost_message,
                            wait_gap, watch_held)
from .place import place_in_tray, recover
from .place_config import PlaceConfig
from .stages import Stage

log = logging.getLogger("grasp_pipeline.grasp")

__all__ = ["GraspAction", "GraspStage", "StageFailure"]


#: the grasp action's stages are :class:`~.stages.Stage` members (PRE_GRASP … PLACE)
GraspStage = Stage


def grasp_summary(grasp, plane) -> dict:
    """What a report says of an executed grasp: its kind, tilt, score and source."""
    g = Grasp.of(grasp, plane_n=None if plane is None else np.asarray(plane.n, float))
    return {"kind": g.kind.value, "tilt_deg": round(float(g.tilt_deg), 1), "score": round(float(g.score), 3),
            "source": g.source, "width_m": round(float(g.width_m), 4)}


def held_points(scene, k: int) -> np.ndarray:
    """The points of object ``k`` of ``scene`` in the latest frame, each extended down to the
    table (2.5-D: what is seen from above extends down to what it stands on)."""
    from ..grasping.target_model import fill_columns

    own = np.asarray(scene.object_points[k], float).reshape(-1, 3) if k < len(scene.object_points) \
        else np.zeros((0, 3))
    if len(own) == 0 or scene.plane is None:
        return own
    n, c = np.asarray(scene.plane.n, float), float(scene.plane.c)
    h = own @ n + c
    return np.vstack([own, fill_columns(own, h, np.zeros((0, 3)), np.zeros(0), n, 0.01)])


class GraspAction:
    """Runs one grasp (and place) at a time as a runtime task, with stage feedback.

    ``runtime.world`` is the robot (clock, arm, gripper, contact monitor); ``loop`` the
    perception loop (scene and plane); ``motion`` the motion client; ``work_cell`` gives the
    tray to place into (None: no PLACE); ``home_q`` the joints to return to; ``place_config``
    the PLACE stage's parameters."""

    def __init__(self, runtime: Runtime, loop, motion, config: GraspConfig | None = None,
                 work_cell: Optional[WorkCell] = None, home_q: Optional[np.ndarray] = None,
                 events: Optional[EventBus] = None, place_config: PlaceConfig | None = None) -> None:
        self.rt = runtime
        self.loop = loop
        self.motion = motion
        self.config = config or GraspConfig()
        self.place_config = place_config or PlaceConfig()
        self.tray = None  # what it put into the tray (:class:`.tray.TrayContents`), from the first place
        self.work_cell = work_cell
        self.home_q = None if home_q is None else np.asarray(home_q, float)
        self.events = events if events is not None else EventBus()
        self.stage: Optional[Stage] = None
        self.task: Optional[Task] = None
        self.placed_count = 0
        # tracks of objects already lifted off the table → where they were lifted from [m]
        self.picked_at: dict[int, np.ndarray] = {}
        self._target_height_m: Optional[float] = None  # measured height of the object in hand
        self._target_tid: Optional[int] = None
        self._target_points: Optional[np.ndarray] = None  # the target as perceived at the grasp
        self.backoff_m = 0.0  # how far above the contact point the executed grasp stopped [m]
        self.tcp_height_m: Optional[float] = None  # TCP above the table at the grasp [m]
        self.held_points_tcp: Optional[np.ndarray] = None  # the held object's points, TCP frame

    @property
    def robot(self):
        return self.rt.world

    # ---- goal -------------------------------------------------------------------
    def start(self, grasp=None, place: bool = True, alternatives: Sequence = ()):
        """Start a grasp of ``grasp`` (default: the latest published best grasp), then the
        ``alternatives`` in order when it cannot be planned. Returns (accepted, message)."""
        if self.task is not None and not self.task.done:
            return False, f"grasp refused: a grasp is running (stage {self.stage})"
        if grasp is None:
            if self.loop.report_if_stale(self.robot.time_s):
                return False, "grasp refused: perception is stale (no recent camera frame)"
            grasp = self.loop.selector.best_grasp
        candidates = [g for g in (grasp, *alternatives) if g is not None]
        if not candidates:
            return False, "no best grasp yet"
        self.task = self.rt.start("grasp", self._run(candidates, place))
        return True, "grasp started"

    # ---- the task ---------------------------------------------------------------
    def _enter(self, out: GraspOutcome, stage: Stage) -> None:
        self.stage = stage
        t = round(float(self.robot.time_s), 4)
        out.stages.append((stage, t))
        log.info("grasp stage %s", stage)
        self.events.publish(StageEvent(t, stage, perception=self.loop))

    def _run(self, candidates: list, place: bool):
        out = GraspOutcome(width_m=float(candidates[0].width_m))
        try:
            yield from self._grasp(candidates, out)
            out.success = True
            self._enter(out, Stage.DONE)
            if place and self.work_cell is not None and self.work_cell.tray_center_m is not None:
                self._enter(out, Stage.PLACE)
                yield from place_in_tray(self, out)
                out.placed = True
        except GraspPipelineError as exc:
            out.failed_stage = self.stage
            if isinstance(exc, ObjectDropped):  # a drop while carrying: not picked
                out.success = False
            out.message = f"{out.failed_stage} failed: {exc}"
            log.error("grasp %s", out.message)
            out.release_time_s = float(self.robot.time_s)
            yield from recover(self)
        finally:
            self.stage = None
        return out

    def lingering_tids(self) -> set:
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

    def _set_scene(self, grasp) -> tuple[Optional[int], object]:
        """Perceived scene at the moment of the grasp; the target (the grasp's own
        ``target_tid``, else the track under the grasp) and its fragments are no obstacles.
        Returns (target tid, scene)."""
        scene = snapshot(self.loop, exclude_tids=self.lingering_tids())
        target_tid = getattr(grasp, "target_tid", None)
        if target_tid is not None and target_tid not in scene.tids:
            target_tid = None
        if scene.boxes and target_tid is None:  # a grasp that does not say: the track under it
            boxes_as_tracks = [t for t in self.loop.tracks() if t.tid in scene.tids]
            target, _ = nearest_track(boxes_as_tracks, np.asarray(grasp.position)[:2])
            target_tid = None if target is None else int(target.tid)
        if target_tid is not None:
            scene = scene.without_fragments(target_tid, self.config.fragment_margin_m)
        self.motion.set_scene(scene, target_tid)
        k = scene.index_of(target_tid)
        self._target_height_m = None if k is None else float(scene.boxes[k].extents[2])
        self._target_tid = target_tid
        self._target_points = None if k is None else held_points(scene, k)
        return target_tid, scene

    def _grasp(self, candidates: list, out: GraspOutcome):
        cfg, robot, motion = self.config, self.robot, self.motion
        self.held_points_tcp = None
        target_tid, scene = self._set_scene(candidates[0])
        self._enter(out, Stage.PRE_GRASP)
        plan = self._plan(candidates)
        self.backoff_m = plan.backoff_m
        plane = self.loop.plane
        self.tcp_height_m = None if plane is None else \
            float(np.asarray(plane.n, float) @ plan.T_grasp[:3, 3] + float(plane.c))
        out.width_m, out.candidate = float(plan.grasp.width_m), plan.index
        out.grasp = grasp_summary(plan.grasp, self.loop.plane)
        opening = opening_for(plan.grasp, cfg, GRIPPER_MAX_WIDTH_M)
        robot.set_gripper(opening, effort_N=cfg.close_effort_N)
        yield from wait_gap(robot, opening, cfg)  # the fingers as planned before the arm moves
        yield from motion.execute("pre_grasp", plan.pre_grasp)

        self._enter(out, Stage.APPROACH)
        yield from motion.execute("approach", plan.approach, ContactAllowance.FINGERS)

        self._enter(out, Stage.CLOSE)
        out.stall_gap_m = yield from close_until_stall(robot, float(plan.grasp.width_m), cfg)
        motion.planner.set_finger_opening(out.stall_gap_m)
        k = scene.index_of(target_tid)
        if k is not None:
            self.picked_at[target_tid] = np.asarray(scene.boxes[k].center[:2], float).copy()

        self._enter(out, Stage.LIFT)
        yield from self._lift(plan, out)
        yield from self._hold_check(out)
        self._attach_held(plan)

    def _lift(self, plan: PlannedGrasp, out: GraspOutcome):
        """Task: by ``lift_height_m`` along the table normal, whatever the approach (pulling
        back along a tilted approach would drag the object over the table); when the closed
        hand sits inside a neighbour's clearance (the line's start is refused), straight up
        without the check."""
        cfg, motion = self.config, self.motion
        T_lift = plan.T_grasp.copy()
        T_lift[:3, 3] += cfg.lift_height_m * self._up()
        held = ContactAllowance.HELD_OBJECT
        try:
            yield from self.carrying(motion.line(T_lift, kind="lift", allow_target_contact=True,
                                                 allowance=held), out, Stage.LIFT)
        except StartStateInvalidError as exc:
            log.warning("lift line refused (%s); lifting straight up", exc)
            yield from self.carrying(motion.escape_up(cfg.lift_height_m, kind="lift", allowance=held),
                                     out, Stage.LIFT)

    def _up(self) -> np.ndarray:
        """The table normal (world z before a plane is known)."""
        plane = self.loop.plane
        return np.array([0.0, 0.0, 1.0]) if plane is None else np.asarray(plane.n, dtype=float)

    def _attach_held(self, plan: PlannedGrasp) -> None:
        """Once lifted, the object moves with the hand in the planner's world: its perceived
        points at the grasp (what was seen, extended down to what it stood on) fixed to the
        hand at the grasp pose; no longer an obstacle where it stood."""
        self.held_points_tcp = None
        if self._target_points is None or not len(self._target_points):
            return
        T_inv = np.linalg.inv(plan.T_grasp)
        self.held_points_tcp = self._target_points @ T_inv[:3, :3].T + T_inv[:3, 3]
        name = f"object/{self._target_tid}"
        n = self.motion.attach(name, self._target_points, plan.T_grasp)
        log.info("holding %s: %d spheres attached to the hand in the planner's world", name, n)

    def _plan(self, candidates: list) -> PlannedGrasp:
        """:func:`plan_grasp` for the candidates; publishes a :class:`GraspEvent` (the chosen
        candidate, or none when :class:`NoReachableGrasp` is raised)."""
        robot = self.robot
        try:
            plan = plan_grasp(self.motion, candidates, self.config, robot.tcp_pose(),
                              GRIPPER_MAX_WIDTH_M)
        except NoReachableGrasp:
            if self.events.wants(GraspEvent):
                self.events.publish(GraspEvent(float(robot.time_s), tuple(candidates)))
            raise
        if self.events.wants(GraspEvent):
            self.events.publish(GraspEvent(float(robot.time_s), tuple(candidates), plan.index,
                                           plan.T_grasp.copy(), plan.backoff_m))
        return plan

    def carrying(self, motion_gen, out: GraspOutcome, stage: Stage):
        """Task: a motion with the object in hand, aborted when the object drops."""
        return (yield from watch_held(self.robot, motion_gen, out.stall_gap_m, self.config, stage))

    def _hold_check(self, out: GraspOutcome):
        cfg, robot = self.config, self.robot
        t_end = robot.time_s + cfg.hold_check_s
        while robot.time_s < t_end:
            if hold_lost(robot, out.stall_gap_m, cfg):
                raise StageFailure(lost_message(robot, out.stall_gap_m, "lost after lifting"))
            yield
