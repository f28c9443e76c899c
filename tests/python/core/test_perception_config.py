"""Config values are validated in Python before they reach C++ (perception/config.py).

Regression: ``SceneFilterConfig(cluster_eps='abc')``, ``plane_ransac_iters=10**12`` or a
negative seed ended in a raw pybind ``TypeError`` naming no parameter. Now: a ConfigError
naming the section, the parameter, the value and the allowed range; the Python ranges
agree with the C++ ``validate()`` at every bound; the C++ parameter setters and integer
arguments name the field/argument too.
"""

import dataclasses
import math

import numpy as np
import pytest

from grasp_pipeline import _core
from grasp_pipeline.config import build_config
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.perception import ObbConfig, SceneFilterConfig, load_scene_filter_config
from grasp_pipeline.perception.config import _OBB_RANGES, _SCENE_FILTER_RANGES
from grasp_pipeline.robot.depth_noise import DepthNoiseConfig
from grasp_pipeline.robot.limits import GRIPPER_MAX_WIDTH_M


@pytest.mark.parametrize("cls, kwargs, words", [
    (SceneFilterConfig, {"cluster_eps": "abc"}, ["scene_filter.cluster_eps", "'abc'", "not a number", "(0, 1] m"]),
    (SceneFilterConfig, {"plane_ransac_iters": 10**12}, ["plane_ransac_iters", "1000000000000", "[1, 1000000]"]),
    (SceneFilterConfig, {"seed": -1}, ["scene_filter.seed", "-1", "[0, 18446744073709551615]"]),
    (SceneFilterConfig, {"seed": 2**64}, ["seed", "18446744073709551616"]),
    (SceneFilterConfig, {"plane_ransac_iters": 2.5}, ["plane_ransac_iters", "not an integer", "[1, 1000000]"]),
    (SceneFilterConfig, {"plane_lock": 1}, ["plane_lock", "not a bool", "true or false"]),
    (SceneFilterConfig, {"band": float("nan")}, ["band", "nan", "not a finite", "[0, 1] m"]),
    (SceneFilterConfig, {"band": 10**400}, ["band", "not a finite float64", "[0, 1] m"]),
    (SceneFilterConfig, {"band": True}, ["band", "not a number"]),
    (SceneFilterConfig, {"max_abs_coordinate_m": 0.0}, ["max_abs_coordinate_m", "(0, 1000000000] m"]),
    (SceneFilterConfig, {"cluster_voxel_m": 0.02}, ["cluster_voxel_m", "0.02", "cluster_eps = 0.015"]),
    (SceneFilterConfig, {"cluster_max_extent": 0.005}, ["cluster_max_extent", ">= cluster_min_extent"]),
    (ObbConfig, {"n_theta": 1}, ["obb.n_theta", "= 1", "[2, 100000]"]),
    (ObbConfig, {"window": None}, ["obb.window", "None", "not an integer"]),
    (ObbConfig, {"max_age_s": float("inf")}, ["max_age_s", "not a finite", "> 0 s"]),
    (ObbConfig, {"min_graspable_width": 0.09}, ["obb.min_graspable_width", "[0, 0.08] m"]),
    (DepthNoiseConfig, {"depth_noise_sigma_m": 0.0}, ["depth_noise.depth_noise_sigma_m", "(0, 0.1] m"]),
])
def test_bad_values_raise_config_error_naming_parameter_value_and_range(cls, kwargs, words):
    with pytest.raises(ConfigError) as info:
        cls(**kwargs)
    msg = str(info.value)
    for w in words:
        assert w in msg, msg


def test_the_yaml_and_override_path_gives_the_same_errors():
    with pytest.raises(ConfigError, match=r"plane_ransac_iters = 1000000000000 .*\[1, 1000000\]"):
        load_scene_filter_config(overrides={"plane_ransac_iters": 1000000000000})
    with pytest.raises(ConfigError, match=r"seed = -3 is out of range"):
        load_scene_filter_config(overrides={"seed": -3})
    with pytest.raises(ConfigError, match="cluster_eps"):
        build_config(SceneFilterConfig, {"cluster_eps": "abc"})


def test_valid_numpy_and_int_values_are_accepted():
    cfg = SceneFilterConfig(cluster_eps=np.float32(0.02), plane_ransac_iters=np.int64(300), band=0,
                            plane_lock=np.bool_(False), seed=2**64 - 1)
    core = cfg.to_core(DepthNoiseConfig())
    assert core.plane_ransac_iters == 300 and core.seed == 2**64 - 1 and core.plane_lock is False


def _probe_values(rule, is_int):
    out = []
    for b in (rule.lo, rule.hi):
        if b is None:
            continue
        if is_int:
            out += [b - 1, b, b + 1]
        else:
            out += [b, math.nextafter(b, -math.inf), math.nextafter(b, math.inf)]
    return out or [-1e300, 1e300]


def _accepts_python(cls, name, value):
    try:
        cls(**{name: value})
        return True
    except ConfigError:
        return False


