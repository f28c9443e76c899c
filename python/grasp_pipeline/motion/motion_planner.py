"""One entry point for the orchestrator: scene in, timed collision-free trajectories out.

``MotionPlanner`` owns the robot model pieces (sphere model, IK, TOPP-RA timer) and the
current perceived scene (occupancy map + object boxes). Typical use::

    mp = MotionPlanner()                                   # config/motion.yaml
    mp.set_scene(scene.environment_points, scene.object_boxes, capture_q=scene.capture_q)
    traj = mp.plan_to_joints(world.q, q_goal)             # JointTrajectory
    traj = mp.plan_to_pose(world.q, T_world_tcp)          # IK (nearest valid) + plan
    mp.set_target(box_index)                               # the grasp target is no obstacle
    traj = mp.plan_cartesian(q, T_tcp_grasp, allow_target_contact=True)

Every returned trajectory has been re-checked at its TOPP-RA samples (so the spline's
deviation from the checked polyline cannot clip an obstacle).
"""

from __future__ import annotations

import logging
import time

import mujoco
import numpy as np

from ..array_rows import rows_where
from ..robot import description as rm
from .cartesian import CartesianPlanner
from .config import MotionConfig, load_motion_config
from .exceptions import EnvironmentCloudError, GoalInCollisionError, PlanningFailedError
from .ik import IKResult, PandaIK
from .object_points import ObjectPoints, columns
from .occupancy import OccupancyMap, OrientedBox, cell_rounding_m, cleared_cell_m, in_box
from .planner import JointPlanner
from .poses import validate_joints, validate_pose
from .robot_spheres import RobotSpheres
from .timing import TrajectoryTimer
from .trajectory import JointPath, JointTrajectory
from .validity import StateValidator

log = logging.getLogger(__name__)

#: Knot densification factor of the second timing attempt.
_DENSER_KNOTS = 5.0


