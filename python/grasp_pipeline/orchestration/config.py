"""Parameter sets of the orchestration: ``config/scan.yaml`` and ``config/grasp.yaml``."""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..exceptions import ConfigError


def _positive(obj, *names: str, allow_zero: bool = False) -> None:
    for n in names:
        v = getattr(obj, n)
        if not (v >= 0 if allow_zero else v > 0) or v != v:
            raise ConfigError(f"{type(obj).__name__}.{n} = {v}: expected a "
                              f"{'non-negative' if allow_zero else 'positive'} number")


#: What makes a segment ambiguous (:mod:`.ambiguity`): a footprint wider than the gripper in
#: every direction; a non-convex outline.
CLOSER_LOOK_RULES = ("wide", "non_convex")


@dataclass(frozen=True)
class ScanConfig:
    """SPEC 6 active scan and perception liveness."""

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
    scan_timeout_s: float = 120.0
    closer_look: bool = True
    closer_look_rules: tuple[str, ...] = ("wide",)
    closer_look_standoff_m: float = 0.25
    closer_look_min_solidity: float = 0.80
    closer_look_cell_m: float = 0.004
    closer_look_min_points: int = 30

    def validate(self) -> None:
        _positive(self, "closer_look_standoff_m", "closer_look_cell_m", "closer_look_min_points")
        unknown = sorted(set(self.closer_look_rules) - set(CLOSER_LOOK_RULES))
        if unknown:
            raise ConfigError(f"ScanConfig.closer_look_rules: unknown rule(s) {unknown}; "
                              f"choose from {list(CLOSER_LOOK_RULES)}")
        if not 0.0 < self.closer_look_min_solidity <= 1.0:
            raise ConfigError(f"ScanConfig.closer_look_min_solidity = {self.closer_look_min_solidity}: "
                              "expected a fraction in (0, 1]")
        _positive(self, "dwell_timeout_s", "stale_timeout_s", "return_settle_tol_rad",
                  "select_max_distance_m",
                  "return_settle_timeout_s", "rough_view_s", "scan_timeout_s")
        _positive(self, "settle_view_s", allow_zero=True)
        _positive(self, "dwell_frames", "select_verify_frames", allow_zero=True)


#: The grasp sources ``grasp.grasp_source`` may name.
GRASP_SOURCES = ("any_side", "top_down")


@dataclass(frozen=True)
class GraspConfig:
    """SPEC 7 grasp action (the PLACE stage's parameters: :class:`~.place_config.PlaceConfig`)."""

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
    lift_height_m: float = 0.10
    hold_check_s: float = 2.0
    retreat_height_m: float = 0.10
    release_wait_s: float = 0.6
    pick_timeout_s: float = 90.0
    table_clearance_m: float = 0.004
    palm_clearance_m: float = 0.01
    grasp_source: str = "any_side"

    def validate(self) -> None:
        _positive(self, *(f.name for f in fields(self)
                          if f.name not in ("close_squeeze_m", "approach_backoffs_m", "grasp_source")))
        if self.grasp_source not in GRASP_SOURCES:
            raise ConfigError(f"GraspConfig.grasp_source = {self.grasp_source!r}: expected one of "
                              f"{', '.join(GRASP_SOURCES)}")
        if not self.approach_backoffs_m or any(not 0 <= b <= 0.05 for b in self.approach_backoffs_m):
            raise ConfigError("GraspConfig.approach_backoffs_m: expected a non-empty list of "
                              "back-offs in [0, 0.05] m")
        _positive(self, "close_squeeze_m", allow_zero=True)
        if not 0 < self.close_command_fraction <= 1:
            raise ConfigError("GraspConfig.close_command_fraction: expected (0, 1]")



@dataclass(frozen=True)
class DeclutterConfig:
    """Clearing a table (``run --declutter``, ``bench clutter``): the round rules of the
    VGN/GIGA benchmarks plus our choice of the next target."""

    max_consecutive_failures: int = 2
    max_attempts: int = 20
    failed_anchor_radius_m: float = 0.03
    order: str = "accessibility"
    free_space_enough_m: float = 0.03

    def validate(self) -> None:
        _positive(self, "max_consecutive_failures", "max_attempts")
        _positive(self, "failed_anchor_radius_m", "free_space_enough_m", allow_zero=True)
        if self.order not in ("accessibility", "nearest"):
            raise ConfigError(f"DeclutterConfig.order = {self.order!r}: expected 'accessibility' "
                              "or 'nearest'")


@dataclass(frozen=True)
class GraspFitConfig:
    """Grasps fitted to the perceived points and the support rule (ours; extends SPEC 2.6 and
    3, see ``docs/spec_extensions.md``)."""

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

    def validate(self) -> None:
        _positive(self, "cloud_voxel_m", "support_gap_m", "footprint_cell_m", "box_sample_step_m", "line_step_m",
                  "min_material_points", "max_candidates")
        _positive(self, "support_ring_m", "blocked_points", "column_tolerance_m",
                  "clearance_enough_m", "min_pad_overlap_m", allow_zero=True)
        _positive(self, "contact_depth_m", "max_centroid_offset_m", "min_open_margin_m",
                  "level_gap_m")
        for name in ("see_through_fraction", "min_contact_fraction"):
            if not 0 < getattr(self, name) <= 1:
                raise ConfigError(f"GraspFitConfig.{name}: expected (0, 1]")
