"""Parameter set of the evaluation: ``config/grasp_bound.yaml`` (scoring only; the robot never
reads it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import OPENING_M, Range, check_ranges, length_m


@dataclass(frozen=True)
class GraspBoundConfig:
    """The geometric bound of a grasp (:mod:`.grasp_bound`) and the matching of the robot's
    tracks to the true objects (:mod:`.object_outcomes`); see ``config/grasp_bound.yaml``."""

    max_width_m: float = 0.075
    tilted_limit_deg: float = 60.0
    min_contact_height_m: float = 0.01
    contact_band_m: float = 0.002
    match_distance_m: float = 0.03

    RANGES: ClassVar[Mapping[str, Range]] = {
        "max_width_m": Range(0.0, OPENING_M.hi, lo_open=True, unit=" m"),
        "tilted_limit_deg": Range(0.0, 90.0, lo_open=True, hi_open=True, unit=" deg"),
        "min_contact_height_m": length_m(zero=True), "contact_band_m": length_m(zero=True),
        "match_distance_m": length_m(zero=True),
    }

    def validate(self) -> None:
        check_ranges(self, "grasp_bound")
