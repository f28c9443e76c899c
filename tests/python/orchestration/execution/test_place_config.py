"""The PLACE stage's parameters: config/place.yaml, validated."""

import pytest

from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.orchestration.execution.place_config import PlaceConfig
from grasp_pipeline.settings import load_settings


def test_the_defaults_load_from_place_yaml_and_can_be_overridden():
    s = load_settings(["place"], sets=["place.release_max_drop_m=0.04"])
    assert isinstance(s.place, PlaceConfig)
    assert s.place.release_max_drop_m == 0.04
    assert s.place.release_clearance_m == PlaceConfig().release_clearance_m


@pytest.mark.parametrize("name", ["release_max_drop_m", "lower_attempts", "look_frames", "spot_cell_m",
                                  "arrived_min_area_m2"])
def test_non_positive_values_are_refused(name):
    with pytest.raises(ConfigError, match=f"place.{name} = 0 is out of range"):
        PlaceConfig(**{name: 0}).validate()


def test_a_release_aim_above_the_highest_release_is_refused():
    with pytest.raises(ConfigError, match="release_clearance_m = 0.04 is out of range: expected a height below release_max_drop_m"):
        PlaceConfig(release_clearance_m=0.04, release_max_drop_m=0.03).validate()


def test_a_search_step_coarser_than_the_release_band_is_refused():
    with pytest.raises(ConfigError, match="lower_step_m = 0.02"):
        PlaceConfig(lower_step_m=0.02).validate()


def test_unknown_place_parameters_are_refused_naming_where_they_are_listed():
    with pytest.raises(ConfigError, match="unknown parameter.*release_height_m.*config/place.yaml"):
        load_settings(["place"], sets=["place.release_height_m=0.1"])
