"""Parameters of the any-side (6-DoF) grasp sampler: ``config/grasp_sampler.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

from ...exceptions import ConfigError


@dataclass(frozen=True)
class SamplerConfig:
    """How the any-side sampler proposes grasps (see :mod:`.any_side`)."""

    max_tilt_deg: float = 60.0
    tilts_deg: tuple[float, ...] = (20.0, 40.0, 60.0)
    azimuths: int = 6
    rotations: int = 12
    normal_axes: int = 4
    lines: int = 3
    line_spacing_m: float = 0.008
    cell_m: float = 0.005
    max_points: int = 1200
    max_cell_m: float = 0.009
    preselect: int = 40
    reach_candidates: int = 10
    max_proposals: int = 6
    approach_checks_m: tuple[float, ...] = (0.0, 0.03, 0.06)
    duplicate_distance_m: float = 0.008
    max_raise_m: float = 0.03
    duplicate_angle_deg: float = 15.0
    centre_scale_m: float = 0.03
    width_scale_m: float = 0.02
    weight_coverage: float = 1.0
    weight_antipodal: float = 2.0
    weight_centre: float = 1.0
    weight_depth: float = 0.5
    weight_width: float = 1.0
    weight_overlap: float = 0.5
    weight_tilt: float = 3.0
    weight_clearance: float = 0.5
    hand_clearance_enough_m: float = 0.01
    unknown_max_fraction: float = 0.5
    friction_cone_deg: float = 35.0
    min_facing_fraction: float = 0.25
    weight_unknown: float = 1.0

    def validate(self) -> None:
        if not 0.0 <= self.max_tilt_deg <= 90.0:
            raise ConfigError(f"SamplerConfig.max_tilt_deg = {self.max_tilt_deg}: expected 0-90 deg")
        if any(not 0.0 < t <= 90.0 for t in self.tilts_deg):
            raise ConfigError("SamplerConfig.tilts_deg: expected tilts in (0, 90] deg")
        for name in ("azimuths", "rotations", "lines", "max_points", "preselect",
                     "reach_candidates", "max_proposals"):
            v = getattr(self, name)
            if not 1 <= v <= 100000:
                raise ConfigError(f"SamplerConfig.{name} = {v}: expected an integer in [1, 100000]")
        if not 0 <= self.normal_axes <= 1000:
            raise ConfigError(f"SamplerConfig.normal_axes = {self.normal_axes}: expected 0-1000")
        for name in ("line_spacing_m", "cell_m", "max_cell_m", "duplicate_distance_m", "max_raise_m", "centre_scale_m", "width_scale_m",
                     "hand_clearance_enough_m"):
            v = getattr(self, name)
            if not 0.0 < v <= 0.5:
                raise ConfigError(f"SamplerConfig.{name} = {v}: expected (0, 0.5] m")
        if not self.approach_checks_m or any(not 0.0 <= b <= 0.3 for b in self.approach_checks_m):
            raise ConfigError("SamplerConfig.approach_checks_m: expected distances in [0, 0.3] m")
        if not 0.0 <= self.min_facing_fraction <= 1.0:
            raise ConfigError("SamplerConfig.min_facing_fraction: expected [0, 1]")
        if not 0.0 < self.friction_cone_deg < 90.0:
            raise ConfigError("SamplerConfig.friction_cone_deg: expected (0, 90) deg")
        if not 0.0 < self.duplicate_angle_deg <= 90.0:
            raise ConfigError("SamplerConfig.duplicate_angle_deg: expected (0, 90] deg")
        if not 0.0 <= self.unknown_max_fraction <= 1.0:
            raise ConfigError("SamplerConfig.unknown_max_fraction: expected [0, 1]")
        for name in ("weight_coverage", "weight_antipodal", "weight_centre", "weight_depth",
                     "weight_width", "weight_overlap", "weight_tilt", "weight_clearance",
                     "weight_unknown"):
            v = getattr(self, name)
            if not 0.0 <= v <= 100.0:
                raise ConfigError(f"SamplerConfig.{name} = {v}: expected a weight in [0, 100]")
