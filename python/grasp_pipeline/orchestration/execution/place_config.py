"""The PLACE stage's parameters (``config/place.yaml``): carrying the held object to the tray,
choosing where it goes, lowering and releasing it, and looking whether it arrived."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ...config_ranges import Range, check_ranges, count, duration_s, length_m, require


@dataclass(frozen=True)
class PlaceConfig:
    """Where and how the held object is put into the tray (see ``config/place.yaml``)."""

    carry_height_m: float = 0.30
    arrival_height_m: float = 0.15
    hang_clearance_m: float = 0.03
    release_clearance_m: float = 0.015
    release_max_drop_m: float = 0.03
    lower_step_m: float = 0.003
    lower_attempts: int = 3
    lower_backoff_m: float = 0.03
    touch_down_m: float = 0.005
    slot_dx_m: float = 0.05
    slot_dy_m: float = 0.08
    spot_cell_m: float = 0.005
    spot_spacing_m: float = 0.005
    spot_separation_m: float = 0.03
    arrival_spots: int = 6
    stack_max_m: float = 0.08
    look_height_m: float = 0.35
    look_frames: int = 2
    look_timeout_s: float = 1.0
    seen_min_height_m: float = 0.008
    arrived_min_area_m2: float = 0.0002
    arrived_search_m: float = 0.05
    arrived_max_above_m: float = 0.03

    RANGES: ClassVar[Mapping[str, Range]] = {
        "carry_height_m": length_m(0.8),
        "arrival_height_m": length_m(0.6),
        "hang_clearance_m": length_m(0.3),
        "release_clearance_m": length_m(0.1),
        "release_max_drop_m": length_m(0.2),
        "lower_step_m": length_m(0.05),
        "lower_attempts": count(1, 20),
        "lower_backoff_m": length_m(0.2),
        "touch_down_m": length_m(0.1),
        "slot_dx_m": length_m(0.2),
        "slot_dy_m": length_m(0.2),
        "spot_cell_m": length_m(0.05),
        "spot_spacing_m": length_m(0.1),
        "spot_separation_m": length_m(0.3),
        "arrival_spots": count(1, 100),
        "stack_max_m": length_m(0.3),
        "look_height_m": length_m(1.0),
        "look_frames": count(1, 30),
        "look_timeout_s": duration_s(60.0),
        "seen_min_height_m": length_m(0.1),
        "arrived_min_area_m2": Range(0.0, 0.25, lo_open=True, unit=" m^2"),
        "arrived_search_m": length_m(0.3),
        "arrived_max_above_m": length_m(0.3),
    }

    def validate(self) -> None:
        check_ranges(self, "place")
        require(self.release_clearance_m < self.release_max_drop_m, "place", "release_clearance_m",
                self.release_clearance_m, f"a height below release_max_drop_m = "
                f"{self.release_max_drop_m:g} m (the aimed release height would count as a "
                "release from high)")
        require(self.lower_step_m <= self.release_max_drop_m - self.release_clearance_m, "place",
                "lower_step_m", self.lower_step_m, "at most release_max_drop_m - "
                "release_clearance_m (the search would step past the heights a release may "
                "start from)")
        require(self.arrival_height_m < self.carry_height_m + 0.5, "place", "arrival_height_m",
                self.arrival_height_m, "a height near the tray (below carry_height_m + 0.5 m)")
