"""A fake robot implementing the protocols of grasp_pipeline.robot.protocols, and a fake
motion client: enough to drive the grasp action without any simulator.

The gripper moves its gap towards the command at a fixed speed; when an object of
``object_width_m`` lies between the fingers, closing stalls there and squeezes with the
commanded effort. ``slip_at_s``: from then on the object is gone (the fingers close on air).
``turn_at_s``/``turned_width_m``: from then on the object is that narrow (a rounded object
turning between the pads; the fingers follow it and keep squeezing).

The camera: while frames are requested, every :data:`FRAME_STEPS` steps each frame listener
gets a frame whose points are the tray's floor (:data:`TRAY_FLOOR`) and the objects released
over it: opening the fingers wider than the held object over the tray leaves a box of
``object_width_m`` x ``object_width_m`` x ``object_height_m`` standing on the floor under the
TCP (unless ``released_vanish``: it falls out of view).
"""

from __future__ import annotations

from contextlib import contextmanager
from functools import lru_cache
from types import SimpleNamespace

import numpy as np

from grasp_pipeline.robot.protocols import ContactAllowance

GRIPPER_SPEED_MPS = 0.1
FRAME_STEPS = 16
#: The tray floor of the fakes: centre (x, y), half size, top height [m].
TRAY_FLOOR = (0.34, 0.58, 0.14, 0.2)


@lru_cache(maxsize=1)
def _planner_parts():
    """The robot model and the motion parameters the place stage reads from the planner."""
    from grasp_pipeline.motion.config import load_motion_config
    from grasp_pipeline.robot.description import load_robot_model

    return load_robot_model(), load_motion_config()


def _box_points(x: float, y: float, w: float, h: float, floor_z: float, step: float = 0.004) -> np.ndarray:
    g = np.arange(-0.5 * w, 0.5 * w + 1e-9, step)
    X, Y = np.meshgrid(x + g, y + g)
    return np.c_[X.ravel(), Y.ravel(), np.full(X.size, floor_z + h)]


class FakeRobot:
    def __init__(self, object_width_m: float | None = 0.05, slip_at_s: float | None = None,
                 squeeze_N: float | None = None, turn_at_s: float | None = None,
                 turned_width_m: float | None = None, object_height_m: float = 0.05,
                 released_vanish: bool = False) -> None:
        self.time_s = 0.0
        self.timestep_s = 0.002
        self.q = np.zeros(7)
        self.qd = np.zeros(7)
        self.finger_gap_m = 0.08
        self.finger_speed_mps = 0.0
        self.gripper_force_N = 0.0
        self.object_width_m = object_width_m
        self.slip_at_s = slip_at_s
        self.turn_at_s, self.turned_width_m = turn_at_s, turned_width_m
        self.squeeze_N = squeeze_N  # force reported at a stall (default: the effort)
        self._cmd, self._effort = 0.08, 40.0
        self.tcp = np.eye(4)
        self.tcp[:3, :3] = np.diag([1.0, -1.0, -1.0])
        self.tcp[:3, 3] = [0.5, 0.0, 0.5]
        self.gripper_commands: list[float] = []
        self.object_height_m = object_height_m
        self.released_vanish = released_vanish
        self.released: list[tuple[float, float, float, float]] = []  # (x, y, width, height)
        self._frame_requests = 0
        self._listeners: list = []
        self._steps = 0

    # Clock
    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.time_s += self.timestep_s
            self._move_fingers()
            self._steps += 1
            if self._frame_requests and self._steps % FRAME_STEPS == 0:
                frame = SimpleNamespace(points_world=self.scene_points(), time_s=self.time_s)
                for listener in list(self._listeners):
                    listener(frame)

    def scene_points(self) -> np.ndarray:
        """What the camera sees: the tray floor and the objects released over it."""
        cx, cy, half, z = TRAY_FLOOR
        pts = [_box_points(cx, cy, 2.0 * half, 0.0, z)]
        pts += [_box_points(x, y, w, h, z) for x, y, w, h in self.released]
        return np.vstack(pts)

    def _move_fingers(self) -> None:
        if self.slip_at_s is not None and self.time_s >= self.slip_at_s:
            self.object_width_m = None
        if self.turn_at_s is not None and self.time_s >= self.turn_at_s and self.object_width_m \
                and self.object_width_m != self.turned_width_m:
            self.object_width_m = self.turned_width_m
            if self.finger_gap_m > self.object_width_m:  # the pads follow the turning object
                self.finger_gap_m = self.object_width_m
        target = self._cmd
        blocked = self.object_width_m is not None and target < self.object_width_m <= self.finger_gap_m + 1e-9
        if blocked:
            target = self.object_width_m
        step = GRIPPER_SPEED_MPS * self.timestep_s
        diff = target - self.finger_gap_m
        move = diff if abs(diff) <= step else np.sign(diff) * step
        self.finger_gap_m += move
        self.finger_speed_mps = 0.5 * move / self.timestep_s
        at_object = blocked and abs(self.finger_gap_m - self.object_width_m) < 1e-9
        self.gripper_force_N = (self._effort if self.squeeze_N is None else self.squeeze_N) if at_object else 0.0

    # Arm
    def follow_trajectory(self, t_s, q, qd=None, start_time_s=None) -> float:
        return self.time_s + float(np.asarray(t_s)[-1])

    def reference(self):
        return self.q, np.zeros(7)

    def hold(self, q=None) -> None:
        pass

    def tcp_pose(self) -> np.ndarray:
        return self.tcp.copy()

    # Gripper
    def set_gripper(self, width_m: float, effort_N=None, speed_mps=None) -> None:
        cx, cy, half, _ = TRAY_FLOOR
        over_tray = abs(self.tcp[0, 3] - cx) <= half and abs(self.tcp[1, 3] - cy) <= half
        w = self.object_width_m
        if over_tray and w is not None and width_m > self.finger_gap_m + 1e-3 and not self.released_vanish:
            self.released.append((float(self.tcp[0, 3]), float(self.tcp[1, 3]), w, self.object_height_m))
        self._cmd = float(width_m)
        self._effort = 40.0 if effort_N is None else float(effort_N)
        self.gripper_commands.append(self._cmd)

    # Camera
    def camera_pose(self) -> np.ndarray:
        return self.tcp.copy()

    def add_frame_listener(self, listener) -> None:
        self._listeners.append(listener)

    def remove_frame_listener(self, listener) -> None:
        if listener in self._listeners:
            self._listeners.remove(listener)

    @contextmanager
    def request_frames(self):
        self._frame_requests += 1
        try:
            yield
        finally:
            self._frame_requests -= 1

    @property
    def looking_time_s(self) -> float:
        return self.time_s

    # Contact monitor
    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        return []


