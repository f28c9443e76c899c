"""Parameters of the cluttered scenes: ``config/clutter.yaml`` (VGN/GIGA's packed and pile)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..config import load_config
from ..exceptions import ConfigError


@dataclass(frozen=True)
class ClutterConfig:
    """See ``config/clutter.yaml`` for every parameter's meaning."""

    objects_per_scene: int = 5
    square_center_m: tuple[float, ...] = (0.52, 0.0)
    square_size_m: float = 0.30
    packed_scale: tuple[float, ...] = (0.7, 0.9)
    pile_scale: tuple[float, ...] = (0.8, 1.0)
    placement_attempts: int = 12
    placement_gap_m: float = 0.002
    drop_height_m: float = 0.2
    settle_s: float = 1.5
    box_wall_height_m: float = 0.15
    box_wall_thickness_m: float = 0.01

    def validate(self) -> None:
        if not 1 <= self.objects_per_scene <= 30:
            raise ConfigError(f"clutter.objects_per_scene must be 1..30, got {self.objects_per_scene}")
        if len(self.square_center_m) != 2:
            raise ConfigError("clutter.square_center_m needs (x, y)")
        for name in ("packed_scale", "pile_scale"):
            lo_hi = getattr(self, name)
            if len(lo_hi) != 2 or not 0 < lo_hi[0] <= lo_hi[1] <= 3:
                raise ConfigError(f"clutter.{name} must be [min, max] with 0 < min <= max <= 3, got {lo_hi}")
        for name in ("square_size_m", "drop_height_m", "settle_s", "box_wall_height_m",
                     "box_wall_thickness_m"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"clutter.{name} must be > 0, got {getattr(self, name)}")
        if self.placement_attempts < 1 or self.placement_gap_m < 0:
            raise ConfigError("clutter.placement_attempts must be >= 1 and placement_gap_m >= 0")


def load_clutter_config(path: str | Path | None = None,
                        overrides: Mapping[str, Any] | None = None) -> ClutterConfig:
    return load_config(ClutterConfig, "clutter", path=path, overrides=overrides)
