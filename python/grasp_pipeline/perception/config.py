"""Typed parameter sets of the perception core (SPEC 1.6 and 2.7).

Field names and defaults are SPEC's; the YAML files are ``config/scene_filter.yaml``
and ``config/obb.yaml``.

Every value is checked here, in Python, before it reaches C++ (at construction, in
``__post_init__``, and again by ``validate()``): its type (a bool for a switch, an integer
for a count, a finite real number otherwise) and its range, which mirrors the C++ core's
``validate()`` (tests pin that the two agree at every bound). A bad value raises
:class:`ConfigError` naming the section, the parameter, the value and the allowed range,
e.g. ``scene_filter.plane_ransac_iters = 1000000000000 is out of range: expected an integer
in [1, 1000000]`` — never a raw pybind ``TypeError``. ``to_core()`` then runs the C++
``validate()`` as a second line of defence.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, NamedTuple, Optional

import numpy as np

from ..config import load_config
from ..exceptions import ConfigError


class _Range(NamedTuple):
    """Allowed values of one parameter: lo/hi (None: unbounded), open ends, unit."""

    lo: Optional[float]
    hi: Optional[float]
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""

    def contains(self, x: float) -> bool:
        if self.lo is not None and (x < self.lo or (self.lo_open and x == self.lo)):
            return False
        return not (self.hi is not None and (x > self.hi or (self.hi_open and x == self.hi)))

    def text(self, kind: str) -> str:
        if self.lo is None and self.hi is None:
            return "a finite number" if kind == "a number" else kind
        if self.hi is None:
            return f"{kind} {'>' if self.lo_open else '>='} {_fmt(self.lo)}{self.unit}"
        if self.lo is None:
            return f"{kind} {'<' if self.hi_open else '<='} {_fmt(self.hi)}{self.unit}"
        lo_b, hi_b = "(" if self.lo_open else "[", ")" if self.hi_open else "]"
        return f"{kind} in {lo_b}{_fmt(self.lo)}, {_fmt(self.hi)}{hi_b}{self.unit}"


def _fmt(x: float) -> str:
    """1000000 rather than 1e+06 for whole numbers (the bounds users type)."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e20 else f"{x:g}"


_UINT64_MAX = 2**64 - 1


def _check_type(section: str, name: str, typ: Any, value: Any, expected: str) -> None:
    """ConfigError unless ``value`` is a bool / integer / finite real number as ``typ`` says."""
    where = f"{section}.{name} = {value!r}"
    got = type(value).__name__
    is_bool = isinstance(value, (bool, np.bool_))
    if typ in (bool, "bool"):
        if not is_bool:
            raise ConfigError(f"{where} is not a bool (got {got}): use true or false")
    elif typ in (int, "int"):
        if is_bool or not isinstance(value, numbers.Integral):
            raise ConfigError(f"{where} is not an integer (got {got}): expected {expected}")
    elif is_bool or not isinstance(value, numbers.Real):
        raise ConfigError(f"{where} is not a number (got {got}): expected {expected}")
    elif not _finite_float(value):
        raise ConfigError(f"{where} is not a finite float64 number: expected {expected}")


def _finite_float(value: Any) -> bool:
    try:
        return math.isfinite(float(value))
    except OverflowError:  # an int beyond float64
        return False


def _check_fields(cfg: Any, section: str, ranges: Mapping[str, _Range]) -> None:
    """Type and range of every field of ``cfg`` (ranges keyed by field name)."""
    for f in dataclasses.fields(cfg):
        value = getattr(cfg, f.name)
        kind = "an integer" if f.type in (int, "int") else "a number"
        rule = ranges.get(f.name, _Range(None, None))
        _check_type(section, f.name, f.type, value, rule.text(kind))
        if f.type not in (bool, "bool") and not rule.contains(value):
            raise ConfigError(f"{section}.{f.name} = {value!r} is out of range: expected "
                              f"{rule.text(kind)}")


def _require(ok: bool, section: str, name: str, value: Any, expected: str) -> None:
    if not ok:
        raise ConfigError(f"{section}.{name} = {value!r} is out of range: expected {expected}")


def _to_core(cfg: Any, core_cls: type) -> Any:
    params = core_cls()
    for f in dataclasses.fields(cfg):
        setattr(params, f.name, getattr(cfg, f.name))
    return params


