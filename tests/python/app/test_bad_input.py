"""Bad input through the Python API: clear errors before any work, or a refused step in a
valid report — never a traceback from deep inside, never NaN in the JSON."""

import json
import math

import pytest

from grasp_pipeline.app.run import run_pipeline
from grasp_pipeline.exceptions import ConfigError, InputError
from grasp_pipeline.orchestration import FixedGraspSource
from grasp_pipeline.report.serialize import OutputError
from grasp_pipeline.settings import load_settings


def test_an_unknown_scene_is_refused_before_the_world_is_built(tmp_path):
    with pytest.raises(InputError, match="scene must be one of reference, random"):
        run_pipeline(scene="moon", out_dir=tmp_path, video=False)


def test_an_unwritable_report_path_is_refused_before_the_simulation(tmp_path):
    with pytest.raises(OutputError, match="is a directory"):
        run_pipeline(out_dir=tmp_path, json_path=tmp_path, video=False)


def test_a_non_finite_selection_is_refused_and_the_report_stays_valid_json(tmp_path):
    report = run_pipeline(select=[(math.nan, 0.0)], out_dir=tmp_path, json_path=tmp_path / "r.json",
                          video=False, scan=False)
    pick = report.picks[0]
    assert pick.failed_stage == "SELECT" and "finite" in pick.message
    json.loads((tmp_path / "r.json").read_text(), parse_constant=lambda c: pytest.fail(c))


@pytest.mark.parametrize("item, words", [
    ("grasp.lift_height_m=abc", "lift_height_m"),
    ("grasp.lift_height_m=nan", "lift_height_m"),
    ("camera.width_px=100000", "8..4096"),
    ("motion.num_planning_attempts=100000000000000000000000", "num_planning_attempts"),
    ("seed=3", "ambiguous"),
    ("nosuch=1", "unknown parameter"),
])
def test_bad_overrides_name_the_parameter(item, words):
    with pytest.raises(ConfigError, match=words):
        load_settings(("scene_filter", "camera", "grasp", "motion"), None, [item])


def test_a_fixed_grasp_source_needs_a_positive_radius():
    with pytest.raises(ValueError, match="radius_m"):
        FixedGraspSource([], radius_m=0.0)
