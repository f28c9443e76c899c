"""The runtime's looks (frames on demand) and the perception loop's liveness on the
looking clock, with a tiny fake camera (no simulator)."""

from contextlib import contextmanager
from types import SimpleNamespace

import numpy as np

from grasp_pipeline.orchestration import PerceptionLoop, Runtime
from grasp_pipeline.orchestration.config import ScanConfig


class FakeCamera:
    """A clock and a camera: records whether frames were requested at every step."""

    def __init__(self) -> None:
        self.time_s, self.timestep_s = 0.0, 0.01
        self.requests = 0
        self.looking_time_s = 0.0
        self.looked: list[bool] = []

    @contextmanager
    def request_frames(self):
        self.requests += 1
        try:
            yield
        finally:
            self.requests -= 1

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.time_s += self.timestep_s
            if self.requests:
                self.looking_time_s += self.timestep_s
            self.looked.append(self.requests > 0)


def test_spin_looks_by_default_and_not_when_told():
    cam = FakeCamera()
    rt = Runtime(cam)
    rt.spin(0.1)
    assert cam.looked and all(cam.looked)
    cam.looked.clear()
    rt.spin(0.1, look=False)
    assert cam.looked and not any(cam.looked)
    assert cam.requests == 0


def test_spin_until_looks_only_when_asked():
    cam = FakeCamera()
    rt = Runtime(cam)
    assert not rt.spin_until(lambda: False, 0.05)
    assert not any(cam.looked)
    assert rt.spin_until(lambda: cam.time_s >= 0.1, 1.0, look=True)
    assert any(cam.looked) and cam.requests == 0


def test_a_task_that_is_closed_while_looking_releases_its_request():
    cam = FakeCamera()
    rt = Runtime(cam)

    def task():
        with rt.looking():
            while True:
                yield

    t = rt.start("look forever", task())
    rt.spin(0.05, look=False)
    assert cam.requests == 1
    t.gen.close()
    assert cam.requests == 0


def _frame(t: float):
    return SimpleNamespace(T_world_camera=np.eye(4), time_s=t, points_world=np.zeros((0, 3)), width=0, rgb=None)


def test_liveness_counts_only_looking_time():
    cam = FakeCamera()
    session = SimpleNamespace(process=lambda pts, pos, t, **kw: SimpleNamespace(raw=SimpleNamespace(tids=[], views=[])),
                              tracks=lambda: [], tracker=SimpleNamespace(last_gate=None), plane=None)
    loop = PerceptionLoop(session, ScanConfig(stale_timeout_s=0.5), ready_camera_pose=np.eye(4), camera=cam)
    assert loop.stale(cam.time_s)  # no frame ever
    loop.on_frame(_frame(cam.time_s))
    rt = Runtime(cam)
    rt.spin(2.0, look=False)  # a long motion: nobody looks, nothing was due
    assert not loop.stale(cam.time_s)
    rt.spin(0.4)  # looking, no frame: 0.4 s < 0.5 s
    assert not loop.stale(cam.time_s)
    rt.spin(0.2)  # 0.6 s of looking without a frame
    assert loop.stale(cam.time_s)
    loop.on_frame(_frame(cam.time_s))
    assert not loop.stale(cam.time_s)


def test_without_a_camera_liveness_is_on_simulated_time():
    session = SimpleNamespace(process=lambda pts, pos, t, **kw: SimpleNamespace(raw=SimpleNamespace(tids=[], views=[])),
                              tracks=lambda: [], tracker=SimpleNamespace(last_gate=None), plane=None)
    loop = PerceptionLoop(session, ScanConfig(stale_timeout_s=0.5), ready_camera_pose=np.eye(4))
    loop.on_frame(_frame(1.0))
    assert not loop.stale(1.4) and loop.stale(1.6)


def test_frames_while_looking_elsewhere_keep_perception_alive_but_are_not_processed():
    """The look into the tray after a place: its frames must not feed (or retire) the tracks."""
    cam = FakeCamera()
    processed = []
    session = SimpleNamespace(process=lambda pts, pos, t, **kw: processed.append(t) or
                              SimpleNamespace(raw=SimpleNamespace(tids=[], views=[])),
                              tracks=lambda: [], tracker=SimpleNamespace(last_gate=None), plane=None)
    loop = PerceptionLoop(session, ScanConfig(stale_timeout_s=0.5), ready_camera_pose=np.eye(4), camera=cam)
    loop.on_frame(_frame(0.0))
    rt = Runtime(cam)
    with loop.looking_elsewhere():
        rt.spin(0.4)
        loop.on_frame(_frame(cam.time_s))
        rt.spin(0.4)
    assert processed == [0.0] and loop.frames == 1
    assert not loop.stale(cam.time_s)  # the camera delivered 0.4 s of looking ago
    loop.on_frame(_frame(cam.time_s))
    assert len(processed) == 2 and loop.frames == 2
