"""Parameters of the scene volume and of the side view that fills it (``config/volume.yaml``).

``volume_*``: the voxel grid (:mod:`.scene_volume`) — its world box, voxel, the occupied band
around each measured surface, the log-odds update, which frames are integrated and what is
forgotten after a grasp attempt. ``side_view_*``: when a target's sides count as unknown
(:mod:`.side_coverage`), the candidate views around it (:mod:`.view_planner`) and the extra
look (:mod:`grasp_pipeline.orchestration.scanning.side_view`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import FRACTION, Range, check_ranges, count, length_m, require

#: What is forgotten after a grasp attempt (``volume_forget``).
FORGET_TARGET, FORGET_ALL, FORGET_NONE = "target", "all", "none"

#: Log-odds bounds of an occupancy update (p = 0.0067 .. 0.9933).
LOGODDS = Range(-5.0, 5.0)


@dataclass(frozen=True)
class VolumeConfig:
    """See ``config/volume.yaml``."""

    volume_box_min_m: tuple[float, ...] = (0.25, -0.40, 0.18)
    volume_box_max_m: tuple[float, ...] = (0.85, 0.40, 0.50)
    volume_voxel_m: float = 0.005
    volume_truncation_m: float = 0.01
    volume_max_range_m: float = 1.2
    volume_logodds_hit: float = 0.85
    volume_logodds_miss: float = -0.4
    volume_logodds_min: float = -2.0
    volume_logodds_max: float = 3.5
    volume_integrate_every_frames: int = 5
    volume_integrate_moved_m: float = 0.005
    volume_integrate_turned_deg: float = 1.0
    volume_forget: str = FORGET_TARGET
    volume_forget_margin_m: float = 0.05
    side_view: bool = True
    side_view_unknown_fraction: float = 0.25
    side_view_shell_m: float = 0.03
    side_view_table_clearance_m: float = 0.015
    side_view_elevations_deg: tuple[float, ...] = (35.0, 47.5, 60.0)
    side_view_azimuth_step_deg: float = 30.0
    side_view_distances_m: tuple[float, ...] = (0.35, 0.45)
    side_view_min_range_m: float = 0.15
    side_view_min_gain_fraction: float = 0.2
    side_view_max_ik_checks: int = 12
    side_view_dwell_frames: int = 5
    side_view_return: bool = True

    RANGES: ClassVar[Mapping[str, Range]] = {
        "volume_box_min_m": Range(-10.0, 10.0, unit=" m"), "volume_box_max_m": Range(-10.0, 10.0, unit=" m"),
        "volume_voxel_m": Range(0.001, 0.1, unit=" m"), "volume_truncation_m": length_m(),
        "volume_max_range_m": length_m(10.0),
        "volume_logodds_hit": Range(0.0, LOGODDS.hi, lo_open=True),  # occupied evidence raises
        "volume_logodds_miss": Range(LOGODDS.lo, 0.0, hi_open=True),  # free evidence lowers
        "volume_logodds_min": LOGODDS, "volume_logodds_max": LOGODDS,
        "volume_integrate_every_frames": count(1, 1000), "volume_integrate_moved_m": length_m(zero=True),
        "volume_integrate_turned_deg": Range(0.0, 180.0, unit=" deg"),
        "volume_forget_margin_m": length_m(0.5, zero=True), "side_view_unknown_fraction": FRACTION,
        "side_view_shell_m": length_m(0.2), "side_view_table_clearance_m": length_m(0.2, zero=True),
        "side_view_elevations_deg": Range(0.0, 90.0, lo_open=True, hi_open=True, unit=" deg"),
        "side_view_azimuth_step_deg": Range(0.0, 180.0, lo_open=True, unit=" deg"),
        "side_view_distances_m": length_m(), "side_view_min_range_m": length_m(zero=True),
        "side_view_min_gain_fraction": FRACTION, "side_view_max_ik_checks": count(1, 1000),
        "side_view_dwell_frames": count(1, 1000),
    }

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """Raise ConfigError naming the first parameter out of range (the voxel grid's own
        limits are checked again by the C++ core): each value's range (``RANGES``), then the
        rules between values (``_validate_rules``)."""
        check_ranges(self, "volume")
        self._validate_rules("volume")

    def _validate_rules(self, v: str) -> None:
        lo, hi = tuple(self.volume_box_min_m), tuple(self.volume_box_max_m)
        for name, box in (("volume_box_min_m", lo), ("volume_box_max_m", hi)):
            require(len(box) == 3, v, name, list(box), "3 finite numbers (x, y, z) in m")
        require(all(b - a >= self.volume_voxel_m for a, b in zip(lo, hi)), v, "volume_box_max_m",
                list(hi), "at least one voxel above volume_box_min_m on every axis")
        require(0.5 * self.volume_voxel_m <= self.volume_truncation_m, v, "volume_truncation_m",
                self.volume_truncation_m, "[volume_voxel_m / 2, 1] m")
        require(self.volume_logodds_max >= self.volume_logodds_hit, v, "volume_logodds_max",
                self.volume_logodds_max, ">= volume_logodds_hit")
        require(self.volume_logodds_min <= self.volume_logodds_miss, v, "volume_logodds_min",
                self.volume_logodds_min, "<= volume_logodds_miss")
        require(self.volume_forget in (FORGET_TARGET, FORGET_ALL, FORGET_NONE), v, "volume_forget",
                self.volume_forget, f"one of {FORGET_TARGET}, {FORGET_ALL}, {FORGET_NONE}")
        require(self.side_view_shell_m >= self.volume_voxel_m, v, "side_view_shell_m",
                self.side_view_shell_m, ">= volume_voxel_m")
        require(len(self.side_view_elevations_deg) > 0, v, "side_view_elevations_deg",
                list(self.side_view_elevations_deg), "a non-empty list of angles in (0, 90) deg above the table")
        dist = tuple(self.side_view_distances_m)
        require(len(dist) > 0 and all(d > self.side_view_min_range_m for d in dist), v,
                "side_view_distances_m", list(dist), "a non-empty list of distances above side_view_min_range_m")
        require(self.side_view_min_range_m < self.volume_max_range_m, v, "side_view_min_range_m",
                self.side_view_min_range_m, "[0, volume_max_range_m) m")
