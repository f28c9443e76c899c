"""Parameter sets of the orchestration: ``config/scan.yaml``, ``config/grasp.yaml``,
``config/declutter.yaml`` and ``config/grasp_fit.yaml``. Each declares the range of every number
(``RANGES``, checked by :func:`grasp_pipeline.config_ranges.check_ranges`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import (FORCE_N, OPENING_M, POSITIVE_FRACTION, Range, angle_rad,
                             check_ranges, count, duration_s, length_m, require, step_m)
from ..exceptions import ConfigError
from .grasping.source_names import grasp_source_names

#: What makes a segment ambiguous (:mod:`.scanning.ambiguity`): a footprint wider than the
#: gripper in every direction; a non-convex outline.
CLOSER_LOOK_RULES = ("wide", "non_convex")


@dataclass(frozen=True)
class ScanConfig:
    """method.md §6 active scan and perception liveness."""

    dwell_frames: int = 5
    dwell_timeout_s: float = 5.0
    stale_timeout_s: float = 2.0
    return_to_start: bool = True
    select_verify_frames: int = 3
    select_max_distance_m: float = 0.10
    return_settle_tol_rad: float = 1e-4
    return_settle_timeout_s: float = 1.0
    rough_view_s: float = 0.5
    settle_view_s: float = 0.3
    target_view_timeout_s: float = 0.3
    scan_timeout_s: float = 120.0
    closer_look: bool = True
    closer_look_rules: tuple[str, ...] = ("wide",)
    closer_look_standoff_m: float = 0.25
    closer_look_min_solidity: float = 0.80
    closer_look_cell_m: float = 0.004
    closer_look_min_points: int = 30

    RANGES: ClassVar[Mapping[str, Range]] = {
        "dwell_frames": count(0, 1000),
        "dwell_timeout_s": duration_s(600.0),
        "stale_timeout_s": duration_s(600.0),
        "select_verify_frames": count(0, 1000),
        "select_max_distance_m": length_m(),
        "return_settle_tol_rad": angle_rad(0.1),
        "return_settle_timeout_s": duration_s(600.0),
        "rough_view_s": duration_s(600.0),
        "settle_view_s": duration_s(600.0, zero=True),
        "target_view_timeout_s": duration_s(600.0, zero=True),
        "scan_timeout_s": duration_s(),
        "closer_look_standoff_m": length_m(),
        "closer_look_min_solidity": POSITIVE_FRACTION,
        "closer_look_cell_m": step_m(),
        "closer_look_min_points": count(1, 1_000_000),
    }

    def validate(self) -> None:
        check_ranges(self, "scan")
        unknown = sorted(set(self.closer_look_rules) - set(CLOSER_LOOK_RULES))
        if unknown:
            raise ConfigError(f"scan.closer_look_rules: unknown rule(s) {unknown}; "
                              f"choose from {list(CLOSER_LOOK_RULES)}")


@dataclass(frozen=True)
class GraspConfig:
    """method.md §7 grasp action (the PLACE stage's parameters: :class:`~.place_config.PlaceConfig`)."""

    pre_grasp_distance_m: float = 0.12
    fragment_margin_m: float = 0.01
    target_fixture_margin_m: float = 0.03
    rough_takeover_m: float = 0.02
    approach_backoffs_m: tuple[float, ...] = (0.0, 0.008, 0.015)
    open_margin_m: float = 0.02
    close_effort_N: float = 40.0
    close_command_fraction: float = 0.5
    close_squeeze_m: float = 0.01
    gripper_goal_tolerance_m: float = 0.001
    stall_speed_mps: float = 0.005
    stall_time_s: float = 0.5
    stall_gap_band_m: float = 0.0005
    close_timeout_s: float = 8.0
    fully_closed_gap_m: float = 0.004
    held_gap_drop_m: float = 0.003
    held_min_force_N: float = 5.0
    hold_by_force: bool = True
    lift_height_m: float = 0.10
    hold_check_s: float = 2.0
    retreat_height_m: float = 0.10
    release_wait_s: float = 0.6
    pick_timeout_s: float = 90.0
    table_clearance_m: float = 0.004
    palm_clearance_m: float = 0.01
    grasp_source: str = "any_side"

    RANGES: ClassVar[Mapping[str, Range]] = {
        "pre_grasp_distance_m": length_m(0.5),
        "fragment_margin_m": length_m(0.2),
        "target_fixture_margin_m": length_m(0.5),
        "rough_takeover_m": length_m(0.2),
        "approach_backoffs_m": length_m(0.05, zero=True),
        "open_margin_m": Range(0.0, OPENING_M.hi, lo_open=True, unit=" m"),
        "close_effort_N": FORCE_N,
        "close_command_fraction": POSITIVE_FRACTION,
        "close_squeeze_m": OPENING_M,
        "gripper_goal_tolerance_m": length_m(0.01),
        "stall_speed_mps": Range(0.0, 0.2, lo_open=True, unit=" m/s"),
        "stall_time_s": duration_s(60.0),
        "stall_gap_band_m": length_m(0.01),
        "close_timeout_s": duration_s(600.0),
        "fully_closed_gap_m": Range(0.0, OPENING_M.hi, lo_open=True, unit=" m"),
        "held_gap_drop_m": Range(0.0, OPENING_M.hi, lo_open=True, unit=" m"),
        "held_min_force_N": FORCE_N,
        "lift_height_m": length_m(0.5),
        "hold_check_s": duration_s(600.0),
        "retreat_height_m": length_m(0.5),
        "release_wait_s": duration_s(60.0),
        "pick_timeout_s": duration_s(),
        "table_clearance_m": length_m(0.1),
        "palm_clearance_m": length_m(0.1),
    }

    def validate(self) -> None:
        check_ranges(self, "grasp")
        require(len(self.approach_backoffs_m) > 0, "grasp", "approach_backoffs_m",
                self.approach_backoffs_m, "a non-empty list of back-offs in [0, 0.05] m")
        require(self.held_min_force_N <= self.close_effort_N, "grasp", "held_min_force_N",
                self.held_min_force_N, f"a force <= close_effort_N = {self.close_effort_N:g} N "
                "(the grip cannot press harder than it closes)")
        names = grasp_source_names()
        if self.grasp_source not in names:
            raise ConfigError(f"grasp.grasp_source = {self.grasp_source!r}: expected one of "
                              f"{', '.join(names)}")



@dataclass(frozen=True)
class DeclutterConfig:
    """Clearing a table (``run --declutter``, ``bench clutter``): the round rules of the
    VGN/GIGA benchmarks plus our choice of the next target."""

    max_consecutive_failures: int = 2
    max_attempts: int = 20
    failed_anchor_radius_m: float = 0.03
    order: str = "score"
    free_space_enough_m: float = 0.03

    RANGES: ClassVar[Mapping[str, Range]] = {
        "max_consecutive_failures": count(1, 1000),
        "max_attempts": count(1, 1000),
        "failed_anchor_radius_m": length_m(0.5, zero=True),
        "free_space_enough_m": Range(0.0, OPENING_M.hi, unit=" m"),
    }

    def validate(self) -> None:
        check_ranges(self, "declutter")
        if self.order not in ("score", "accessibility", "nearest"):
            raise ConfigError(f"declutter.order = {self.order!r}: expected 'score', 'accessibility' "
                              "or 'nearest'")


@dataclass(frozen=True)
class GraspFitConfig:
    """Grasps fitted to the perceived points and the support rule (ours; docs/method.md §3.2 and
    §2.8, extending method.md §3 and §2.6)."""

    cloud_voxel_m: float = 0.003
    support_gap_m: float = 0.015
    support_ring_m: float = 0.015
    see_through_fraction: float = 0.5
    footprint_cell_m: float = 0.005
    box_sample_step_m: float = 0.0025
    line_step_m: float = 0.006
    min_material_points: int = 4
    blocked_points: int = 2
    column_tolerance_m: float = 0.002
    clearance_enough_m: float = 0.008
    max_candidates: int = 4
    min_pad_overlap_m: float = 0.012
    contact_depth_m: float = 0.005
    min_contact_fraction: float = 0.5
    max_centroid_offset_m: float = 0.02
    min_open_margin_m: float = 0.008
    level_gap_m: float = 0.01
    level_min_columns: int = 4

    RANGES: ClassVar[Mapping[str, Range]] = {
        "cloud_voxel_m": step_m(),
        "support_gap_m": length_m(0.1),
        "support_ring_m": length_m(0.1, zero=True),
        "see_through_fraction": POSITIVE_FRACTION,
        "footprint_cell_m": step_m(),
        "box_sample_step_m": step_m(),
        "line_step_m": step_m(),
        "min_material_points": count(1, 10_000),
        "blocked_points": count(0, 10_000),
        "column_tolerance_m": length_m(0.02, zero=True),
        "clearance_enough_m": OPENING_M,
        "max_candidates": count(1, 100),
        "min_pad_overlap_m": length_m(0.05, zero=True),
        "contact_depth_m": length_m(0.05),
        "min_contact_fraction": POSITIVE_FRACTION,
        "max_centroid_offset_m": length_m(0.2),
        "min_open_margin_m": Range(0.0, OPENING_M.hi, lo_open=True, hi_open=True, unit=" m"),
        "level_gap_m": length_m(0.2),
        "level_min_columns": count(1, 1000),
    }

    def validate(self) -> None:
        check_ranges(self, "grasp_fit")
