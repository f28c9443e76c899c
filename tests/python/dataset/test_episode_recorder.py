"""The episode recorder on a fake robot and a hand-made event stream (no simulator)."""

from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline.dataset.episode_recorder import EpisodeRecorder, pick_outcome
from grasp_pipeline.orchestration.events import EventBus, PickEvent, StageEvent, Tick

DT = 0.002
FPS = 15


class FakeRobot:
    """Joints follow a ramp; the reference leads the joints by ``lag_s``; TCP moves along x."""

    def __init__(self, lag_s: float = 0.01):
        self.time_s, self.lag_s = 0.0, lag_s

    def _q(self, t):
        return np.full(7, 0.1 * t)

    @property
    def q(self):
        return self._q(self.time_s)

    @property
    def finger_gap_m(self):
        return 0.08 - 0.001 * self.time_s

    @property
    def gripper_target_m(self):
        return 0.0 if self.time_s > 1.0 else 0.08

    def reference(self):
        return self._q(self.time_s + self.lag_s), np.zeros(7)

    def tcp_pose(self):
        T = np.eye(4)
        T[0, 3] = 0.5 + 0.01 * self.time_s
        return T


def _run(robot, bus, until_s):
    while robot.time_s < until_s - 1e-12:
        robot.time_s = round(robot.time_s + DT, 9)
        bus.publish(Tick(robot.time_s))


def _pick(robot, bus, success=True, placed=True, stage=None, obj="red_mug"):
    row = SimpleNamespace(success=success, placed=placed, failed_stage=stage, message="m",
                          object=obj, anchor=[0.5, 0.0])
    bus.publish(PickEvent(robot.time_s, row))


def _recorder(robot, images=False):
    episodes = []
    render = (lambda: ({"wrist": np.zeros((4, 6, 3), np.uint8)}, {"wrist": np.ones((4, 6), np.float32)})) \
        if images else None
    rec = EpisodeRecorder(robot, FPS, episodes.append, lambda r: (f"pick up the {r.object}", r.object),
                          render=render)
    bus = EventBus()
    rec.attach(bus)
    return rec, bus, episodes


def test_samples_at_the_recording_rate_from_the_scan_to_each_pick():
    robot = FakeRobot()
    rec, bus, episodes = _recorder(robot)
    _run(robot, bus, 0.5)                      # before the scan ends: nothing recorded
    bus.publish(StageEvent(robot.time_s, "scan_done"))
    _run(robot, bus, 1.5)
    _pick(robot, bus)
    _run(robot, bus, 2.5)
    _pick(robot, bus, success=False, placed=False, stage="CLOSE", obj="blue_box")
    _run(robot, bus, 3.0)                       # after the last pick: no episode
    assert bus.failures == []
    assert len(episodes) == 2
    first, second = episodes
    assert first.time_s[0] == pytest.approx(0.5)
    assert second.time_s[0] == pytest.approx(1.5)
    for ep in episodes:
        dt = np.diff(ep.time_s)
        assert np.all(np.abs(dt - 1.0 / FPS) <= DT + 1e-9)
        # every sample is within one physics step after its nominal time
        nominal = ep.time_s[0] + np.arange(ep.length) / FPS
        assert np.all((ep.time_s - nominal >= -1e-9) & (ep.time_s - nominal <= DT + 1e-9))
    assert first.length == 15 + 1 and second.length == 15 + 1
    assert (first.task, first.success, first.failed_stage, first.object) == ("pick up the red_mug", True, "", "red_mug")
    assert (second.success, second.failed_stage, second.object) == (False, "CLOSE", "blue_box")


def test_action_is_the_target_in_force_at_the_next_frame():
    robot = FakeRobot(lag_s=0.01)
    rec, bus, episodes = _recorder(robot)
    bus.publish(StageEvent(0.0, "scan_done"))
    _run(robot, bus, 1.3)
    _pick(robot, bus)
    ep = episodes[0]
    assert ep.state.shape == (ep.length, 8) and ep.action.shape == (ep.length, 8)
    np.testing.assert_allclose(ep.state[:, :7], np.tile(0.1 * ep.time_s[:, None], 7), atol=1e-6)
    # action i = the reference sampled at frame i+1 (reference = joints 10 ms ahead)
    np.testing.assert_allclose(ep.action[:-1, :7], np.tile(0.1 * (ep.time_s[1:, None] + 0.01), 7), atol=1e-6)
    np.testing.assert_allclose(ep.action[-1, :7], np.full(7, 0.1 * (ep.time_s[-1] + 0.01)), atol=1e-6)
    # gripper command: 0.08 until 1 s, then closed; the action's is the next frame's command
    expected_grip = np.where(np.append(ep.time_s[1:], ep.time_s[-1]) > 1.0, 0.0, 0.08)
    np.testing.assert_allclose(ep.action[:, 7], expected_grip)
    np.testing.assert_allclose(ep.state[:, 7], 0.08 - 0.001 * ep.time_s, atol=1e-6)


def test_end_effector_pose_and_delta():
    robot = FakeRobot()
    rec, bus, episodes = _recorder(robot)
    bus.publish(StageEvent(0.0, "scan_done"))
    _run(robot, bus, 1.0)
    _pick(robot, bus)
    ep = episodes[0]
    np.testing.assert_allclose(ep.ee_pose[:, 0], 0.5 + 0.01 * ep.time_s, atol=1e-6)
    np.testing.assert_allclose(ep.ee_pose[:, 3:], np.tile([0, 0, 0, 1.0], (ep.length, 1)), atol=1e-7)
    np.testing.assert_allclose(ep.action_ee_delta[:-1, 0], np.diff(ep.ee_pose[:, 0]), atol=1e-6)
    assert np.all(ep.action_ee_delta[-1, :6] == 0)
    np.testing.assert_allclose(ep.action_ee_delta[:, 6], ep.action[:, 7])


def test_images_and_depths_are_stacked_per_camera():
    robot = FakeRobot()
    rec, bus, episodes = _recorder(robot, images=True)
    bus.publish(StageEvent(0.0, "scan_done"))
    _run(robot, bus, 0.4)
    _pick(robot, bus)
    ep = episodes[0]
    assert ep.images["wrist"].shape == (ep.length, 4, 6, 3) and ep.images["wrist"].dtype == np.uint8
    assert ep.depths["wrist"].shape == (ep.length, 4, 6) and ep.depths["wrist"].dtype == np.float32


def test_nothing_is_recorded_without_the_start_stage():
    robot = FakeRobot()
    rec, bus, episodes = _recorder(robot)
    _run(robot, bus, 1.0)
    _pick(robot, bus)
    assert episodes == []


@pytest.mark.parametrize("success, placed, stage, expected", [
    (True, True, None, (True, "")),
    (True, False, None, (False, "VERIFY")),      # reported success, object not in the tray
    (False, False, "SELECT", (False, "SELECT")),
    (False, False, None, (False, "UNKNOWN")),
])
def test_pick_outcome(success, placed, stage, expected):
    assert pick_outcome(SimpleNamespace(success=success, placed=placed, failed_stage=stage)) == expected
