"""The Rerun recorder on a fake event stream, read back with Rerun's own reader.

The events are hand-made (a fake robot, fake perception results and tracks); the recording,
the forward kinematics and the reader are real."""

import sys
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.exceptions import InputError
from grasp_pipeline.motion.trajectory import JointTrajectory
from grasp_pipeline.orchestration.events import (EventBus, FrameEvent, GraspEvent, PerceptionEvent,
                                                 PickEvent, PlanEvent, StageEvent, Tick)
from grasp_pipeline.report.config import RerunConfig
from grasp_pipeline.report.rerun_recorder import (RerunUnavailable, attach, check_recording_path,
                                                  import_rerun)
from grasp_pipeline.report.rerun_summary import summarize_recording
from grasp_pipeline.report.serialize import OutputError
from grasp_pipeline.robot import description as rm
from grasp_pipeline.robot.frame import Frame

W, H = 16, 12
STEP_S = 0.002
CAMERA_HZ = 30.0


class FakeRobot:
    """The Arm/Gripper parts the recorder reads: a TCP moving along x, a closing gripper."""

    def __init__(self):
        self.t = 0.0

    def tcp_pose(self):
        T = np.eye(4)
        T[:3, 3] = [0.4 + 0.1 * self.t, 0.0, 0.5]
        return T

    @property
    def finger_gap_m(self):
        return max(0.0, 0.08 - 0.01 * self.t)


@dataclass
class FakeResult:
    """A perception result: object rows (label 0) and environment rows (label -1)."""

    points: np.ndarray
    labels: np.ndarray
    ms: float = 3.5

    @property
    def raw(self):
        return SimpleNamespace(ms_total=self.ms)

    def object_points(self):
        m = self.labels >= 0
        return self.points[m], self.labels[m]

    def environment_points(self):
        return self.points[self.labels == -1]


def fake_track(tid: int, x: float, quality=_core.ViewQuality.NADIR):
    c, s = np.cos(0.3), np.sin(0.3)
    est = SimpleNamespace(center=np.array([x, 0.0, 0.225]), extents=np.array([0.05, 0.04, 0.06]),
                          R_box=np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]))
    return SimpleNamespace(tid=tid, quality=quality, smoothed=est)


def fake_frame(t: float, index: int) -> Frame:
    rng = np.random.default_rng(index)
    depth = rng.uniform(0.3, 0.6, (H, W)).astype(np.float32)
    depth[0, 0] = np.nan
    pts = rng.uniform(-1, 1, (H * W, 3)).astype(np.float32)
    K = np.array([[20.0, 0, W / 2], [0, 20.0, H / 2], [0, 0, 1]])
    T = np.eye(4)
    T[:3, 3] = [0.3, 0.0, 0.6]
    return Frame(points_world=pts, depth=depth, time_s=t, T_world_camera=T, K=K, backend="raycast",
                 index=index, rgb=np.full((H, W, 3), 120, np.uint8))


def publish_frame(bus: EventBus, t: float, index: int, tracks) -> None:
    frame = fake_frame(t, index)
    labels = np.where(np.arange(H * W) % 4 == 0, 0, -1)
    bus.publish(FrameEvent(t, frame))
    bus.publish(PerceptionEvent(t, FakeResult(frame.points_world, labels), tuple(tracks)))


def grasp(x: float, width_m: float = 0.05):
    R = np.column_stack([[0, 0, -1.0], [-1.0, 0, 0], [0, 1.0, 0]])  # approach -z, closing y
    return _core.BestGrasp(R, np.array([x, 0.0, 0.225]), width_m)


def run_fake(bus: EventBus, robot: FakeRobot, seconds: float, tracks, t0: float = 0.0) -> int:
    """Ticks every 2 ms with camera frames at 30 Hz for ``seconds``; returns the frames sent."""
    frames, next_frame = 0, t0
    for k in range(int(round(seconds / STEP_S)) + 1):
        t = round(t0 + k * STEP_S, 6)
        robot.t = t
        if t + 1e-9 >= next_frame:
            publish_frame(bus, t, frames, tracks)
            frames += 1
            next_frame += 1.0 / CAMERA_HZ
        bus.publish(Tick(t))
    return frames


def tcp_of(q):
    model = rm.load_robot_model()
    return (rm.forward_kinematics(q, model) @ rm.flange_T_tcp(model))[:3, 3]


@pytest.fixture
def recorded(tmp_path):
    """A 2 s fake run: frames, a stage, a plan, a grasp decision, a pick; then the summary."""
    bus, robot = EventBus(), FakeRobot()
    path = tmp_path / "fake.rrd"
    rec = attach(bus, path, robot, RerunConfig(rerun_frame_rate_hz=2.0, rerun_state_rate_hz=20.0,
                                               rerun_max_environment_points=50, rerun_plan_samples=10))
    tracks = [fake_track(0, 0.5), fake_track(3, 0.6, _core.ViewQuality.OBLIQUE)]
    frames = run_fake(bus, robot, 0.99, tracks)        # the frame at 29/30 s waits (2 Hz)
    bus.publish(StageEvent(1.01, "scan_done"))
    q = np.linspace(rm.READY_Q, rm.NEUTRAL_Q, 40)
    traj = JointTrajectory(t_s=np.linspace(0, 1, 40), q=q, qd=np.zeros_like(q), qdd=np.zeros_like(q))
    bus.publish(PlanEvent(1.02, "pre_grasp", "RRTConnect", 12.0, 30.0, 1.0, trajectory=traj))
    bus.publish(GraspEvent(1.02, (grasp(0.5), grasp(0.52, 0.04)), 1, np.eye(4), 0.0))
    frames += run_fake(bus, robot, 1.0, tracks[:1], t0=1.03)
    bus.publish(PickEvent(2.1, SimpleNamespace(success=True)))
    assert rec.close() == str(path) and rec.problem is None
    return SimpleNamespace(summary=summarize_recording(path), frames=frames, rec=rec, q=q)


