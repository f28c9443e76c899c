"""The PLACE stage's parameters (``config/place.yaml``): carrying the held object to the tray,
choosing where it goes, lowering and releasing it, and looking whether it arrived."""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..exceptions import ConfigError


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

    def validate(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if not v > 0 or v != v:
                raise ConfigError(f"PlaceConfig.{f.name} = {v}: expected a positive number")
        if self.release_clearance_m >= self.release_max_drop_m:
            raise ConfigError(f"PlaceConfig.release_clearance_m = {self.release_clearance_m} must be "
                              f"below release_max_drop_m = {self.release_max_drop_m} (the aimed "
                              "release height would count as a release from high)")
        if self.lower_step_m > self.release_max_drop_m - self.release_clearance_m:
            raise ConfigError(f"PlaceConfig.lower_step_m = {self.lower_step_m}: expected at most "
                              "release_max_drop_m - release_clearance_m (the search would step "
                              "past the heights a release may start from)")
        if self.arrival_height_m >= self.carry_height_m + 0.5:
            raise ConfigError("PlaceConfig.arrival_height_m: expected a height near the tray "
                              "(below carry_height_m + 0.5 m)")
