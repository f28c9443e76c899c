"""The active scan's closer look at ambiguous segments (orchestration/scanning/scan.py), with
a fake robot, a fake motion client and a stand-in perception loop: no simulator."""

from types import SimpleNamespace

import numpy as np

from grasp_pipeline import _core
from grasp_pipeline.orchestration.config import ScanConfig
from grasp_pipeline.orchestration.runtime import Runtime
from grasp_pipeline.orchestration.scanning.scan import ActiveScan

from ..fake_robot import FakeMotion, FakeRobot

TABLE_Z_M = 0.2
READY_CAMERA_Z_M = 0.75
FRAME_PERIOD_S = 1.0 / 30.0
MAX_WIDTH_M = 0.072


def _track(tid, xy, extents_m):
    centre = np.array([xy[0], xy[1], TABLE_Z_M + 0.5 * extents_m[2]])
    est = SimpleNamespace(center=centre, R_box=np.eye(3), extents=np.asarray(extents_m, float))
    return SimpleNamespace(tid=tid, smoothed=est, quality=_core.ViewQuality.NADIR, last_seen_s=1e9)


class FakeLoop:
    """Tracks that are always NADIR and in view; a frame every 1/30 s of simulated time."""

    def __init__(self, robot: FakeRobot, tracks: list) -> None:
        self.robot, self._tracks = robot, tracks
        self.plane = _core.Plane([0.0, 0.0, 1.0], -TABLE_Z_M)
        self.band_m = 0.01
        self.ready_camera_pose = np.eye(4)
        self.ready_camera_pose[:3, :3] = np.diag([1.0, -1.0, -1.0])  # looking down
        self.ready_camera_pose[:3, 3] = [0.4, 0.0, READY_CAMERA_Z_M]
        self.plane_locked, self.stale_reported, self.latest = True, False, None

    @property
    def frames(self) -> int:
        return int(self.robot.time_s / FRAME_PERIOD_S)

    def tracks(self) -> list:
        return self._tracks

    def report_if_stale(self, now_s: float) -> bool:
        return False

    def nearest_track(self, xy, within_gate: bool = True):
        return min(self._tracks, key=lambda t: float(np.hypot(*(t.smoothed.center[:2] - xy[:2]))))

    def scene_cloud(self):
        return None


class PoseMotion(FakeMotion):
    """Records the flange target of every pose motion by kind."""

    def __init__(self, robot, unreachable_kinds=()):
        super().__init__(robot, unreachable_kinds)
        self.poses: list[tuple[str, np.ndarray]] = []

    def to_pose(self, T, frame="tcp", kind="pose", allowance=None):
        self.poses.append((kind, np.asarray(T, float).copy()))
        return (yield from super().to_pose(T, frame, kind))


def _scan(tracks, unreachable=(), config=ScanConfig()):
    robot = FakeRobot(object_width_m=None)
    loop, rt = FakeLoop(robot, tracks), Runtime(robot)
    motion = PoseMotion(robot, unreachable)
    scan = ActiveScan(rt, loop, motion, np.eye(4), config, max_width_m=MAX_WIDTH_M)
    assert scan.trigger().accepted
    return rt.run(scan.task, 60.0), motion


def test_a_segment_wider_than_the_gripper_everywhere_is_looked_at_from_closer_above():
    merged = _track(0, (0.50, -0.08), (0.090, 0.085, 0.05))   # two objects in one segment?
    single = _track(1, (0.55, 0.08), (0.040, 0.080, 0.05))    # narrow one way: graspable
    out, motion = _scan([merged, single])
    assert out.completed and [p.nadir for p in out.probes] == [True, True]
    assert [k for k, _ in motion.poses] == ["scan_probe", "scan_closer_look", "scan_probe"]
    assert out.probes[0].closer_look == ("wide: footprint 90 x 85 mm, wider than the gripper's 72 mm "
                                         "in every direction; then 1 segment(s) there")
    assert out.probes[1].closer_look == ""
    probe_T, closer_T = motion.poses[0][1], motion.poses[1][1]
    # straight above the segment's centre, the camera 0.25 m above its top, still looking down
    assert np.allclose(closer_T[:2, 3], merged.smoothed.center[:2])
    assert np.isclose(closer_T[2, 3], TABLE_Z_M + 0.05 + ScanConfig().closer_look_standoff_m)
    assert np.isclose(probe_T[2, 3], READY_CAMERA_Z_M)
    assert np.allclose(closer_T[:3, :3], probe_T[:3, :3])


def test_a_closer_look_that_cannot_be_planned_is_reported_and_the_scan_goes_on():
    merged = _track(0, (0.50, -0.08), (0.090, 0.085, 0.05))
    other = _track(1, (0.55, 0.08), (0.095, 0.080, 0.05))
    out, motion = _scan([merged, other], unreachable={"scan_closer_look"})
    assert out.completed and not out.failure
    assert [k for k, _ in motion.executed if k.startswith("scan_")] == [
        "scan_probe", "scan_probe", "scan_return"]
    assert all("could not move closer: scan_closer_look: no path (fake)" in p.closer_look for p in out.probes)


def test_no_closer_look_when_it_is_switched_off_or_would_not_be_lower():
    merged = _track(0, (0.50, -0.08), (0.090, 0.085, 0.05))
    out, motion = _scan([merged], config=ScanConfig(closer_look=False))
    assert [k for k, _ in motion.poses] == ["scan_probe"] and out.probes[0].closer_look == ""
    tall = _track(0, (0.50, -0.08), (0.090, 0.085, 0.40))  # its top + 0.25 m is above the probe
    out, motion = _scan([tall])
    assert [k for k, _ in motion.poses] == ["scan_probe"] and out.probes[0].closer_look == ""
