"""Typed parameter sets of the perception core (method.md §1.6 and 2.7).

Field names and defaults are those of docs/method.md §1.6 and §2.7; the YAML files are
``config/scene_filter.yaml`` and ``config/obb.yaml``.

Every value is checked here, in Python, before it reaches C++ (at construction, in
``__post_init__``, and again by ``validate()``): its type (a bool for a switch, an integer
for a count, a finite real number otherwise) and its range, which mirrors the C++ core's
``validate()`` (tests pin that the two agree at every bound). A bad value raises
:class:`ConfigError` naming the section, the parameter, the value and the allowed range,
e.g. ``scene_filter.plane_ransac_iters = 1000000000000 is out of range: expected an integer
in [1, 1000000]`` — never a raw pybind ``TypeError`` (the one validator of every parameter
set, :func:`grasp_pipeline.config_ranges.check_ranges`). ``to_core()`` then runs the C++
``validate()`` as a second line of defence.

Two facts the C++ parameter sets hold are not parameters of these sets, so that they cannot
disagree with their one definition: the depth noise (``depth_noise_sigma_m`` and its range
model, the sensor's: :mod:`grasp_pipeline.robot.depth_noise`, ``config/depth_noise.yaml``) and
the gripper's opening (``ObbParams.gripper_open``, the robot's:
:data:`grasp_pipeline.robot.limits.GRIPPER_MAX_WIDTH_M`). ``to_core(depth_noise)`` fills them in.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping

from ..config import load_config
from ..config_ranges import OPENING_M, UINT64_MAX, Range, check_ranges, require
from ..exceptions import ConfigError
from ..robot.depth_noise import DepthNoiseConfig
from ..robot.limits import GRIPPER_MAX_WIDTH_M


def _to_core(cfg: Any, core_cls: type, section: str, **facts: float) -> Any:
    """The C++ parameter set ``core_cls`` with ``cfg``'s values and ``facts`` (values defined
    elsewhere, see the module doc), validated by the core."""
    params = core_cls()
    for f in dataclasses.fields(cfg):
        setattr(params, f.name, getattr(cfg, f.name))
    for name, value in facts.items():
        setattr(params, name, value)
    try:
        params.validate()
    except ValueError as exc:
        raise ConfigError(f"{section}: {exc}") from None
    return params


#: method.md §1.6 ranges (the C++ SceneFilterParams::validate()); cross-field rules in validate().
_SCENE_FILTER_RANGES = {
    "plane_dist_thresh": Range(0, 1.0, lo_open=True, unit=" m"),
    "plane_max_tilt_deg": Range(0, 90, lo_open=True, hi_open=True, unit=" deg"),
    "plane_ransac_iters": Range(1, 1_000_000),
    "plane_fit_max_points": Range(3, 10_000_000),
    "plane_min_inlier_ratio": Range(0, 1),
    "plane_max_count": Range(1, 100),
    "plane_dominance": Range(0, 1, lo_open=True),
    "plane_lock_after": Range(1, 100_000),
    "plane_update_tol_deg": Range(0, 90, unit=" deg"),
    "plane_update_tol_m": Range(0, 10, unit=" m"),
    "plane_init_frames": Range(1, 1_000_000),
    "cluster_eps": Range(0, 1.0, lo_open=True, unit=" m"),
    "cluster_min_points": Range(1, 10_000_000),
    "cluster_min_extent": Range(0, 10, unit=" m"),
    "cluster_max_extent": Range(None, 100, unit=" m (<= 0 disables the bound)"),
    "band": Range(0, 1.0, unit=" m"),
    "cluster_voxel_m": Range(0, 1.0, hi_open=True, unit=" m"),
    "seed": Range(0, UINT64_MAX),
    "max_abs_coordinate_m": Range(0, 1e9, lo_open=True, unit=" m"),
    "segment_smooth_radius_px": Range(0, 10, unit=" px"),
    "segment_max_step_m": Range(0, 1.0, lo_open=True, unit=" m"),
    "segment_max_hue_diff_deg": Range(None, 180.0, unit=" deg (<= 0: colour unused)"),
    "segment_min_saturation": Range(0, 1),
    "segment_min_brightness": Range(0, 255),
    "segment_absorb_max_points": Range(0, 10_000_000, unit=" (0: never)"),
    "segment_nest_fraction": Range(None, 1.0, unit=" (<= 0: never joined)"),
    "segment_nest_min_slope_deg": Range(0, 90, hi_open=True, unit=" deg"),
    "segment_nest_max_slope_deg": Range(0, 90, lo_open=True, hi_open=True, unit=" deg"),
    "segment_nest_rings_px": Range(2, 50, unit=" px"),
    "object_min_height_sigmas": Range(0, 100, unit=" (0 disables)"),
}

#: method.md §2.7 ranges (the C++ ObbParams::validate()); cross-field rules in validate().
_OBB_RANGES = {
    "top_slice_sigmas": Range(0, 100, lo_open=True),
    "top_slice_iters": Range(1, 1000),
    "n_theta": Range(2, 100_000),
    "width_tol_m": Range(0, 1, unit=" m"),
    "isotropy_ratio_max": Range(1, 100),
    "min_graspable_width": OPENING_M,
    "min_height": Range(0, 10, unit=" m"),
    "resting_margin": Range(0, 1, unit=" m"),
    "side_seen_sigmas": Range(0, 1000),
    "window": Range(1, 10_000),
    "assoc_gate_frac": Range(0, 10, lo_open=True),
    "max_age_s": Range(0, None, lo_open=True, unit=" s"),
    "nadir_hold_s": Range(0, None, lo_open=True, unit=" s"),
    "nadir_angle_max_deg": Range(0, 90, hi_open=True, unit=" deg"),
    "nadir_min_distance_m": Range(0, 10, unit=" m"),
}


@dataclass(frozen=True)
class SceneFilterConfig:
    """method.md §1.6: table plane search, persistence and clustering."""

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
    #: (ours) organized frames: segment the candidates over the image (range steps,
    #: colour boundaries) instead of Euclidean clustering; see organized_segmentation.hpp.
    segment_organized: bool = True
    segment_smooth_radius_px: int = 2
    segment_max_step_m: float = 0.006
    segment_max_hue_diff_deg: float = 20.0
    segment_min_saturation: float = 0.25
    segment_min_brightness: float = 30.0
    segment_absorb_max_points: int = 400
    #: (ours) a segment nested in another one across a sloped surface joins it (a
    #: bottle's cap and shoulder seen from above); see nested_segments.hpp.
    segment_nest_fraction: float = 0.9
    segment_nest_min_slope_deg: float = 25.0
    segment_nest_max_slope_deg: float = 80.0
    segment_nest_rings_px: int = 6
    #: (ours) the range-dependent minimum object height, in sigmas of the depth noise
    #: (config/depth_noise.yaml; 0 disables).
    object_min_height_sigmas: float = 1.0

    RANGES: ClassVar[Mapping[str, Range]] = _SCENE_FILTER_RANGES

    def __post_init__(self) -> None:
        self.validate()

    def to_core(self, depth_noise: DepthNoiseConfig):
        """The C++ ``SceneFilterParams`` with these values and the sensor's ``depth_noise``
        model (validated)."""
        from .. import _core

        self.validate()
        return _to_core(self, _core.SceneFilterParams, "scene_filter",
                        depth_noise_sigma_m=depth_noise.depth_noise_sigma_m,
                        depth_noise_ref_range_m=depth_noise.depth_noise_ref_range_m,
                        depth_noise_exponent=depth_noise.depth_noise_exponent)

    def validate(self) -> None:
        """ConfigError naming the parameter, its value and the allowed range."""
        check_ranges(self, "scene_filter")
        s = "scene_filter"
        require(self.cluster_max_extent <= 0 or self.cluster_max_extent >= self.cluster_min_extent,
                 s, "cluster_max_extent", self.cluster_max_extent,
                 f">= cluster_min_extent = {self.cluster_min_extent:g} m (or <= 0 to disable)")
        require(self.segment_nest_max_slope_deg > self.segment_nest_min_slope_deg, s,
                 "segment_nest_max_slope_deg", self.segment_nest_max_slope_deg,
                 f"an angle in (segment_nest_min_slope_deg = {self.segment_nest_min_slope_deg:g}, 90) deg")
        require(self.cluster_voxel_m < self.cluster_eps, s, "cluster_voxel_m", self.cluster_voxel_m,
                 f"a leaf size in [0, cluster_eps = {self.cluster_eps:g}) m (0 = exact)")


@dataclass(frozen=True)
class ObbConfig:
    """method.md §2.7 (perception part): object estimate, guards and tracker. method.md's
    ``depth_noise_sigma`` is the sensor's (``config/depth_noise.yaml``) and ``gripper_open``
    the robot's largest opening (robot/limits.py): :meth:`to_core` fills them in."""

    top_slice_sigmas: float = 4.0
    top_slice_iters: int = 3
    n_theta: int = 361
    width_tol_m: float = 0.002
    isotropy_ratio_max: float = 1.10
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

    RANGES: ClassVar[Mapping[str, Range]] = _OBB_RANGES

    def __post_init__(self) -> None:
        self.validate()

    def to_core(self, depth_noise: DepthNoiseConfig):
        """The C++ ``ObbParams`` with these values, the sensor's noise sigma and the gripper's
        opening (validated)."""
        from .. import _core

        self.validate()
        return _to_core(self, _core.ObbParams, "obb", depth_noise_sigma=depth_noise.depth_noise_sigma_m,
                        gripper_open=GRIPPER_MAX_WIDTH_M)

    def validate(self) -> None:
        """ConfigError naming the parameter, its value and the allowed range."""
        check_ranges(self, "obb")


def load_scene_filter_config(path: str | Path | None = None,
                             overrides: Mapping[str, Any] | None = None) -> SceneFilterConfig:
    """``config/scene_filter.yaml`` (+ optional user file and overrides)."""
    return load_config(SceneFilterConfig, "scene_filter", path, overrides)


def load_obb_config(path: str | Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> ObbConfig:
    """``config/obb.yaml`` (+ optional user file and overrides)."""
    return load_config(ObbConfig, "obb", path, overrides)