class FakeTrajectory:
    def __init__(self, T: np.ndarray, duration_s: float = 0.2) -> None:
        self.T = np.array(T, dtype=float)  # a copy: the caller may reuse its matrix (as a bisection does)
        self.q = np.zeros((2, 7))
        self.duration_s = duration_s


class FakeMotion:
    """Plans instantly; 'executes' by stepping the robot for the trajectory's duration.

    ``lines_blocked_below_z_m``: straight lines ending lower than this are refused (as the
    planner refuses what comes within a clearance); ``stop_kinds``: {kind: fraction} — the
    first execution of that kind stops (an ``ExecutionError``, e.g. a contact) at that
    fraction of its way."""

    def __init__(self, robot: FakeRobot, unreachable_kinds=()) -> None:
        self.robot = robot
        model, config = _planner_parts()
        # the fake's forward kinematics: the TCP stands q[0] high (what a stop's joints say)
        ik = SimpleNamespace(fk_tcp=lambda q: np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, q[0]], [0, 0, 0, 1.0]]))
        self.planner = SimpleNamespace(set_finger_opening=lambda m: None, model=model, config=config, ik=ik)
        self.lines_blocked_below_z_m = -np.inf
        self.poses_blocked_below_z_m = -np.inf  # joint-space goals lower than this are refused
        self.stop_kinds: dict[str, float] = {}
        self.stop_held_up_m: dict[str, float] = {}  # {kind: m}: that stop is the arm not following, held up this much
        self.obstacles: dict = {}
        self.executed: list[tuple[str, ContactAllowance]] = []
        self.unreachable_kinds = set(unreachable_kinds)
        self.refused_lines: set[str] = set()  # line kinds refused as starting in a clearance
        self.escapes: list[str] = []
        self.gap_at_start: dict[str, float] = {}  # finger gap when each kind of motion first started
        self.scene = None
        self.q_cmd = np.zeros(7)

    def set_scene(self, scene, target_tid=None) -> None:
        self.scene = scene

    def set_target(self, index) -> None:
        pass

    def sync(self) -> None:
        pass

    def plan_pose(self, T, q_from=None, frame="tcp"):
        if np.asarray(T)[2, 3] < self.poses_blocked_below_z_m:
            from grasp_pipeline.motion.exceptions import PlanningFailedError

            raise PlanningFailedError("pose within a clearance (fake)")
        return FakeTrajectory(np.asarray(T))

    def plan_line(self, T, q_from=None, frame="tcp", allow_target_contact=False):
        if np.asarray(T)[2, 3] < self.lines_blocked_below_z_m:
            from grasp_pipeline.motion.exceptions import CartesianPathError

            raise CartesianPathError("Cartesian line blocked (fake)")
        return FakeTrajectory(np.asarray(T))

    def add_obstacle(self, name, box, tops=None) -> None:
        self.obstacles[name] = (box, tops)

    def remove_obstacle(self, name) -> None:
        self.obstacles.pop(name, None)

    def plan_approach(self, T_grasp, T_pre):
        return FakeTrajectory(np.asarray(T_pre)), FakeTrajectory(np.asarray(T_grasp))

    def set_touchable(self, name) -> None:
        self.touchable = name

    def attach(self, name, points_world, T_world_tcp) -> int:
        self.attached = name
        return len(points_world)

    def detach(self):
        name, self.attached = getattr(self, "attached", None), None
        return name

    def trim_held(self) -> int:
        return 0

    def execute(self, kind, traj, allowance=ContactAllowance.NONE):
        from grasp_pipeline.motion.exceptions import PlanningFailedError

        if kind in self.unreachable_kinds:
            raise PlanningFailedError(f"{kind}: no path (fake)")
        self.executed.append((kind, allowance))
        self.gap_at_start.setdefault(kind, self.robot.finger_gap_m)
        t_end = self.robot.time_s + traj.duration_s
        while self.robot.time_s < t_end:
            self.robot.step()
            yield
        stop = self.stop_kinds.pop(kind, None)
        if stop is not None:
            from grasp_pipeline.motion.exceptions import ExecutionError

            self.robot.tcp[:3, 3] += stop * (np.asarray(traj.T, float)[:3, 3] - self.robot.tcp[:3, 3])
            held_up = self.stop_held_up_m.pop(kind, None)
            if held_up is not None:
                raise ExecutionError(f"execution stopped: tracking error (fake) in {kind}", reason="tracking",
                                     time_s=self.robot.time_s, q_commanded=np.zeros(7),
                                     q_measured=np.r_[held_up, np.zeros(6)])
            raise ExecutionError(f"execution stopped: unexpected robot contact (fake) in {kind}",
                                 reason="contact", time_s=self.robot.time_s)
        self.robot.tcp = np.asarray(traj.T, float).copy()
        return None

    def line(self, T, frame="tcp", kind="line", allow_target_contact=False, allowance=ContactAllowance.NONE,
             release_contacts=False):
        if kind in self.refused_lines:
            from grasp_pipeline.motion.exceptions import StartStateInvalidError

            raise StartStateInvalidError(f"{kind}: start state is invalid (fake)")
        return (yield from self.execute(kind, FakeTrajectory(np.asarray(T)), allowance))

    def to_pose(self, T, frame="tcp", kind="pose", allowance=ContactAllowance.NONE):
        return (yield from self.execute(kind, FakeTrajectory(np.asarray(T)), allowance))

    def to_joints(self, q, kind="joints", allowance=ContactAllowance.NONE, release_contacts=False):
        return (yield from self.execute(kind, FakeTrajectory(self.robot.tcp), allowance))

    def escape_up(self, distance_m, kind="escape", allowance=ContactAllowance.NONE):
        T = self.robot.tcp.copy()
        T[2, 3] += distance_m
        self.escapes.append(kind)
        return (yield from self.execute(kind, FakeTrajectory(T), allowance))