def _accepts_cpp(core_cls, name, value, core_name=None):
    params = core_cls()
    try:
        setattr(params, core_name or name, value)
        params.validate()
        return True
    except (ValueError, TypeError):
        return False


@pytest.mark.parametrize("cls, core_cls, ranges", [
    (SceneFilterConfig, _core.SceneFilterParams, _SCENE_FILTER_RANGES),
    (ObbConfig, _core.ObbParams, _OBB_RANGES),
])
def test_python_ranges_agree_with_the_cpp_validate_at_every_bound(cls, core_cls, ranges):
    fields = {f.name: f.type for f in dataclasses.fields(cls)}
    assert set(ranges) == {n for n, t in fields.items() if t != "bool"}
    for name, rule in ranges.items():
        is_int = fields[name] == "int"
        for value in _probe_values(rule, is_int):
            py_ok, cpp_ok = _accepts_python(cls, name, value), _accepts_cpp(core_cls, name, value)
            assert py_ok == cpp_ok, f"{name} = {value!r}: python {py_ok}, C++ {cpp_ok}"


@pytest.mark.parametrize("core_cls, core_names", [
    (_core.SceneFilterParams, {"depth_noise_sigma_m": "depth_noise_sigma_m",
                               "depth_noise_ref_range_m": "depth_noise_ref_range_m",
                               "depth_noise_exponent": "depth_noise_exponent"}),
    (_core.ObbParams, {"depth_noise_sigma_m": "depth_noise_sigma"}),
])
def test_the_depth_noise_ranges_agree_with_the_cpp_validate_at_every_bound(core_cls, core_names):
    for name, core_name in core_names.items():
        for value in _probe_values(DepthNoiseConfig.RANGES[name], False):
            py_ok = _accepts_python(DepthNoiseConfig, name, value)
            cpp_ok = _accepts_cpp(core_cls, name, value, core_name)
            assert py_ok == cpp_ok, f"{name} = {value!r}: python {py_ok}, C++ {core_name} {cpp_ok}"


def test_the_cpp_sets_take_the_sensor_noise_and_the_robot_opening_from_their_one_definition():
    noise = DepthNoiseConfig(depth_noise_sigma_m=0.003, depth_noise_ref_range_m=0.5, depth_noise_exponent=1.5)
    sf, obb = SceneFilterConfig().to_core(noise), ObbConfig().to_core(noise)
    assert (sf.depth_noise_sigma_m, sf.depth_noise_ref_range_m, sf.depth_noise_exponent) == (0.003, 0.5, 1.5)
    assert obb.depth_noise_sigma == 0.003 and obb.gripper_open == GRIPPER_MAX_WIDTH_M
    # neither set can be given its own value of these facts
    for cls, name in ((SceneFilterConfig, "depth_noise_sigma_m"), (ObbConfig, "depth_noise_sigma"),
                      (ObbConfig, "gripper_open")):
        with pytest.raises(ConfigError, match="unknown parameter"):
            build_config(cls, {name: 0.002}, section="x")


@pytest.mark.parametrize("name, value, exc, words", [
    ("cluster_eps", "abc", TypeError, ["SceneFilterParams.cluster_eps", "expected a number", "'abc'"]),
    ("plane_ransac_iters", 10**12, ValueError, ["SceneFilterParams.plane_ransac_iters", "out of range"]),
    ("plane_ransac_iters", 1.5, TypeError, ["plane_ransac_iters", "expected an integer"]),
    ("seed", -1, ValueError, ["SceneFilterParams.seed", "[0, 2^64 - 1]"]),
    ("plane_lock", "yes", TypeError, ["SceneFilterParams.plane_lock", "True or False"]),
])
def test_core_parameter_setters_name_the_field(name, value, exc, words):
    p = _core.SceneFilterParams()
    with pytest.raises(exc) as info:
        setattr(p, name, value)
    for w in words:
        assert w in str(info.value), str(info.value)
    q = _core.ObbParams()
    with pytest.raises(ValueError, match="ObbParams.n_theta"):
        q.n_theta = 2**40


def test_integer_arguments_of_bound_functions_name_the_argument():
    pts = np.random.default_rng(0).uniform(0, 0.1, (50, 3))
    with pytest.raises(ValueError, match="min_points"):
        _core.euclidean_clusters(pts, 0.015, 10**12, 0.0, 0.3)
    with pytest.raises(ValueError, match=r"seed: 18446744073709551616 is out of range"):
        _core.fit_plane_ransac(pts, _core.SceneFilterParams(), seed=2**64)
    with pytest.raises(ValueError, match="seed"):
        _core.extract_planes(pts, _core.SceneFilterParams(), seed=-1)
    with pytest.raises(ValueError, match=r"n_theta: .* \[2, 100000\]"):
        _core.width_scan([0.0], [0.0], 10**10)
    with pytest.raises(TypeError, match="iters: expected an integer"):
        _core.slice_median_top([0.1, 0.2, 0.3], 0.002, 4.0, 2.0)
    assert _core.fit_plane_ransac(pts, _core.SceneFilterParams(), seed=2**64 - 1) is None or True
