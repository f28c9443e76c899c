"""The composition root wires each fact from its one definition: the simulated camera and
perception share one depth-noise model, and the scan takes the gripper's usable opening."""

import pytest

from grasp_pipeline.app.sim_system import SECTIONS, build_system
from grasp_pipeline.settings import load_settings
from grasp_pipeline.sim.scenes import reference_scene


def test_the_camera_and_perception_share_the_depth_noise_and_the_scan_the_usable_opening():
    settings = load_settings(SECTIONS, None, ["depth_noise.depth_noise_sigma_m=0.003",
                                              "grasp_fit.min_open_margin_m=0.01"])
    system = build_system(reference_scene(settings.sim), settings)
    try:
        assert system.world.camera.depth_noise is settings.depth_noise
        assert system.loop.session.depth_noise is settings.depth_noise
        assert system.loop.session._core.scene_filter.params.depth_noise_sigma_m == 0.003
        assert system.scanner.max_width_m == pytest.approx(0.08 - 0.01)
    finally:
        system.close()