def test_every_entity_is_recorded_with_the_right_counts(recorded):
    s, frames = recorded.summary, recorded.frames
    assert s["/world/objects"].logs == frames                        # boxes: every frame
    assert s["/world/objects"].batches[0] == 2 and s["/world/objects"].last == 1
    assert s["/plots/perception_ms"].logs == frames
    # images and clouds at 2 Hz: t = 0, 0.5 | 1.03, 1.53, 2.03; plus the frame of 29/30 s,
    # drawn at scan_done
    assert s["/world/camera"].logs == s["/world/camera/image/rgb"].logs == 6
    assert s["/world/camera/image/depth"].logs == s["/world/cloud/objects"].logs == 6
    assert s["/world/camera/image"].static                           # the pinhole, once
    assert s["/world/cloud/objects"].largest == H * W // 4
    assert s["/world/cloud/environment"].largest == 50               # thinned to the limit
    assert s["/world/tcp"].logs == s["/plots/finger_gap_mm"].logs == 41  # 20 Hz over 2.03 s
    assert s["/world/paths/planned"].logs == 1
    assert s["/world/grasps/candidates"].batches == [2]
    assert s["/world/grasps/chosen"].logs == 1
    assert s["/timeline/stages"].texts == ["scan_done"]
    assert s["/timeline/picks"].texts == ["picked"]
    assert "RRTConnect" in s["/timeline/plans"].texts[0]
    assert s["/world/paths/executed"].last == 2                     # a strip per motion
    assert recorded.rec.logged["camera_frames"] == 6


def test_the_key_stage_frame_is_recorded_at_its_own_time(recorded):
    times = recorded.summary["/world/camera"].times_s
    frame_29 = np.ceil(29 / CAMERA_HZ / STEP_S) * STEP_S   # on the 2 ms tick grid: 0.968 s
    np.testing.assert_allclose(times, [0.0, 0.5, frame_29, 1.03, 1.53, 2.03], atol=1e-6)


def test_the_planned_path_is_the_trajectory_s_tcp_by_forward_kinematics(recorded, tmp_path):
    import rerun.dataframe as rdf

    rec = rdf.load_recording(str(recorded.rec.path))
    table = rec.view(index="sim_time", contents="/world/paths/planned").select().read_all()
    strip = np.array(table.column("/world/paths/planned:LineStrips3D:strips").to_pylist()[0][0])
    assert len(strip) == 10
    np.testing.assert_allclose(strip[0], tcp_of(recorded.q[0]), atol=1e-5)
    np.testing.assert_allclose(strip[-1], tcp_of(recorded.q[-1]), atol=1e-5)


def test_without_a_robot_the_state_series_are_left_out(tmp_path):
    bus = EventBus()
    rec = attach(bus, tmp_path / "r.rrd")
    run_fake(bus, FakeRobot(), 0.2, [fake_track(0, 0.5)])
    rec.close()
    s = summarize_recording(tmp_path / "r.rrd")
    assert "/world/tcp" not in s and "/world/paths/executed" not in s
    assert s["/world/objects"].logs == 7 and not bus.wants(Tick)


def test_a_failing_recorder_stops_with_a_warning_and_the_run_goes_on(tmp_path):
    bus, robot = EventBus(), FakeRobot()
    rec = attach(bus, tmp_path / "r.rrd", robot)

    def broken():
        raise OSError("[Errno 28] No space left on device")

    robot.tcp_pose = broken
    run_fake(bus, robot, 0.1, [fake_track(0, 0.5)])       # nothing reaches the publisher
    assert "No space left" in rec.problem and not bus.failures
    assert not bus.wants(Tick) and not bus.wants(PerceptionEvent)
    assert rec.close() is not None
    summarize_recording(tmp_path / "r.rrd")               # what was written is readable


def test_without_the_sdk_a_clear_error_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "rerun", None)       # import rerun -> ImportError
    with pytest.raises(RerunUnavailable, match=r"pip install 'grasp-pipeline\[rerun\]'"):
        import_rerun()


def test_an_old_sdk_is_refused(monkeypatch):
    monkeypatch.setitem(sys.modules, "rerun", SimpleNamespace(__version__="0.19.1"))
    with pytest.raises(RerunUnavailable, match="0.19.1"):
        import_rerun()


def test_the_recording_path_must_be_a_writable_rrd_file(tmp_path):
    with pytest.raises(InputError, match=r"\.rrd"):
        check_recording_path(tmp_path / "run.mp4")
    (tmp_path / "d.rrd").mkdir()
    with pytest.raises(OutputError, match="directory"):
        check_recording_path(tmp_path / "d.rrd")
    assert check_recording_path(tmp_path / "new" / "run.rrd").parent.is_dir()


def test_run_pipeline_refuses_rerun_without_the_sdk_before_building_anything(monkeypatch, tmp_path):
    from grasp_pipeline.app import run as run_module

    monkeypatch.setitem(sys.modules, "rerun", None)

    def no_simulation(*a, **k):
        raise AssertionError("the simulation must not start")

    monkeypatch.setattr(run_module, "build_system", no_simulation)
    with pytest.raises(RerunUnavailable):
        run_module.run_pipeline(out_dir=tmp_path / "out", rerun=tmp_path / "run.rrd", video=False)
    assert not (tmp_path / "run.rrd").exists()
