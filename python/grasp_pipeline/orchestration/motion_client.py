"""The orchestrator's handle on the motion layer: plan on the *perceived* scene, execute as
runtime tasks.

Obstacles come from perception only — the environment points of a frame taken at a known
arm pose (for the robot's self-filter) and the oriented boxes of the tracked objects —
plus the work cell's fixed furniture that is part of the robot's set-up (the tray's boxes,
from the work-cell description; never an object's pose). Every executed plan is published
as a :class:`~.events.PlanEvent`.
Motions are planned from the last *commanded* joints (the measured ones lag by ~1e-3 rad,
which can put a start state a fraction of a millimetre inside a clearance).
"""

from __future__ import annotations

import logging
from typing import Optional, Sequence

import numpy as np

from ..motion.executor import ExecutionReport, TrajectoryExecutor
from ..motion.motion_planner import MotionPlanner
from ..motion.object_points import PointModel
from ..motion.occupancy import OrientedBox
from ..motion.perceived_scene import PerceivedScene
from ..motion.trajectory import JointPath, JointTrajectory
from ..robot.protocols import ContactAllowance
from .events import EventBus, PlanEvent

log = logging.getLogger("grasp_pipeline.motion_client")

NONE = ContactAllowance.NONE


class MotionClient:
    """Plans with :class:`MotionPlanner` and executes with :class:`TrajectoryExecutor`."""

    def __init__(self, world, planner: MotionPlanner, fixtures: Sequence[OrientedBox] = (),
                 events: Optional[EventBus] = None) -> None:
        """``world``: the robot (clock, arm, contact monitor); ``fixtures``: the work cell's
        fixed obstacles (:attr:`grasp_pipeline.motion.work_cell.WorkCell.fixtures`)."""
        self.world = world
        self.planner = planner
        self.events = events if events is not None else EventBus()
        self.executor = TrajectoryExecutor(world, planner.config)
        self.fixtures = list(fixtures)
        self.q_cmd = np.asarray(world.q, dtype=float).copy()
        self.object_boxes: list[OrientedBox] = []
        self.plans: list[dict] = []  # log of every plan: kind, method, ms, duration

    # ---- scene ------------------------------------------------------------------
    def set_scene(self, scene: PerceivedScene, target_tid: Optional[int] = None) -> None:
        """Perceived obstacles; the box of track ``target_tid`` is the target (no obstacle); the
        other objects are modelled by their points where they were seen well enough, else by
        their boxes (:class:`~grasp_pipeline.motion.object_points.PointModel`)."""
        self.object_boxes = list(scene.boxes)
        tops = scene.object_tops(PointModel.from_motion(self.planner.config))
        self.planner.set_scene(scene.environment_points, self.object_boxes + self.fixtures,
                               capture_q=scene.capture_q, target_index=scene.index_of(target_tid),
                               object_tops=tops, plane=scene.plane)

    def set_target(self, target_index: Optional[int]) -> None:
        self.planner.set_target(target_index)

    # ---- motions (task generators returning an ExecutionReport) -------------------
    def plan_pose(self, T_world: np.ndarray, q_from: Optional[np.ndarray] = None,
                  frame: str = "tcp") -> JointTrajectory:
        """Plan (without moving) to a pose, from ``q_from`` (default: the commanded joints)."""
        return self.planner.plan_to_pose(self.q_cmd if q_from is None else q_from, T_world, frame)

    def plan_line(self, T_world: np.ndarray, q_from: Optional[np.ndarray] = None, frame: str = "tcp",
                  allow_target_contact: bool = False) -> JointTrajectory:
        """Plan (without moving) a straight TCP line from ``q_from``."""
        return self.planner.plan_cartesian(self.q_cmd if q_from is None else q_from, T_world, frame,
                                           allow_target_contact)

    def execute(self, kind: str, traj: JointTrajectory, allowance: ContactAllowance = NONE):
        """Task generator: run a planned trajectory (it must start at the commanded joints)."""
        return (yield from self._execute(kind, traj, allowance))

    def _execute(self, kind: str, traj: JointTrajectory, allowance: ContactAllowance = NONE,
                 release_contacts: bool = False):
        plan = {"kind": kind, "method": traj.path.method if traj.path else "",
                "planning_ms": traj.path.planning_ms if traj.path else 0.0,
                "timing_ms": traj.timing_ms, "duration_s": traj.duration_s}
        self.plans.append({**plan, "planning_cpu_ms": traj.path.cpu_ms if traj.path else 0.0})
        if self.events.wants(PlanEvent):
            self.events.publish(PlanEvent(float(self.world.time_s), **plan, trajectory=traj))
        report: ExecutionReport = yield from self.executor.execute_steps(
            traj, allowance, release_contacts=release_contacts)
        self.q_cmd = traj.q[-1].copy()
        return report

    def escape_up(self, distance_m: float, kind: str = "escape",
                  allowance: ContactAllowance = NONE):
        """Task generator: straight up by ``distance_m`` when the planner refuses to start
        (the arm sits inside a *clearance*, e.g. after opening the fingers near a wall).
        The short joint-space line to the IK solution above is not collision-checked against
        the clearance; contacts present at its start are tolerated (moving away from what
        stopped the arm), any new contact that ``allowance`` does not cover stops it."""
        T = self.world.tcp_pose().copy()
        T[2, 3] += max(0.0, float(distance_m))
        ik = self.planner.solve_ik(T, self.q_cmd, "tcp")
        path = JointPath(np.vstack([self.q_cmd, ik.q]), 0.0, "escape", 0, 0)
        traj = self.planner.timer.time_path(path)
        return (yield from self._execute(kind, traj, allowance, release_contacts=True))

    def sync(self) -> None:
        """After a stop, plan from where the arm actually is."""
        self.q_cmd = np.asarray(self.world.q, dtype=float).copy()

    def to_joints(self, q_goal: np.ndarray, kind: str = "joints", allowance: ContactAllowance = NONE,
                  release_contacts: bool = False):
        traj = self.planner.plan_to_joints(self.q_cmd, np.asarray(q_goal, dtype=float))
        return (yield from self._execute(kind, traj, allowance, release_contacts))

    def to_pose(self, T_world: np.ndarray, frame: str = "tcp", kind: str = "pose",
                allowance: ContactAllowance = NONE):
        traj = self.planner.plan_to_pose(self.q_cmd, T_world, frame)
        return (yield from self._execute(kind, traj, allowance))

    def line(self, T_world: np.ndarray, frame: str = "tcp", kind: str = "line",
             allow_target_contact: bool = False, allowance: ContactAllowance = NONE,
             release_contacts: bool = False):
        """Straight TCP line; ``allowance``: the contacts this motion expects;
        ``release_contacts``: contacts present at the start are tolerated (moving away)."""
        traj = self.planner.plan_cartesian(self.q_cmd, T_world, frame, allow_target_contact)
        return (yield from self._execute(kind, traj, allowance, release_contacts))
