"""Parameter sets of the simulator: ``config/camera.yaml`` and ``config/sim.yaml``.

Load with ``load_camera_config()`` / ``load_sim_config()`` (packaged defaults, then an optional
user file, then ``name=value`` overrides; see :func:`grasp_pipeline.config.load_config`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..config import load_config
from ..exceptions import ConfigError

CAMERA_BACKENDS = ("auto", "gl", "raycast")
#: When frames are rendered: only while requested (``on_demand``) or always (``continuous``).
FRAME_MODES = ("on_demand", "continuous")


def _check_range(name: str, rng: tuple[float, ...], lo: float = 0.0) -> None:
    if len(rng) != 2 or not (lo <= rng[0] <= rng[1]):
        raise ConfigError(f"{name} must be [min, max] with {lo} <= min <= max, got {list(rng)}")


@dataclass(frozen=True)
class CameraConfig:
    """Depth camera: image size, field of view, rate, valid range, noise model, backend;
    ``rgb``: deliver a colour image aligned with the depth (``Frame.rgb``); ``labels``: also
    compute per-pixel object labels (evaluation only, read through the ground-truth module,
    never in the frame); ``frames``: ``on_demand`` renders a frame only while a consumer
    requests frames (``SimWorld.request_frames``), ``continuous`` at ``rate_hz`` whenever a
    frame listener exists (the old path, kept for comparisons)."""

    width_px: int = 640
    height_px: int = 480
    vfov_deg: float = 58.0
    rate_hz: float = 30.0
    frames: str = "on_demand"
    min_range_m: float = 0.12
    max_range_m: float = 3.0
    noise_sigma_m: float = 0.002
    noise_ref_range_m: float = 0.4
    noise_exponent: float = 2.0
    grazing_max_deg: float = 80.0
    backend: str = "auto"
    seed: int = 0
    rgb: bool = True
    labels: bool = False

    def validate(self) -> None:
        if not (8 <= self.width_px <= MAX_IMAGE_PX and 8 <= self.height_px <= MAX_IMAGE_PX):
            raise ConfigError(f"camera image must be 8..{MAX_IMAGE_PX} px on each side, got "
                              f"{self.width_px}x{self.height_px}")
        if not 0 <= self.seed < 2**63:
            raise ConfigError(f"camera.seed must be a whole number >= 0, got {self.seed}")
        if not 1.0 < self.vfov_deg < 170.0:
            raise ConfigError(f"vfov_deg must be in (1, 170), got {self.vfov_deg}")
        if self.rate_hz <= 0:
            raise ConfigError(f"rate_hz must be > 0, got {self.rate_hz}")
        if not 0 < self.min_range_m < self.max_range_m:
            raise ConfigError(
                f"need 0 < min_range_m < max_range_m, got {self.min_range_m}, {self.max_range_m}")
        if self.noise_sigma_m < 0 or self.noise_ref_range_m <= 0:
            raise ConfigError("noise_sigma_m must be >= 0 and noise_ref_range_m > 0")
        if not 0 < self.grazing_max_deg <= 90:
            raise ConfigError(f"grazing_max_deg must be in (0, 90], got {self.grazing_max_deg}")
        if self.frames not in FRAME_MODES:
            raise ConfigError(f"camera.frames must be one of {FRAME_MODES}, got {self.frames!r}")
        if self.backend not in CAMERA_BACKENDS:
            raise ConfigError(f"backend must be one of {CAMERA_BACKENDS}, got {self.backend!r}")
        for flag in ("rgb", "labels"):
            value = getattr(self, flag)
            if not isinstance(value, bool):
                raise ConfigError(f"camera.{flag} must be true or false, got {value!r}")

    @property
    def period_s(self) -> float:
        """Time between frames [s]."""
        return 1.0 / self.rate_hz


#: Largest camera image side [px] (a 4096 x 4096 frame is 16.8 M points).
MAX_IMAGE_PX = 4096


@dataclass(frozen=True)
class SimConfig:
    """Physics step, gripper behaviour, object material and the random-scene ranges."""

    timestep_s: float = 0.002
    gripper_speed_mps: float = 0.1
    gripper_default_effort_N: float = 40.0
    gripper_max_effort_N: float = 140.0
    object_density_kg_m3: float = 800.0
    object_friction: float = 1.0
    table_top_z_m: float = 0.2
    region_x_m: tuple[float, ...] = (0.40, 0.64)
    region_y_m: tuple[float, ...] = (-0.22, 0.22)
    min_separation_m: float = 0.12
    object_count: tuple[int, ...] = (1, 6)
    cube_size_m: tuple[float, ...] = (0.03, 0.06)
    cuboid_width_m: tuple[float, ...] = (0.03, 0.07)
    cuboid_height_m: tuple[float, ...] = (0.03, 0.07)
    cylinder_diameter_m: tuple[float, ...] = (0.03, 0.07)
    cylinder_height_m: tuple[float, ...] = (0.04, 0.07)

    def validate(self) -> None:
        if not 0.0005 <= self.timestep_s <= 0.005:
            raise ConfigError(f"timestep_s must be in [0.0005, 0.005], got {self.timestep_s}")
        if self.gripper_speed_mps <= 0:
            raise ConfigError(f"gripper_speed_mps must be > 0, got {self.gripper_speed_mps}")
        if not 0 < self.gripper_default_effort_N <= self.gripper_max_effort_N:
            raise ConfigError("need 0 < gripper_default_effort_N <= gripper_max_effort_N")
        if self.object_density_kg_m3 <= 0 or self.object_friction <= 0:
            raise ConfigError("object_density_kg_m3 and object_friction must be > 0")
        _check_range("region_x_m", self.region_x_m, lo=-10.0)
        _check_range("region_y_m", self.region_y_m, lo=-10.0)
        _check_range("object_count", tuple(float(v) for v in self.object_count), lo=1.0)
        for name in ("cube_size_m", "cuboid_width_m", "cuboid_height_m",
                     "cylinder_diameter_m", "cylinder_height_m"):
            _check_range(name, getattr(self, name), lo=0.005)
        if self.min_separation_m < 0:
            raise ConfigError("min_separation_m must be >= 0")


def load_camera_config(path: str | Path | None = None,
                       overrides: Mapping[str, Any] | None = None) -> CameraConfig:
    """Camera parameters: ``config/camera.yaml`` < ``path`` < ``overrides``."""
    return load_config(CameraConfig, "camera", path=path, overrides=overrides)


def load_sim_config(path: str | Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> SimConfig:
    """Simulator parameters: ``config/sim.yaml`` < ``path`` < ``overrides``."""
    return load_config(SimConfig, "sim", path=path, overrides=overrides)
