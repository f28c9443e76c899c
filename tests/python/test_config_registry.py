"""One registry of parameter sets; every default defined once and equal everywhere."""

import dataclasses
import math

import pytest

from grasp_pipeline import _core
from grasp_pipeline.config import read_yaml
from grasp_pipeline.assets import default_config_dir
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.settings import SECTIONS, load_settings, section_class


def _same(a, b) -> bool:
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=1e-15)
    return a == b


@pytest.mark.parametrize("section", sorted(SECTIONS))
def test_yaml_defaults_equal_the_dataclass_defaults(section):
    cls = section_class(section)
    yaml_values = read_yaml(default_config_dir() / f"{section}.yaml")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    assert set(yaml_values) == set(fields), f"{section}.yaml and {cls.__name__} name different parameters"
    for name, value in yaml_values.items():
        assert _same(value, fields[name].default), f"{section}.{name}: yaml {value!r} vs {fields[name].default!r}"


@pytest.mark.parametrize("section, core_cls", [("scene_filter", "SceneFilterParams"), ("obb", "ObbParams")])
def test_cpp_defaults_equal_the_yaml_defaults(section, core_cls):
    core = getattr(_core, core_cls)()
    yaml_values = read_yaml(default_config_dir() / f"{section}.yaml")
    for name, value in yaml_values.items():
        assert _same(getattr(core, name), value), f"{section}.{name}: C++ {getattr(core, name)!r} vs yaml {value!r}"


def test_cpp_defaults_of_the_filled_in_facts_equal_their_one_definition():
    from grasp_pipeline.robot.limits import GRIPPER_MAX_WIDTH_M

    noise = read_yaml(default_config_dir() / "depth_noise.yaml")
    sf, obb = _core.SceneFilterParams(), _core.ObbParams()
    assert sf.depth_noise_sigma_m == obb.depth_noise_sigma == noise["depth_noise_sigma_m"]
    assert sf.depth_noise_ref_range_m == noise["depth_noise_ref_range_m"]
    assert sf.depth_noise_exponent == noise["depth_noise_exponent"]
    assert obb.gripper_open == GRIPPER_MAX_WIDTH_M


#: Facts with one definition: the set that owns them (None: the robot's published figures,
#: robot/limits.py) and the name stems a parameter for them would have. No other set may hold one.
ONE_DEFINITION = {
    "the depth sensor's noise": ("depth_noise", ("noise_sigma", "noise_ref_range", "noise_exponent")),
    "the hand's largest opening": (None, ("gripper_open", "gripper_max_width")),
    "the hand's largest force": (None, ("gripper_max_effort", "gripper_max_force")),
}


def test_facts_with_one_definition_are_parameters_of_no_other_set():
    offenders = []
    for section in SECTIONS:
        for f in dataclasses.fields(section_class(section)):
            for fact, (owner, stems) in ONE_DEFINITION.items():
                if section != owner and any(stem in f.name for stem in stems):
                    offenders.append(f"{section}.{f.name} ({fact})")
    assert offenders == []


#: Names that mean different things in different sets (set them as section.name).
DISTINCT_MEANINGS = {"seed": ["scene_filter", "camera"]}  # RANSAC sampling vs depth noise


def test_every_parameter_name_is_defined_in_one_section_only():
    owners: dict[str, list[str]] = {}
    for section in SECTIONS:
        for f in dataclasses.fields(section_class(section)):
            owners.setdefault(f.name, []).append(section)
    assert {n: s for n, s in owners.items() if len(s) > 1} == DISTINCT_MEANINGS


def test_every_command_section_is_known_without_importing_its_package_first():
    # perceive loads only scene_filter/obb but must accept a run config's grasp/scan sections
    import subprocess
    import sys

    code = ("from grasp_pipeline.settings import section_class; "
            "print(section_class('grasp').__name__, section_class('scan').__name__)")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert res.stdout.split() == ["GraspConfig", "ScanConfig"], res.stderr


def test_a_run_config_with_grasp_and_scan_sections_is_accepted_by_perceive_settings(tmp_path):
    cfg = tmp_path / "run.yaml"
    cfg.write_text("grasp:\n  lift_height_m: 0.12\nscan:\n  dwell_frames: 4\nobb:\n  window: 5\n")
    s = load_settings(("scene_filter", "obb"), str(cfg))
    assert s.obb.window == 5


def test_unknown_names_in_a_user_config_are_blamed_on_the_user_file(tmp_path):
    cfg = tmp_path / "mine.yaml"
    cfg.write_text("grasp:\n  lift_hieght_m: 0.12\n")
    with pytest.raises(ConfigError, match="mine.yaml"):
        load_settings(("grasp",), str(cfg))
