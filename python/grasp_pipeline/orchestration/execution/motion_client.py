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

from ...motion.exceptions import GoalInCollisionError, MotionError, PlanningFailedError
from ...motion.executor import ExecutionReport, TrajectoryExecutor
from ...motion.motion_planner import MotionPlanner
from ...motion.occupancy import OrientedBox
from ...motion.perceived_scene import PerceivedScene
from ...motion.planning_world import PERCEIVED_PREFIX, PlanningWorld
from ...motion.trajectory import JointPath, JointTrajectory
from ...robot.protocols import ContactAllowance
from ..events import EventBus, PlanEvent

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
        self.planning_world = PlanningWorld(planner, fixtures)
        self.q_cmd = np.asarray(world.q, dtype=float).copy()
        self.plans: list[dict] = []  # log of every plan: kind, method, ms, duration

    # ---- scene ------------------------------------------------------------------
    def set_scene(self, scene: PerceivedScene, target_tid: Optional[int] = None) -> None:
        """Perceived obstacles (:meth:`PlanningWorld.set_perceived`); the hand may touch the
        object of track ``target_tid`` (the grasp target); the other objects are modelled by
        their points where they were seen well enough, else by their boxes."""
        pw = self.planning_world
        pw.set_perceived(scene)
        pw.allow_touching(None if target_tid is None or target_tid not in scene.tids
                          else f"{PERCEIVED_PREFIX}{target_tid}")
        pw.commit()

    def set_touchable(self, name: Optional[str]) -> None:
        """The object the hand may touch (None: none) — pushed to the planner at once."""
        self.planning_world.allow_touching(name)
        self.planning_world.commit()

    def attach(self, name: str, points_world: np.ndarray, T_world_tcp: np.ndarray) -> int:
        """The hand holds the object ``name`` (its points at the TCP pose ``T_world_tcp``):
        it moves with the hand in the planner's world (:meth:`PlanningWorld.attach`)."""
        n = self.planning_world.attach(name, points_world, T_world_tcp)
        self.planning_world.commit()
        return n

    def trim_held(self) -> int:
        """Drop the parts of the held object's model that lie inside obstacles where the arm
        holds it now (:meth:`PlanningWorld.trim_attached`); returns how many spheres."""
        n = self.planning_world.trim_attached(self.q_cmd)
        if n:
            self.planning_world.commit()
        return n

    def detach(self) -> Optional[str]:
        """The hand holds nothing any more; returns what it held (None: nothing)."""
        name = self.planning_world.detach()
        if name is not None:
            self.planning_world.commit()
        return name

    def add_obstacle(self, name: str, box: OrientedBox, tops: Optional[np.ndarray] = None) -> None:
        """A named obstacle the robot knows of without seeing it now (e.g. what it placed):
        its ``box``, or its column ``tops`` when given (:meth:`PlanningWorld.add_object`)."""
        self.planning_world.add_object(name, box, tops)
        self.planning_world.commit()

    def remove_obstacle(self, name: str) -> None:
        """Forget the named obstacle (e.g. an object no longer where it was placed)."""
        self.planning_world.remove_object(name)
        self.planning_world.commit()

    # ---- motions (task generators returning an ExecutionReport) -------------------
    def plan_pose(self, T_world: np.ndarray, q_from: Optional[np.ndarray] = None,
                  frame: str = "tcp") -> JointTrajectory:
        """Plan (without moving) to a pose, from ``q_from`` (default: the commanded joints)."""
        return self.planner.plan_to_pose(self.q_cmd if q_from is None else q_from, T_world, frame)

    def plan_joints(self, q_goal: np.ndarray, q_from: Optional[np.ndarray] = None) -> JointTrajectory:
        """Plan (without moving) to joints ``q_goal`` from ``q_from`` (default: the commanded joints)."""
        return self.planner.plan_to_joints(self.q_cmd if q_from is None else q_from,
                                           np.asarray(q_goal, dtype=float))

    def plan_approach(self, T_grasp: np.ndarray, T_pre: np.ndarray,
                      tries: int = 3) -> tuple[JointTrajectory, JointTrajectory]:
        """(pre-grasp trajectory, approach trajectory) of one grasp pose, planned without moving.

        The approach line is planned first, *backwards*: from an IK solution of the grasp pose
        along the straight line to the pre-grasp pose ``T_pre`` (each step seeded by the
        previous one), so the whole approach stays on one IK branch — planning the pre-grasp
        first could land on another branch than the grasp's (a tilted approach then needs a
        joint jump on the way in). Then the joint-space motion from the commanded joints to the
        line's start (valid without target contact). Up to ``tries`` collision-free grasp
        solutions (target contact allowed), nearest the commanded joints first."""
        planner, v = self.planner, self.planner.validator
        sols = planner.solve_ik(T_grasp, self.q_cmd, "tcp").solutions
        with _target_contact(v):
            ok = v.check_batch(sols)
        if not np.any(ok):
            raise GoalInCollisionError(f"all {len(sols)} IK solutions of the grasp pose collide; "
                                       f"nearest: {v.explain(sols[0])}")
        errors = []
        for q_g in sols[ok][:tries]:
            try:
                back = planner.plan_path_cartesian(q_g, T_pre, "tcp", allow_target_contact=True)
                q_pre = back.waypoints[-1]
                if not v.is_valid(q_pre):
                    raise GoalInCollisionError(f"pre-grasp state invalid: {v.explain(q_pre)}")
                traj_pre = self.plan_joints(q_pre)
            except MotionError as exc:
                errors.append(str(exc))
                continue
            path = JointPath(back.waypoints[::-1].copy(), back.planning_ms, "cartesian", 0,
                             back.checked_states, back.cpu_ms)
            return traj_pre, planner.time_path(path, allow_target_contact=True)
        raise PlanningFailedError("no approach to the grasp pose: " + " | ".join(errors))

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


class _target_contact:
    """``with _target_contact(validator):`` — target contact allowed inside."""

    def __init__(self, validator) -> None:
        self.v = validator

    def __enter__(self):
        self.prev = self.v.allow_target_contact
        self.v.allow_target_contact = True

    def __exit__(self, *exc):
        self.v.allow_target_contact = self.prev
        return False
