"""The side view before a pick (orchestration/scanning/side_view.py) with the fake robot, a
fake motion client whose IK reaches only part of the space, and a real scene volume fed
synthetic views."""

from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.motion.exceptions import UnreachablePoseError
from grasp_pipeline.orchestration.runtime import Runtime
from grasp_pipeline.orchestration.scanning.side_view import SideView, look_at_sides
from grasp_pipeline.perception.scene_volume import SceneVolume
from grasp_pipeline.perception.volume_config import VolumeConfig

from perception.synthetic_depth import K, look_at, render
from ..fake_robot import FakeMotion, FakeRobot

CUBE = ((0.45, -0.05, 0.20), (0.55, 0.05, 0.30))
CENTRE = np.array([0.5, 0.0, 0.25])
FRONT = look_at((0.2, 0.0, 0.45), CENTRE)
BACK = look_at((0.8, 0.0, 0.45), CENTRE)
FRAME_PERIOD_S = 1.0 / 30.0


class FakeLoop:
    """One cube track, a locked table, a real volume; a frame every 1/30 s of simulated time."""

    def __init__(self, robot: FakeRobot, views) -> None:
        self.robot = robot
        self.volume = SceneVolume()
        for T in views:
            self.volume.integrate(render(T, (CUBE,), 0.2), K, T)
        est = SimpleNamespace(center=CENTRE, R_box=np.eye(3), extents=np.array([0.1, 0.1, 0.1]))
        self.track = SimpleNamespace(tid=7, smoothed=est)
        self.plane = _core.Plane([0.0, 0.0, 1.0], -0.2)
        self.band_m = 0.01
        self.ready_camera_pose = FRONT
        self.latest = None

    @property
    def frames(self) -> int:
        return int(self.robot.time_s / FRAME_PERIOD_S)

    def tracks(self) -> list:
        return [self.track]

    def scene_cloud(self):
        return None


class ReachMotion(FakeMotion):
    """A fake motion client whose IK reaches flange positions up to ``reach_m`` from the base."""

    def __init__(self, robot, reach_m: float, unreachable_kinds=()):
        super().__init__(robot, unreachable_kinds)
        self.reach_m, self.ik_calls, self.ik_reach_m = reach_m, 0, []
        self.planner = SimpleNamespace(set_finger_opening=lambda m: None, solve_ik=self._ik,
                                       validator=SimpleNamespace(check_batch=lambda Q: np.ones(len(Q), bool)))
        self.poses = []

    def _ik(self, T, q, frame):
        assert frame == "flange"
        self.ik_calls += 1
        self.ik_reach_m.append(float(np.hypot(T[0, 3], T[1, 3])))
        if self.ik_reach_m[-1] > self.reach_m:
            raise UnreachablePoseError("too far (fake)")
        return SimpleNamespace(q=np.zeros(7), solutions=np.zeros((1, 7)))

    def to_pose(self, T, frame="tcp", kind="pose", allowance=None):
        self.poses.append((kind, np.asarray(T, float).copy()))
        return (yield from super().to_pose(T, frame, kind))


def _look(views, reach_m=0.7, unreachable_kinds=(), **config):
    robot = FakeRobot(object_width_m=None)
    loop, rt = FakeLoop(robot, views), Runtime(robot)
    motion = ReachMotion(robot, reach_m, unreachable_kinds)
    side = SideView(rt, loop, motion, np.eye(4), VolumeConfig(**config))
    return look_at_sides(side, loop.track, 60.0), motion, robot


def test_a_cube_seen_from_one_side_gets_a_reachable_view_of_its_far_side():
    out, motion, robot = _look([FRONT])
    assert out.unknown_before > 0.5 and out.faces_before["+x"] == pytest.approx(out.unknown_before, abs=1e-3)
    assert out.moved and out.message == ""
    assert [k for k, _ in motion.executed] == ["side_view", "side_view_return"]
    (kind, T), = motion.poses
    assert np.hypot(T[0, 3], T[1, 3]) <= 0.7  # the fake arm reaches it
    assert out.view["expected_fraction"] >= 0.2 and out.view["azimuth_deg"] % 30 == 0
    assert out.sim_s >= 5 * FRAME_PERIOD_S and out.cpu_s > 0  # it looked for 5 frames
    assert out.unknown_after == out.unknown_before  # nothing integrated the fake frames


def test_known_sides_need_no_view():
    out, motion, _ = _look([FRONT, BACK])
    assert out.unknown_before < 0.25 and out.message == "sides known"
    assert motion.executed == [] and motion.ik_calls == 0 and out.view is None


def test_out_of_reach_no_view_is_taken_and_far_views_are_not_solved_again():
    out, motion, _ = _look([FRONT], reach_m=0.1)
    assert not out.moved and motion.executed == []
    assert "reachable" in out.message
    # The camera is the flange here (every roll at one position): four solves per view, and no
    # view is tried as far out from the base as one that failed before.
    tried = motion.ik_reach_m[::4]
    assert motion.ik_calls == 4 * len(tried) and 1 <= len(tried) <= VolumeConfig().side_view_max_ik_checks
    assert all(b < a for a, b in zip(tried, tried[1:]))


def test_a_view_that_reveals_too_little_is_not_taken():
    out, motion, _ = _look([FRONT], side_view_min_gain_fraction=1.0)
    assert not out.moved and motion.ik_calls == 0 and "reveals" in out.message


def test_a_failed_move_still_returns_to_the_start():
    out, motion, _ = _look([FRONT], unreachable_kinds={"side_view"})
    assert not out.moved and "failed to move" in out.message
    assert [k for k, _ in motion.executed] == ["side_view_return"]


def test_without_a_volume_nothing_is_judged():
    robot = FakeRobot(object_width_m=None)
    loop = FakeLoop(robot, [FRONT])
    loop.volume = None
    side = SideView(Runtime(robot), loop, ReachMotion(robot, 0.7), np.eye(4))
    assert look_at_sides(side, loop.track, 60.0).message == "no scene volume"
