"""Parameter set of the learning environment and its reference policy: ``config/env.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import ConfigError


@dataclass(frozen=True)
class EnvConfig:
    """The episode rules of ``grasp_pipeline/PickPlace-v0``, the reference policy's choices and
    the size of the worker jobs of ``record`` and ``eval`` (see ``env.yaml``)."""

    time_limit_s: float = 60.0
    rest_speed_mps: float = 0.02
    rest_angular_speed_rad_s: float = 0.5
    unique_target: bool = True
    reference_scan: bool = True
    reference_attempts: int = 2
    reference_wait_s: float = 2.0
    episodes_per_job: int = 4

    def validate(self) -> None:
        if not self.time_limit_s > 0:
            raise ConfigError(f"time_limit_s must be > 0, got {self.time_limit_s}")
        if not (self.rest_speed_mps > 0 and self.rest_angular_speed_rad_s > 0):
            raise ConfigError("rest_speed_mps and rest_angular_speed_rad_s must be > 0")
        if self.reference_attempts < 1 or self.episodes_per_job < 1:
            raise ConfigError("reference_attempts and episodes_per_job must be >= 1")
        if self.reference_wait_s < 0:
            raise ConfigError(f"reference_wait_s must be >= 0, got {self.reference_wait_s}")