class MotionPlanner:
    """IK + collision model + OMPL + Cartesian lines + TOPP-RA for one robot."""

    def __init__(self, config: MotionConfig | None = None, model: mujoco.MjModel | None = None) -> None:
        self.config = config if config is not None else load_motion_config()
        self.model = model if model is not None else rm.load_robot_model()
        cfg = self.config
        self.robot = RobotSpheres(self.model, cfg.sphere_cell_m, rm.GRIPPER_MAX_WIDTH_M,
                                  cfg.self_collision_margin_m)
        self.ik = PandaIK(cfg, self.model)
        self.validator = StateValidator(self.robot, cfg)
        self.joint_planner = JointPlanner(self.validator, cfg)
        self.cartesian = CartesianPlanner(self.ik, self.validator, cfg)
        self.timer = TrajectoryTimer(rm.PANDA_QD_MAX, rm.PANDA_QDD_MAX, cfg)
        self.env: OccupancyMap | None = None
        self.boxes: list[OrientedBox] = []
        self.object_tops: list = []
        self.plane = None
        self.target_index: int | None = None
        self.last_scene_ms = 0.0
        self._last_object_points: tuple | None = None

    # ------------------------------------------------------------------ scene
    def set_scene(self, environment_points: np.ndarray, object_boxes: list[OrientedBox] | None = None,
                  capture_q: np.ndarray | None = None, target_index: int | None = None,
                  object_tops: list | None = None, plane=None) -> OccupancyMap:
        """Build the occupancy map from perceived environment points; keep the object boxes.

        ``object_tops``: per box (same order), the column tops of an object modelled by its
        points (:mod:`.object_points`, on the grid of half a voxel; empty: no obstacle) or None
        (modelled by its box); ``plane``: the table (``n``, ``c``) the columns reach down to (None: tops only).

        ``capture_q``: arm joints when the points were captured — points inside the robot's
        own spheres (+ ``self_filter_padding_m``) at that state are dropped (the robot's
        self-filter). Raises EnvironmentCloudError for malformed or oversized clouds.
        """
        t0 = time.perf_counter()
        cfg = self.config
        pts = np.asarray(environment_points)
        if pts.size == 0:
            pts = np.zeros((0, 3))
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise EnvironmentCloudError(f"environment points must be an (N, 3) array, got shape {pts.shape}")
        if len(pts) > cfg.max_environment_points:
            raise EnvironmentCloudError(
                f"environment cloud has {len(pts)} points, over the limit of {cfg.max_environment_points} "
                "(motion.max_environment_points); down-sample it first")
        if capture_q is not None and len(pts):
            pts = self._self_filter(pts, validate_joints(capture_q, "capture joints"))
        self.env = OccupancyMap.from_points(pts, cfg.voxel_size_m, cfg.workspace_min_m, cfg.workspace_max_m,
                                            pad_m=self.validator.required_pad_m(),
                                            max_points=cfg.max_environment_points,
                                            max_voxels=cfg.max_grid_voxels)
        self.boxes = list(object_boxes or [])
        tops = list(object_tops or [])
        self.object_tops = tops + [None] * (len(self.boxes) - len(tops))
        self.plane = plane
        self.set_target(target_index)
        self.last_scene_ms = (time.perf_counter() - t0) * 1e3
        return self.env

    def set_objects(self, object_boxes: list[OrientedBox], object_tops: list | None = None,
                    target_index: int | None = None) -> None:
        """Replace the object boxes (and their column tops, same order) keeping the
        occupancy map of the last :meth:`set_scene`."""
        self.boxes = list(object_boxes)
        tops = list(object_tops or [])
        self.object_tops = tops + [None] * (len(self.boxes) - len(tops))
        self.set_target(target_index)

    def set_target(self, target_index: int | None) -> None:
        """Choose the grasp target among the object boxes (None: every box is an obstacle)."""
        if target_index is not None and not (0 <= target_index < len(self.boxes)):
            raise IndexError(f"target index {target_index} out of range ({len(self.boxes)} boxes)")
        self.target_index = target_index
        others = [i for i in range(len(self.boxes)) if i != target_index]
        obstacles = [self.boxes[i] for i in others if self.object_tops[i] is None]
        tops = [self.object_tops[i] for i in others if self.object_tops[i] is not None
                and len(self.object_tops[i])]
        target = self.boxes[target_index] if target_index is not None else None
        self.validator.set_scene(self.env, obstacles, target, self._object_points(tops))

    def _object_points(self, tops: list) -> ObjectPoints | None:
        """The columns under the non-target objects' tops, as the validator's point obstacles
        (the very object of the last call for the same tops, plane and reach, so that the
        validator keeps its collision scene)."""
        if not tops:
            return None
        cell = cleared_cell_m(self.config.voxel_size_m)
        pad = self.validator.required_points_pad_m(cell_rounding_m(cell))
        plane = None if self.plane is None else (np.array(self.plane.n, float), float(self.plane.c))
        last = self._last_object_points
        if last is not None and last[2] == pad and _same_tops(last[0], tops) and _same_plane(last[1], plane):
            return last[3]
        pts = np.vstack(tops)
        if plane is not None:
            pts = columns(pts, plane[0], plane[1], cell)
        made = ObjectPoints(pts, cell, pad)
        self._last_object_points = ([np.array(t, copy=True) for t in tops], plane, pad, made)
        return made

    def set_finger_opening(self, gap_m: float) -> None:
        """Finger gap assumed by the collision model (e.g. the object width while holding)."""
        self.robot.set_finger_opening(gap_m)

    def _self_filter(self, pts: np.ndarray, q: np.ndarray) -> np.ndarray:
        """The finite points ``pts`` (N, 3) outside the robot's spheres (+ the self-filter
        padding) with the arm at ``q``."""
        if not np.isfinite(pts).all():
            pts = pts[np.all(np.isfinite(pts), axis=1)]
        C = self.robot.centres(q[None])[0]
        r = self.robot.spheres.radius + self.config.self_filter_padding_m
        lo, hi = C.min(0) - r.max(), C.max(0) + r.max()
        near = in_box(pts, lo, hi)
        if not np.any(near) or not may_touch_spheres(rows_where(pts, near), C, r):
            return pts
        from scipy.spatial import cKDTree

        tree = cKDTree(pts[near])
        drop = np.zeros(int(near.sum()), dtype=bool)
        for idx in tree.query_ball_point(C, r):
            if idx:
                drop[idx] = True
        keep = np.ones(len(pts), dtype=bool)
        keep[np.nonzero(near)[0][drop]] = False
        return pts[keep]

    # ------------------------------------------------------------------ planning
    def solve_ik(self, T_world: np.ndarray, q_current: np.ndarray, frame: str = "tcp",
                 q7_samples: int | None = None) -> IKResult:
        """IK of a TCP or flange pose (:class:`~.ik.PandaIK`; ``q7_samples``: fewer samples of
        joint 7 for a quick reachability answer)."""
        if frame == "tcp":
            return self.ik.solve_tcp(T_world, q_current, q7_samples)
        return self.ik.solve_flange(T_world, q_current, q7_samples)

    def plan_path_to_joints(self, q_start: np.ndarray, q_goal: np.ndarray) -> JointPath:
        return self.joint_planner.plan(q_start, q_goal)

    def plan_to_joints(self, q_start: np.ndarray, q_goal: np.ndarray) -> JointTrajectory:
        """Collision-free timed trajectory from ``q_start`` to ``q_goal``."""
        return self.time_path(self.plan_path_to_joints(q_start, q_goal))

    def plan_path_to_pose(self, q_start: np.ndarray, T_world: np.ndarray, frame: str = "tcp") -> JointPath:
        """IK (all solutions, nearest first), then plan to the nearest collision-free one."""
        t0, c0 = time.perf_counter(), time.thread_time()
        validate_pose(T_world, f"{frame} target pose")
        res = self.solve_ik(T_world, q_start, frame)
        ok = self.validator.check_batch(res.solutions)
        if not np.any(ok):
            raise GoalInCollisionError(
                f"all {len(res.solutions)} IK solutions of the {frame} target collide; nearest: "
                f"{self.validator.explain(res.solutions[0])}")
        errors = []
        for q_goal in res.solutions[ok][:3]:
            try:
                p = self.joint_planner.plan(q_start, q_goal)
                return JointPath(p.waypoints, (time.perf_counter() - t0) * 1e3, p.method, p.attempts,
                                 p.checked_states, (time.thread_time() - c0) * 1e3)
            except PlanningFailedError as exc:
                errors.append(str(exc))
        raise PlanningFailedError("no path to any of the nearest collision-free IK solutions: "
                                  + " | ".join(errors))

    def plan_to_pose(self, q_start: np.ndarray, T_world: np.ndarray, frame: str = "tcp") -> JointTrajectory:
        return self.time_path(self.plan_path_to_pose(q_start, T_world, frame))

    def plan_path_cartesian(self, q_start: np.ndarray, T_goal: np.ndarray, frame: str = "tcp",
                            allow_target_contact: bool = False) -> JointPath:
        return self.cartesian.plan(q_start, T_goal, frame, allow_target_contact)

    def plan_cartesian(self, q_start: np.ndarray, T_goal: np.ndarray, frame: str = "tcp",
                       allow_target_contact: bool = False) -> JointTrajectory:
        """Timed straight-line motion of the TCP (or flange) to ``T_goal``."""
        path = self.plan_path_cartesian(q_start, T_goal, frame, allow_target_contact)
        return self.time_path(path, allow_target_contact)

    def time_path(self, path: JointPath, allow_target_contact: bool = False) -> JointTrajectory:
        """TOPP-RA timing + collision re-check of the timed samples.

        The smooth spline through the (densified) waypoints may cut a corner of the checked
        polyline. If a timed sample is invalid, the path is re-timed with 5x denser knots, and
        if that still fails, segment by segment (rest at each waypoint: exactly the polyline).
        """
        t0 = time.perf_counter()
        attempts = (lambda: self.timer.time_path(path),
                    lambda: self.timer.time_path(path, self.config.timing_waypoint_step_rad / _DENSER_KNOTS),
                    lambda: self.timer.time_path_stop_at_waypoints(path))
        for k, make in enumerate(attempts):
            traj = make()
            try:
                self.check_trajectory(traj, allow_target_contact)
            except PlanningFailedError:
                if k == len(attempts) - 1:
                    raise
                log.debug("timed trajectory leaves the checked path (attempt %d); re-timing", k + 1)
                continue
            if k:
                traj = JointTrajectory(traj.t_s, traj.q, traj.qd, traj.qdd,
                                       timing_ms=(time.perf_counter() - t0) * 1e3, path=traj.path)
            return traj
        raise AssertionError("unreachable")

    def check_trajectory(self, traj: JointTrajectory, allow_target_contact: bool = False) -> None:
        """Raise PlanningFailedError if a timed sample is invalid (checked at ≤ the dense step)."""
        q = traj.q
        if len(q) < 2:
            return
        step = np.max(np.abs(np.diff(q, axis=0)), axis=1)
        # pick samples so that consecutive checked samples differ by ≤ final_check_step_rad
        keep = [0]
        acc = 0.0
        for k in range(1, len(q)):
            acc += step[k - 1]
            if acc >= self.config.final_check_step_rad:
                keep.append(k)
                acc = 0.0
        keep.append(len(q) - 1)
        v = self.validator
        prev = v.allow_target_contact
        v.allow_target_contact = allow_target_contact
        try:
            ok = v.check_batch(q[np.unique(keep)])
            if not np.all(ok):
                bad = q[np.unique(keep)][int(np.argmin(ok))]
                raise PlanningFailedError(f"timed trajectory sample is invalid: {v.explain(bad)}")
        finally:
            v.allow_target_contact = prev


