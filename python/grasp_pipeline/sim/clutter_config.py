"""Parameters of the cluttered scenes: ``config/clutter.yaml`` (VGN/GIGA's packed and pile)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping

from ..config import load_config
from ..config_ranges import (CELL_COORDINATE_M, Range, check_ranges, count, duration_s, length_m,
                             require, require_min_max)


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

    RANGES: ClassVar[Mapping[str, Range]] = {
        "objects_per_scene": count(1, 30),
        "square_center_m": CELL_COORDINATE_M,
        "square_size_m": length_m(),
        "packed_scale": Range(0.0, 3.0, lo_open=True),
        "pile_scale": Range(0.0, 3.0, lo_open=True),
        "placement_attempts": count(1, 1000),
        "placement_gap_m": length_m(0.1, zero=True),
        "drop_height_m": length_m(),
        "settle_s": duration_s(60.0),
        "box_wall_height_m": length_m(),
        "box_wall_thickness_m": length_m(0.1),
    }

    def validate(self) -> None:
        check_ranges(self, "clutter")
        require(len(self.square_center_m) == 2, "clutter", "square_center_m",
                self.square_center_m, "(x, y)")
        for name in ("packed_scale", "pile_scale"):
            require_min_max("clutter", name, getattr(self, name))


def load_clutter_config(path: str | Path | None = None,
                        overrides: Mapping[str, Any] | None = None) -> ClutterConfig:
    return load_config(ClutterConfig, "clutter", path=path, overrides=overrides)
