"""The video recorder on the event stream: its own rate; a failing encoder never stops the run."""

import numpy as np

from grasp_pipeline.orchestration.events import EventBus, Tick
from grasp_pipeline.report.video_recorder import VideoRecorder


def test_frames_are_taken_at_the_recorder_rate(tmp_path):
    bus, calls = EventBus(), []

    def render():
        calls.append(1)
        return np.zeros((48, 64, 3), np.uint8)

    rec = VideoRecorder(render, tmp_path / "v.mp4", fps=10.0).attach(bus)
    for k in range(501):                 # 1 s at 2 ms steps
        bus.publish(Tick(k * 0.002))
    assert len(calls) == 11              # t = 0, 0.1, ..., 1.0
    assert rec.close() is not None and rec.problem is None


def test_a_failing_writer_stops_recording_with_a_warning_and_the_run_goes_on(tmp_path):
    bus = EventBus()
    rec = VideoRecorder(lambda: np.zeros((48, 64, 3), np.uint8), tmp_path / "v.mp4").attach(bus)

    def broken_pipe(frame):
        raise BrokenPipeError("[Errno 32] Broken pipe")

    rec.writer.append = broken_pipe
    for k in range(200):
        bus.publish(Tick(k * 0.002))     # no exception reaches the publisher
    assert "Broken pipe" in rec.problem
    assert not bus.wants(Tick)            # unsubscribed itself
