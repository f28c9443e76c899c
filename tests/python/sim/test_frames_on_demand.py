"""Frames on demand in the simulated world: the camera renders only while frames are
requested (counted, nestable), at its rate; the looking clock runs only then; continuous
mode (the old path) renders whenever a listener exists."""

from dataclasses import replace

import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.sim.config import load_camera_config
from grasp_pipeline.sim.world import SimWorld

LOW_RES = {"width_px": 64, "height_px": 48, "rgb": False}


@pytest.fixture(scope="module")
def world():
    w = SimWorld(camera_config=load_camera_config(overrides=LOW_RES))
    yield w
    w.close()


def _count_frames(world: SimWorld, steps: int) -> list:
    frames: list = []
    world.add_frame_listener(frames.append)
    try:
        world.step(steps)
    finally:
        world.remove_frame_listener(frames.append)
    return frames


def test_on_demand_is_the_default():
    assert load_camera_config().frames == "on_demand"


def test_no_frame_is_rendered_without_a_request(world):
    looked = world.looking_time_s
    assert not world.frames_requested
    assert _count_frames(world, 200) == []  # 0.4 s with a listener, nobody looking
    assert world.looking_time_s == looked


def test_a_request_delivers_frames_at_the_camera_rate_and_runs_the_looking_clock(world):
    looked = world.looking_time_s
    with world.request_frames():
        assert world.frames_requested
        frames = _count_frames(world, 250)  # 0.5 s
    assert not world.frames_requested
    assert len(frames) == 15  # first at the next step, then every 1/30 s
    dts = [b.time_s - a.time_s for a, b in zip(frames, frames[1:])]
    assert min(dts) >= world.camera_config.period_s - world.timestep_s
    assert world.looking_time_s - looked == pytest.approx(0.5, abs=1e-9)


def test_requests_nest(world):
    with world.request_frames():
        with world.request_frames():
            pass
        assert world.frames_requested
        assert len(_count_frames(world, 100)) > 0
    assert not world.frames_requested


def test_continuous_mode_renders_whenever_a_listener_exists():
    cfg = replace(load_camera_config(overrides=LOW_RES), frames="continuous")
    with SimWorld(camera_config=cfg) as w:
        assert w.frames_requested
        assert len(_count_frames(w, 250)) in (15, 16)  # 0.5 s at 30 Hz, both ends
        assert w.looking_time_s == w.time_s


def test_an_unknown_frames_mode_is_refused():
    with pytest.raises(ConfigError, match="camera.frames"):
        load_camera_config(overrides={"frames": "sometimes"})
