"""Parameter set of the evaluation: ``config/grasp_bound.yaml`` (scoring only; the robot never
reads it)."""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import ConfigError


@dataclass(frozen=True)
class GraspBoundConfig:
    """The geometric bound of a grasp (:mod:`.grasp_bound`) and the matching of the robot's
    tracks to the true objects (:mod:`.object_outcomes`); see ``config/grasp_bound.yaml``."""

    max_width_m: float = 0.075
    tilted_limit_deg: float = 60.0
    min_contact_height_m: float = 0.01
    contact_band_m: float = 0.002
    match_distance_m: float = 0.03

    def validate(self) -> None:
        if not 0 < self.max_width_m <= 1.0:
            raise ConfigError(f"grasp_bound.max_width_m = {self.max_width_m}: expected 0 < value <= 1 m")
        if not 0 < self.tilted_limit_deg < 90:
            raise ConfigError(f"grasp_bound.tilted_limit_deg = {self.tilted_limit_deg}: expected 0 < value < 90")
        for name in ("min_contact_height_m", "contact_band_m", "match_distance_m"):
            v = getattr(self, name)
            if not 0 <= v <= 1.0:
                raise ConfigError(f"grasp_bound.{name} = {v}: expected 0 <= value <= 1 m")
