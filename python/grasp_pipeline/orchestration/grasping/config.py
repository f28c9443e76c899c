"""Parameters of the any-side (6-DoF) grasp sampler: ``config/grasp_sampler.yaml``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ...config_ranges import (FRACTION, POSITIVE_FRACTION, Range, check_ranges, count, length_m,
                              require, step_m)

#: A weight of the score (0: the term does not count).
WEIGHT = Range(0.0, 100.0)


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
    step_levels: int = 2
    max_cell_m: float = 0.009
    preselect: int = 40
    preselect_batches: int = 3
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

    RANGES: ClassVar[Mapping[str, Range]] = {
        "max_tilt_deg": Range(0.0, 90.0, unit=" deg"),
        "tilts_deg": Range(0.0, 90.0, lo_open=True, unit=" deg"),
        "azimuths": count(1, 72), "rotations": count(1, 72), "normal_axes": count(0, 64),
        "lines": count(1, 21), "line_spacing_m": step_m(0.05), "cell_m": step_m(0.02),
        "max_cell_m": step_m(0.02), "max_points": count(50, 20000),
        "step_levels": count(0, 5), "preselect": count(1, 2000),
        "preselect_batches": count(1, 50),
        "approach_checks_m": length_m(0.3, zero=True), "max_raise_m": length_m(0.1, zero=True),
        "reach_candidates": count(1, 200), "max_proposals": count(1, 200),
        "duplicate_distance_m": length_m(0.1, zero=True),
        "duplicate_angle_deg": Range(0.0, 90.0, lo_open=True, unit=" deg"),
        "unknown_max_fraction": POSITIVE_FRACTION,
        "friction_cone_deg": Range(0.0, 90.0, lo_open=True, hi_open=True, unit=" deg"),
        "min_facing_fraction": FRACTION,
        "centre_scale_m": length_m(0.5), "width_scale_m": length_m(0.5),
        "hand_clearance_enough_m": length_m(0.5),
        **{f"weight_{w}": WEIGHT for w in ("coverage", "antipodal", "centre", "depth", "width",
                                            "overlap", "tilt", "clearance", "unknown")},
    }

    def validate(self) -> None:
        check_ranges(self, "grasp_sampler")
        require(self.cell_m <= self.max_cell_m, "grasp_sampler", "cell_m", self.cell_m,
                f"a cell no coarser than max_cell_m = {self.max_cell_m:g} m")
