"""Parameter sets of the simulator: ``config/camera.yaml`` and ``config/sim.yaml``.

Load with ``load_camera_config()`` / ``load_sim_config()`` (packaged defaults, then an optional
user file, then ``name=value`` overrides; see :func:`grasp_pipeline.config.load_config`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping

from ..config import load_config
from ..config_ranges import (CELL_COORDINATE_M, FORCE_N, RATE_HZ, Range, check_ranges, count,
                             length_m, require, require_min_max)
from ..exceptions import ConfigError

CAMERA_BACKENDS = ("auto", "gl", "raycast")
#: When frames are rendered: only while requested (``on_demand``) or always (``continuous``).
FRAME_MODES = ("on_demand", "continuous")
#: Largest camera image side [px] (a 4096 x 4096 frame is 16.8 M points).
MAX_IMAGE_PX = 4096


@dataclass(frozen=True)
class CameraConfig:
    """Depth camera: image size, field of view, rate, valid range, whether the sensor's depth
    noise is added (``add_noise``; the noise model is ``config/depth_noise.yaml``'s), backend;
    ``rgb``: deliver a colour image aligned with the depth (``Frame.rgb``); ``labels``: also
    compute per-pixel object labels (evaluation only, read through the ground-truth module,
    never in the frame); ``frames``: ``on_demand`` renders a frame only while a consumer
    requests frames (``SimWorld.request_frames``), ``continuous`` at ``rate_hz`` whenever a
    frame listener exists (the old path, kept for comparisons); ``still_tolerance_m``: a frame
    reuses the last render while no geom and not the camera moved more than this since
    (:mod:`.still_scene`; 0: a render per frame)."""

    width_px: int = 640
    height_px: int = 480
    vfov_deg: float = 58.0
    rate_hz: float = 30.0
    frames: str = "on_demand"
    min_range_m: float = 0.12
    max_range_m: float = 3.0
    add_noise: bool = True
    grazing_max_deg: float = 80.0
    backend: str = "auto"
    seed: int = 0
    rgb: bool = True
    labels: bool = False
    still_tolerance_m: float = 1e-6

    RANGES: ClassVar[Mapping[str, Range]] = {
        "width_px": count(8, MAX_IMAGE_PX, " px"),
        "height_px": count(8, MAX_IMAGE_PX, " px"),
        "vfov_deg": Range(1.0, 170.0, lo_open=True, hi_open=True, unit=" deg"),
        "rate_hz": RATE_HZ,
        "min_range_m": length_m(10.0),
        "max_range_m": length_m(100.0),
        "grazing_max_deg": Range(0.0, 90.0, lo_open=True, unit=" deg"),
        "seed": count(0, 2**63 - 1),
        "still_tolerance_m": length_m(0.01, zero=True),
    }

    def validate(self) -> None:
        check_ranges(self, "camera")
        require(self.min_range_m < self.max_range_m, "camera", "min_range_m", self.min_range_m,
                f"a range below max_range_m = {self.max_range_m:g} m")
        if self.frames not in FRAME_MODES:
            raise ConfigError(f"camera.frames must be one of {FRAME_MODES}, got {self.frames!r}")
        if self.backend not in CAMERA_BACKENDS:
            raise ConfigError(f"camera.backend must be one of {CAMERA_BACKENDS}, got {self.backend!r}")

    @property
    def period_s(self) -> float:
        """Time between frames [s]."""
        return 1.0 / self.rate_hz


@dataclass(frozen=True)
class SimConfig:
    """Physics step, gripper behaviour, object material and the random-scene ranges."""

    timestep_s: float = 0.002
    noslip_iterations: int = 0
    noslip_hold_iterations: int = 5
    gripper_speed_mps: float = 0.1
    gripper_default_effort_N: float = 40.0
    object_density_kg_m3: float = 800.0
    object_friction: float = 1.0
    region_x_m: tuple[float, ...] = (0.40, 0.64)
    region_y_m: tuple[float, ...] = (-0.22, 0.22)
    min_separation_m: float = 0.12
    object_count: tuple[int, ...] = (1, 6)
    cube_size_m: tuple[float, ...] = (0.03, 0.06)
    cuboid_width_m: tuple[float, ...] = (0.03, 0.07)
    cuboid_height_m: tuple[float, ...] = (0.03, 0.07)
    cylinder_diameter_m: tuple[float, ...] = (0.03, 0.07)
    cylinder_height_m: tuple[float, ...] = (0.04, 0.07)

    RANGES: ClassVar[Mapping[str, Range]] = {
        "timestep_s": Range(0.0005, 0.005, unit=" s"),
        "noslip_iterations": count(0, 100),
        "noslip_hold_iterations": count(0, 100),
        "gripper_speed_mps": Range(0.0, 1.0, lo_open=True, unit=" m/s"),
        "gripper_default_effort_N": FORCE_N,
        "object_density_kg_m3": Range(0.0, 25_000.0, lo_open=True, unit=" kg/m^3"),
        "object_friction": Range(0.0, 10.0, lo_open=True),
        "region_x_m": CELL_COORDINATE_M,
        "region_y_m": CELL_COORDINATE_M,
        "min_separation_m": length_m(0.5, zero=True),
        "object_count": count(1, 30),
        "cube_size_m": length_m(0.3, lo=0.005),
        "cuboid_width_m": length_m(0.3, lo=0.005),
        "cuboid_height_m": length_m(0.3, lo=0.005),
        "cylinder_diameter_m": length_m(0.3, lo=0.005),
        "cylinder_height_m": length_m(0.3, lo=0.005),
    }

    def validate(self) -> None:
        check_ranges(self, "sim")
        for name in ("region_x_m", "region_y_m", "object_count", "cube_size_m", "cuboid_width_m",
                     "cuboid_height_m", "cylinder_diameter_m", "cylinder_height_m"):
            require_min_max("sim", name, getattr(self, name))


def load_camera_config(path: str | Path | None = None,
                       overrides: Mapping[str, Any] | None = None) -> CameraConfig:
    """Camera parameters: ``config/camera.yaml`` < ``path`` < ``overrides``."""
    return load_config(CameraConfig, "camera", path=path, overrides=overrides)


def load_sim_config(path: str | Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> SimConfig:
    """Simulator parameters: ``config/sim.yaml`` < ``path`` < ``overrides``."""
    return load_config(SimConfig, "sim", path=path, overrides=overrides)