class FakeLoop:
    """A perception loop stand-in: a locked table plane at z = 0.2 m, no tracks; the points of
    the frames it gets (:meth:`on_frame`, a frame listener of the fake robot) except while it
    is told that the camera looks elsewhere."""

    def __init__(self) -> None:
        self.plane = SimpleNamespace(n=np.array([0.0, 0.0, 1.0]), c=-0.2, height_m=0.2)
        self.band_m = 0.01  # the scene filter's band above it
        self.latest = None
        self.frames = 0
        self.selector = SimpleNamespace(best_grasp=None)
        self.elsewhere = 0

    def tracks(self) -> list:
        return []

    def scene_cloud(self):
        return None

    def report_if_stale(self, now) -> bool:
        return False

    def on_frame(self, frame) -> None:
        if self.elsewhere:
            return
        self.latest = SimpleNamespace(result=SimpleNamespace(points=frame.points_world))
        self.frames += 1

    @contextmanager
    def looking_elsewhere(self):
        self.elsewhere += 1
        try:
            yield
        finally:
            self.elsewhere -= 1


def fake_loop(robot: FakeRobot | None = None) -> FakeLoop:
    """A :class:`FakeLoop`, listening to ``robot``'s frames when given."""
    loop = FakeLoop()
    if robot is not None:
        robot.add_frame_listener(loop.on_frame)
    return loop
