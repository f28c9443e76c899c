"""The run video's own rate and size (config/video.yaml)."""

import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.report.config import VideoConfig
from grasp_pipeline.settings import load_settings


def test_the_video_defaults_to_10_fps_at_320_by_240():
    video = load_settings(["video"]).video
    assert (video.video_fps, video.video_width_px, video.video_height_px) == (10.0, 320, 240)


@pytest.mark.parametrize("bad", [{"video_fps": 0.0}, {"video_width_px": 321}, {"video_height_px": 8}])
def test_bad_video_parameters_are_refused(bad):
    with pytest.raises(ConfigError):
        load_settings(["video"], sets=[f"video.{k}={v}" for k, v in bad.items()])


def test_the_scene_view_renders_at_the_configured_size():
    from grasp_pipeline.sim.exceptions import RenderUnavailable
    from grasp_pipeline.sim.scene_view import SceneView
    from grasp_pipeline.sim.world import SimWorld

    cfg = VideoConfig()
    with SimWorld(camera=False) as world:
        try:
            view = SceneView(world, cfg.video_width_px, cfg.video_height_px)
        except RenderUnavailable as exc:
            pytest.fail(f"no GL for the video: {exc}")
        try:
            assert view.render().shape == (cfg.video_height_px, cfg.video_width_px, 3)
        finally:
            view.close()