#: SPEC 1.6 ranges (the C++ SceneFilterParams::validate()); cross-field rules in validate().
_SCENE_FILTER_RANGES = {
    "plane_dist_thresh": _Range(0, 1.0, lo_open=True, unit=" m"),
    "plane_max_tilt_deg": _Range(0, 90, lo_open=True, hi_open=True, unit=" deg"),
    "plane_ransac_iters": _Range(1, 1_000_000),
    "plane_fit_max_points": _Range(3, 10_000_000),
    "plane_min_inlier_ratio": _Range(0, 1),
    "plane_max_count": _Range(1, 100),
    "plane_dominance": _Range(0, 1, lo_open=True),
    "plane_lock_after": _Range(1, 100_000),
    "plane_update_tol_deg": _Range(0, 90, unit=" deg"),
    "plane_update_tol_m": _Range(0, 10, unit=" m"),
    "plane_init_frames": _Range(1, 1_000_000),
    "cluster_eps": _Range(0, 1.0, lo_open=True, unit=" m"),
    "cluster_min_points": _Range(1, 10_000_000),
    "cluster_min_extent": _Range(0, 10, unit=" m"),
    "cluster_max_extent": _Range(None, 100, unit=" m (<= 0 disables the bound)"),
    "band": _Range(0, 1.0, unit=" m"),
    "cluster_voxel_m": _Range(0, 1.0, hi_open=True, unit=" m"),
    "seed": _Range(0, _UINT64_MAX),
    "max_abs_coordinate_m": _Range(0, 1e9, lo_open=True, unit=" m"),
    "segment_smooth_radius_px": _Range(0, 10, unit=" px"),
    "segment_max_step_m": _Range(0, 1.0, lo_open=True, unit=" m"),
    "segment_max_hue_diff_deg": _Range(None, 180.0, unit=" deg (<= 0: colour unused)"),
    "segment_min_saturation": _Range(0, 1),
    "segment_min_brightness": _Range(0, 255),
    "segment_absorb_max_points": _Range(0, 10_000_000, unit=" (0: never)"),
    "segment_nest_fraction": _Range(None, 1.0, unit=" (<= 0: never joined)"),
    "segment_nest_min_slope_deg": _Range(0, 90, hi_open=True, unit=" deg"),
    "segment_nest_max_slope_deg": _Range(0, 90, lo_open=True, hi_open=True, unit=" deg"),
    "segment_nest_rings_px": _Range(2, 50, unit=" px"),
    "depth_noise_sigma_m": _Range(0, 0.1, lo_open=True, unit=" m"),
    "depth_noise_ref_range_m": _Range(0, 100, lo_open=True, unit=" m"),
    "depth_noise_exponent": _Range(0, 4),
    "object_min_height_sigmas": _Range(0, 100, unit=" (0 disables)"),
}

#: SPEC 2.7 ranges (the C++ ObbParams::validate()); cross-field rules in validate().
_OBB_RANGES = {
    "depth_noise_sigma": _Range(0, 0.1, lo_open=True, unit=" m"),
    "top_slice_sigmas": _Range(0, 100, lo_open=True),
    "top_slice_iters": _Range(1, 1000),
    "n_theta": _Range(2, 100_000),
    "width_tol_m": _Range(0, 1, unit=" m"),
    "isotropy_ratio_max": _Range(1, 100),
    "gripper_open": _Range(0, 1, lo_open=True, unit=" m"),
    "min_graspable_width": _Range(0, 1, unit=" m"),
    "min_height": _Range(0, 10, unit=" m"),
    "resting_margin": _Range(0, 1, unit=" m"),
    "side_seen_sigmas": _Range(0, 1000),
    "window": _Range(1, 10_000),
    "assoc_gate_frac": _Range(0, 10, lo_open=True),
    "max_age_s": _Range(0, None, lo_open=True, unit=" s"),
    "nadir_hold_s": _Range(0, None, lo_open=True, unit=" s"),
    "nadir_angle_max_deg": _Range(0, 90, hi_open=True, unit=" deg"),
    "nadir_min_distance_m": _Range(0, 10, unit=" m"),
}


