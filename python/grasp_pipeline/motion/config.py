"""Typed parameters of the motion layer (``config/motion.yaml``).

``load_motion_config()`` reads the packaged defaults, an optional user file and
``name=value`` overrides (see :func:`grasp_pipeline.config.load_config`). method.md §2.7
fixes ``planning_time`` (10 s), ``num_planning_attempts`` (10) and the velocity /
acceleration scales (0.3 / 0.3); here they carry their unit in the name. The planning
time and attempt count are *upper bounds*: planning stops at the first exact solution.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping

from ..config import load_config
from ..config_ranges import (CELL_COORDINATE_M, POSITIVE_FRACTION, Range, angle_rad,
                             check_ranges, count, duration_s, length_m, step_m)
from ..exceptions import ConfigError

#: A fraction that may exceed 1 to switch a rule off (``> 1: boxes only``).
_FRACTION_OR_OFF = Range(0.0, 2.0)

#: OMPL geometric planners this layer knows how to construct by name.
KNOWN_PLANNERS = ("RRTConnect", "RRT", "RRTstar", "PRM", "KPIECE1", "BKPIECE1", "LBKPIECE1")


@dataclass(frozen=True)
class MotionConfig:
    """Every tunable number of IK, collision checking, planning, timing and execution."""

    # --- planner (method.md §2.7) -------------------------------------------------------------
    planner: str = "RRTConnect"
    planning_time_s: float = 10.0
    num_planning_attempts: int = 10
    planner_range_rad: float = 0.0
    try_direct_first: bool = True
    planner_check_step_rad: float = 0.02
    final_check_step_rad: float = 0.0087266
    simplify_max_time_s: float = 0.05
    random_seed: int = 0
    # --- collision model -----------------------------------------------------------------
    voxel_size_m: float = 0.01
    collision_margin_m: float = 0.005
    self_collision_margin_m: float = 0.0
    sphere_cell_m: float = 0.04
    workspace_min_m: tuple[float, ...] = (-1.2, -1.2, -0.3)
    workspace_max_m: tuple[float, ...] = (1.4, 1.2, 1.6)
    max_environment_points: int = 20_000_000
    max_grid_voxels: int = 12_000_000
    self_filter_padding_m: float = 0.02
    target_ignore_padding_m: float = 0.05
    object_points_min_seen_fraction: float = 0.5
    object_points_seen_through_fraction: float = 0.8
    object_points_duplicate_overlap: float = 0.5
    floor_z_m: float = 0.0
    # --- Cartesian segments --------------------------------------------------------------
    cartesian_step_m: float = 0.005
    cartesian_step_rad: float = 0.03
    cartesian_max_joint_step_rad: float = 0.1
    # --- IK ----------------------------------------------------------------------------------
    ik_q7_samples: int = 36
    ik_refine_iterations: int = 30
    ik_tolerance_m: float = 1e-9
    ik_tolerance_rad: float = 1e-9
    ik_accept_position_m: float = 1e-6
    ik_accept_orientation_rad: float = 1e-6
    ik_duplicate_tol_rad: float = 1e-4
    ik_dls_iterations: int = 200
    ik_dls_damping_early: float = 0.05
    ik_dls_damping_late: float = 1e-4
    ik_dls_max_step_m: float = 0.05
    ik_dls_max_step_rad: float = 0.2
    ik_dls_orientation_weight_m_per_rad: float = 0.2
    # --- timing (TOPP-RA) ----------------------------------------------------------------
    velocity_scale: float = 0.3
    acceleration_scale: float = 0.3
    control_rate_hz: float = 500.0
    toppra_gridpoints: int = 200
    timing_waypoint_step_rad: float = 0.05
    timing_limit_tolerance: float = 0.005
    # --- execution --------------------------------------------------------------------------
    tracking_error_limit_rad: float = 0.05
    settle_position_tol_rad: float = 0.005
    settle_velocity_tol_rad_s: float = 0.02
    settle_timeout_s: float = 3.0
    stop_on_contact: bool = True

    RANGES: ClassVar[Mapping[str, Range]] = {
        "planning_time_s": duration_s(600.0),
        "num_planning_attempts": count(1, 1000),
        "planner_range_rad": angle_rad(20.0, zero=True),
        "planner_check_step_rad": Range(0.001, 0.5, unit=" rad"),
        "final_check_step_rad": Range(0.001, 0.5, unit=" rad"),
        "simplify_max_time_s": duration_s(60.0),
        "random_seed": count(-1, 2**32 - 1, " (-1: not seeded)"),
        "voxel_size_m": Range(0.01, 0.05, unit=" m"),
        "collision_margin_m": length_m(0.1, zero=True),
        "self_collision_margin_m": length_m(0.05, zero=True),
        "sphere_cell_m": Range(0.005, 0.2, unit=" m"),
        "workspace_min_m": CELL_COORDINATE_M,
        "workspace_max_m": CELL_COORDINATE_M,
        "max_environment_points": count(1, 100_000_000),
        "max_grid_voxels": count(1, 100_000_000),
        "self_filter_padding_m": length_m(0.2, zero=True),
        "target_ignore_padding_m": length_m(0.2, zero=True),
        "object_points_min_seen_fraction": _FRACTION_OR_OFF,
        "object_points_seen_through_fraction": _FRACTION_OR_OFF,
        "object_points_duplicate_overlap": _FRACTION_OR_OFF,
        "floor_z_m": CELL_COORDINATE_M,
        "cartesian_step_m": step_m(),
        "cartesian_step_rad": Range(0.001, 0.5, unit=" rad"),
        "cartesian_max_joint_step_rad": angle_rad(1.0),
        "ik_q7_samples": count(1, 3600),
        "ik_refine_iterations": count(1, 1000),
        "ik_tolerance_m": length_m(1e-3, zero=True),
        "ik_tolerance_rad": angle_rad(1e-2, zero=True),
        "ik_accept_position_m": length_m(0.01),
        "ik_accept_orientation_rad": angle_rad(0.1),
        "ik_duplicate_tol_rad": angle_rad(0.5),
        "ik_dls_iterations": count(1, 10_000),
        "ik_dls_damping_early": Range(0.0, 1.0, lo_open=True),
        "ik_dls_damping_late": Range(0.0, 1.0, lo_open=True),
        "ik_dls_max_step_m": length_m(0.5),
        "ik_dls_max_step_rad": angle_rad(3.2),
        "ik_dls_orientation_weight_m_per_rad": Range(0.0, 10.0, lo_open=True, unit=" m/rad"),
        "velocity_scale": POSITIVE_FRACTION,
        "acceleration_scale": POSITIVE_FRACTION,
        "control_rate_hz": Range(1.0, 5000.0, unit=" Hz"),
        "toppra_gridpoints": count(2, 10_000),
        "timing_waypoint_step_rad": Range(0.001, 1.0, unit=" rad"),
        "timing_limit_tolerance": Range(0.0, 0.5),
        "tracking_error_limit_rad": angle_rad(1.0),
        "settle_position_tol_rad": angle_rad(0.5),
        "settle_velocity_tol_rad_s": Range(0.0, 1.0, lo_open=True, unit=" rad/s"),
        "settle_timeout_s": duration_s(600.0),
    }

    def validate(self) -> None:
        """Range checks; raise :class:`ConfigError` naming the offending parameter."""
        check_ranges(self, "motion")
        if self.planner not in KNOWN_PLANNERS:
            raise ConfigError(
                f"motion.planner {self.planner!r} unknown; choose one of {', '.join(KNOWN_PLANNERS)}")
        if self.final_check_step_rad > self.planner_check_step_rad:
            raise ConfigError("motion.final_check_step_rad must not exceed planner_check_step_rad "
                              f"({self.final_check_step_rad} > {self.planner_check_step_rad})")
        if len(self.workspace_min_m) != 3 or len(self.workspace_max_m) != 3:
            raise ConfigError("motion.workspace_min_m / workspace_max_m need 3 values (x, y, z)")
        if any(lo >= hi for lo, hi in zip(self.workspace_min_m, self.workspace_max_m)):
            raise ConfigError("motion.workspace_min_m must be below workspace_max_m on every axis")


def load_motion_config(path: str | Path | None = None,
                       overrides: Mapping[str, Any] | None = None) -> MotionConfig:
    """The motion parameters: packaged ``config/motion.yaml`` < ``path`` < ``overrides``."""
    return load_config(MotionConfig, "motion", path=path, overrides=overrides)