#: Cell [m] of the coarse grid that rules out points far from the robot's spheres.
_SELF_FILTER_CELL_M = 0.05
#: Slack [m] of that test: far above the rounding of any distance computed for the filter.
_SELF_FILTER_SLACK_M = 1e-6
#: Above this many candidate points the exact test is left to the k-d tree.
_SELF_FILTER_MAX_CANDIDATES = 20000


def may_touch_spheres(pts: np.ndarray, C: np.ndarray, r: np.ndarray) -> bool:
    """Whether a point of ``pts`` (N, 3) may lie within a sphere (centres ``C`` (S, 3), radii
    ``r`` (S,)). False is certain: every point is farther than its radius plus
    :data:`_SELF_FILTER_SLACK_M` from every centre — so a radius search finds nothing, and the
    self-filter keeps every point without building its k-d tree.

    Points outside the coarse cells that the spheres' grown boxes touch are that far (the
    boxes hold every point within a sphere's grown radius, and the rounded cell index of a
    point is monotone in it); the few others are measured against every sphere."""
    grow = r + _SELF_FILTER_SLACK_M
    h = _SELF_FILTER_CELL_M
    origin = C.min(0) - grow.max() - h
    lo = np.floor((C - grow[:, None] - origin) / h).astype(np.int64)
    hi = np.floor((C + grow[:, None] - origin) / h).astype(np.int64)
    dims = np.array([hi[:, j].max() for j in range(3)]) + 1
    marked = np.zeros(tuple(dims), dtype=bool)
    for a, b in zip(lo, hi):
        marked[a[0]:b[0] + 1, a[1]:b[1] + 1, a[2]:b[2] + 1] = True
    k = np.floor((pts - origin) / h).astype(np.int64)
    ok = in_box(k, np.zeros(3, dtype=np.int64), dims - 1)
    ok[ok] = marked.reshape(-1)[(k[ok, 0] * dims[1] + k[ok, 1]) * dims[2] + k[ok, 2]]
    cand = pts[ok]
    if len(cand) > _SELF_FILTER_MAX_CANDIDATES:
        return True
    for start in range(0, len(cand), 2000):
        d2 = np.sum((cand[start:start + 2000, None, :] - C[None]) ** 2, axis=-1)
        if np.any(d2 <= grow ** 2):
            return True
    return False


def _same_tops(a: list, b: list) -> bool:
    """Whether two lists of column-top arrays hold the same values."""
    return len(a) == len(b) and all(np.array_equal(x, np.asarray(y)) for x, y in zip(a, b))


def _same_plane(a: tuple | None, b: tuple | None) -> bool:
    """Whether two planes ((n, c) or None) are the same."""
    if a is None or b is None:
        return a is b
    return np.array_equal(a[0], b[0]) and a[1] == b[1]