@dataclass(frozen=True)
class SceneFilterConfig:
    """SPEC 1.6: table plane search, persistence and clustering."""

    plane_dist_thresh: float = 0.008
    plane_max_tilt_deg: float = 10.0
    plane_ransac_iters: int = 200
    plane_fit_max_points: int = 4000
    plane_min_inlier_ratio: float = 0.15
    plane_max_count: int = 3
    plane_dominance: float = 0.70
    plane_lock: bool = True
    plane_lock_after: int = 5
    plane_update_tol_deg: float = 5.0
    plane_update_tol_m: float = 0.03
    plane_init_frames: int = 30
    cluster_eps: float = 0.015
    cluster_min_points: int = 20
    cluster_min_extent: float = 0.01
    cluster_max_extent: float = 0.30
    band: float = 0.01
    cluster_voxel_m: float = 0.003
    seed: int = 0
    #: (ours) sane coordinate bound [m]: points with any |coordinate| above it are dropped
    #: and counted (``num_out_of_range``) like NaN rows. Keep equal to the C++ default and
    #: config/scene_filter.yaml.
    max_abs_coordinate_m: float = 1000.0
    #: (ours, issue 12) organized frames: segment the candidates over the image (range steps,
    #: colour boundaries) instead of Euclidean clustering; see organized_segmentation.hpp.
    segment_organized: bool = True
    segment_smooth_radius_px: int = 2
    segment_max_step_m: float = 0.006
    segment_max_hue_diff_deg: float = 20.0
    segment_min_saturation: float = 0.25
    segment_min_brightness: float = 30.0
    segment_absorb_max_points: int = 400
    #: (ours, issue 12) a segment nested in another one across a sloped surface joins it (a
    #: bottle's cap and shoulder seen from above); see nested_segments.hpp.
    segment_nest_fraction: float = 0.9
    segment_nest_min_slope_deg: float = 25.0
    segment_nest_max_slope_deg: float = 80.0
    segment_nest_rings_px: int = 6
    #: (ours, issue 12) depth noise model sigma(r) = sigma * (r / ref)^exponent, and the
    #: range-dependent minimum object height (in sigmas of it; 0 disables).
    depth_noise_sigma_m: float = 0.002
    depth_noise_ref_range_m: float = 0.4
    depth_noise_exponent: float = 2.0
    object_min_height_sigmas: float = 1.0

    def __post_init__(self) -> None:
        self.validate()

    def to_core(self):
        """The C++ ``SceneFilterParams`` with these values (validated)."""
        from .. import _core

        self.validate()
        params = _to_core(self, _core.SceneFilterParams)
        try:
            params.validate()
        except ValueError as exc:
            raise ConfigError(f"scene_filter: {exc}") from None
        return params

    def validate(self) -> None:
        """ConfigError naming the parameter, its value and the allowed range."""
        s = "scene_filter"
        _check_fields(self, s, _SCENE_FILTER_RANGES)
        _require(self.cluster_max_extent <= 0 or self.cluster_max_extent >= self.cluster_min_extent,
                 s, "cluster_max_extent", self.cluster_max_extent,
                 f">= cluster_min_extent = {self.cluster_min_extent:g} m (or <= 0 to disable)")
        _require(self.segment_nest_max_slope_deg > self.segment_nest_min_slope_deg, s,
                 "segment_nest_max_slope_deg", self.segment_nest_max_slope_deg,
                 f"an angle in (segment_nest_min_slope_deg = {self.segment_nest_min_slope_deg:g}, 90) deg")
        _require(self.cluster_voxel_m < self.cluster_eps, s, "cluster_voxel_m", self.cluster_voxel_m,
                 f"a leaf size in [0, cluster_eps = {self.cluster_eps:g}) m (0 = exact)")


@dataclass(frozen=True)
class ObbConfig:
    """SPEC 2.7 (perception part): object estimate, guards and tracker."""

    depth_noise_sigma: float = 0.002
    top_slice_sigmas: float = 4.0
    top_slice_iters: int = 3
    n_theta: int = 361
    width_tol_m: float = 0.002
    isotropy_ratio_max: float = 1.10
    gripper_open: float = 0.08
    min_graspable_width: float = 0.005
    min_height: float = 0.005
    resting_margin: float = 0.008
    side_seen_sigmas: float = 3.0
    window: int = 7
    assoc_gate_frac: float = 0.5
    max_age_s: float = 2.0
    nadir_hold_s: float = 10.0
    nadir_angle_max_deg: float = 5.0
    nadir_min_distance_m: float = 0.25

    def __post_init__(self) -> None:
        self.validate()

    def to_core(self):
        """The C++ ``ObbParams`` with these values (validated)."""
        from .. import _core

        self.validate()
        params = _to_core(self, _core.ObbParams)
        try:
            params.validate()
        except ValueError as exc:
            raise ConfigError(f"obb: {exc}") from None
        return params

    def validate(self) -> None:
        """ConfigError naming the parameter, its value and the allowed range."""
        _check_fields(self, "obb", _OBB_RANGES)
        _require(self.min_graspable_width <= self.gripper_open, "obb", "min_graspable_width",
                 self.min_graspable_width, f"a width in [0, gripper_open = {self.gripper_open:g}] m")


def load_scene_filter_config(path: str | Path | None = None,
                             overrides: Mapping[str, Any] | None = None) -> SceneFilterConfig:
    """``config/scene_filter.yaml`` (+ optional user file and overrides)."""
    return load_config(SceneFilterConfig, "scene_filter", path, overrides)


def load_obb_config(path: str | Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> ObbConfig:
    """``config/obb.yaml`` (+ optional user file and overrides)."""
    return load_config(ObbConfig, "obb", path, overrides)
