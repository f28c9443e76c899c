"""A fake robot implementing the protocols of grasp_pipeline.robot.protocols, and a fake
motion client: enough to drive the grasp action without any simulator.

The gripper moves its gap towards the command at a fixed speed; when an object of
``object_width_m`` lies between the fingers, closing stalls there and squeezes with the
commanded effort. ``slip_at_s``: from then on the object is gone (the fingers close on air).
``turn_at_s``/``turned_width_m``: from then on the object is that narrow (a rounded object
turning between the pads; the fingers follow it and keep squeezing).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from grasp_pipeline.robot.protocols import ContactAllowance

GRIPPER_SPEED_MPS = 0.1


class FakeRobot:
    def __init__(self, object_width_m: float | None = 0.05, slip_at_s: float | None = None,
                 squeeze_N: float | None = None, turn_at_s: float | None = None,
                 turned_width_m: float | None = None) -> None:
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

    # Clock
    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.time_s += self.timestep_s
            self._move_fingers()

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
        self._cmd = float(width_m)
        self._effort = 40.0 if effort_N is None else float(effort_N)
        self.gripper_commands.append(self._cmd)

    # Camera
    def camera_pose(self) -> np.ndarray:
        return self.tcp.copy()

    def add_frame_listener(self, listener) -> None:
        pass

    def remove_frame_listener(self, listener) -> None:
        pass

    # Contact monitor
    def unexpected_contacts(self, allowance: ContactAllowance) -> list[str]:
        return []


class FakeTrajectory:
    def __init__(self, T: np.ndarray, duration_s: float = 0.2) -> None:
        self.T = T
        self.q = np.zeros((2, 7))
        self.duration_s = duration_s


class FakeMotion:
    """Plans instantly; 'executes' by stepping the robot for the trajectory's duration."""

    def __init__(self, robot: FakeRobot, unreachable_kinds=()) -> None:
        self.robot = robot
        self.planner = SimpleNamespace(set_finger_opening=lambda m: None)
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
        return FakeTrajectory(np.asarray(T))

    def plan_line(self, T, q_from=None, frame="tcp", allow_target_contact=False):
        return FakeTrajectory(np.asarray(T))

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


def fake_loop():
    """A perception loop stand-in: a locked table plane at z = 0.2 m, no tracks."""
    plane = SimpleNamespace(n=np.array([0.0, 0.0, 1.0]), c=-0.2, height_m=0.2)
    return SimpleNamespace(tracks=lambda: [], plane=plane, latest=None, scene_cloud=lambda: None,
                           selector=SimpleNamespace(best_grasp=None),
                           report_if_stale=lambda now: False)
