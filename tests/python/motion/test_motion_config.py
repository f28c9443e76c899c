"""The motion parameters load from config/motion.yaml and are range-checked."""

import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.motion.config import MotionConfig, load_motion_config


def test_defaults_match_spec():
    cfg = load_motion_config()
    assert cfg == MotionConfig()  # YAML and dataclass agree
    assert cfg.planner == "RRTConnect"
    assert cfg.planning_time_s == 10.0 and cfg.num_planning_attempts == 10
    assert cfg.velocity_scale == 0.3 and cfg.acceleration_scale == 0.3
    assert 0.01 <= cfg.voxel_size_m <= 0.02


@pytest.mark.parametrize("override, match", [
    ({"planner": "Dijkstra"}, "planner"),
    ({"velocity_scale": 1.5}, "velocity_scale"),
    ({"voxel_size_m": 0.001}, "voxel_size_m"),
    ({"planning_time_s": 0}, "planning_time_s"),
    ({"not_a_parameter": 1}, "unknown"),
])
def test_bad_values_refused(override, match):
    with pytest.raises(ConfigError, match=match):
        load_motion_config(overrides=override)
