"""The language parameter set: loaded from config/language.yaml, checked."""

import pytest

from grasp_pipeline.config import load_config
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.language import LanguageConfig
from grasp_pipeline.settings import load_settings


def test_the_yaml_loads_and_overrides_apply():
    s = load_settings(("language",), sets=["language.size_large_ratio_min=2.0"])
    assert s.language.size_large_ratio_min == 2.0
    assert load_config(LanguageConfig, "language") == LanguageConfig()


@pytest.mark.parametrize("override, match", [
    ({"colour_names": ["red"]}, "same length"),
    ({"colour_rgb": [[2, 0, 0]] * 13}, r"colour_rgb\[0\]\[0\] = 2.0 is out of range: expected a number in \[0, 1\]"),
    ({"shape_synonyms": ["tin=jar"]}, "unknown shape"),
    ({"colour_synonyms": ["scarlet=crimson"]}, "not in colour_names"),
    ({"size_synonyms": ["huge"]}, "not word=meaning"),
    ({"size_small_ratio_max": 1.2}, "size_small_ratio_max"),
    ({"shape_cell_m": 0}, "shape_cell_m"),
])
def test_bad_values_are_refused(override, match):
    with pytest.raises(ConfigError, match=match):
        load_config(LanguageConfig, "language", overrides=override)
