"""Typed parameters of the motion layer (``config/motion.yaml``).

``load_motion_config()`` reads the packaged defaults, an optional user file and
``name=value`` overrides (see :func:`grasp_pipeline.config.load_config`). SPEC 2.7
fixes ``planning_time`` (10 s), ``num_planning_attempts`` (10) and the velocity /
acceleration scales (0.3 / 0.3); here they carry their unit in the name. The planning
time and attempt count are *upper bounds*: planning stops at the first exact solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..config import load_config
from ..exceptions import ConfigError

#: OMPL geometric planners this layer knows how to construct by name.
KNOWN_PLANNERS = ("RRTConnect", "RRT", "RRTstar", "PRM", "KPIECE1", "BKPIECE1", "LBKPIECE1")


@dataclass(frozen=True)
class MotionConfig:
    """Every tunable number of IK, collision checking, planning, timing and execution."""

    # --- planner (SPEC 2.7) -------------------------------------------------------------
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

    def validate(self) -> None:
        """Range checks; raise :class:`ConfigError` naming the offending parameter."""

        def positive(name: str) -> None:
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ConfigError(f"motion.{name} must be > 0, got {v!r}")

        def non_negative(name: str) -> None:
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ConfigError(f"motion.{name} must be >= 0, got {v!r}")

        if self.planner not in KNOWN_PLANNERS:
            raise ConfigError(
                f"motion.planner {self.planner!r} unknown; choose one of {', '.join(KNOWN_PLANNERS)}")
        for name in ("planning_time_s", "num_planning_attempts", "planner_check_step_rad",
                     "final_check_step_rad", "simplify_max_time_s", "voxel_size_m",
                     "sphere_cell_m", "max_environment_points", "max_grid_voxels",
                     "cartesian_step_m", "cartesian_step_rad", "cartesian_max_joint_step_rad",
                     "ik_q7_samples", "ik_refine_iterations", "ik_accept_position_m",
                     "ik_accept_orientation_rad", "ik_duplicate_tol_rad", "control_rate_hz",
                     "toppra_gridpoints", "timing_waypoint_step_rad", "tracking_error_limit_rad",
                     "settle_position_tol_rad", "settle_velocity_tol_rad_s", "settle_timeout_s",
                     ):
            positive(name)
        for name in ("planner_range_rad", "collision_margin_m", "self_collision_margin_m",
                     "self_filter_padding_m", "target_ignore_padding_m", "ik_tolerance_m",
                     "object_points_min_seen_fraction", "object_points_seen_through_fraction",
                     "object_points_duplicate_overlap",
                     "ik_tolerance_rad", "timing_limit_tolerance"):
            non_negative(name)
        for name in ("velocity_scale", "acceleration_scale"):
            v = getattr(self, name)
            if not (0.0 < v <= 1.0):
                raise ConfigError(f"motion.{name} must be in (0, 1], got {v!r}")
        if not (0.01 <= self.voxel_size_m <= 0.05):
            raise ConfigError(f"motion.voxel_size_m must be in [0.01, 0.05] m, got {self.voxel_size_m}")
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
