"""The depth camera's noise: one fact about the sensor, defined once (``config/depth_noise.yaml``).

The noise along the optical axis is modelled as
``sigma(r) = depth_noise_sigma_m * (r / depth_noise_ref_range_m) ** depth_noise_exponent``.
The simulated camera adds it to its frames (``grasp_pipeline.sim.camera``, unless
``camera.add_noise`` is off) and perception expects it: the scene filter's range-dependent
minimum object height and segmentation steps, and the object estimate's top slice and side
test, whose sigma is ``depth_noise_sigma_m`` (:meth:`SceneFilterConfig.to_core
<grasp_pipeline.perception.config.SceneFilterConfig.to_core>`, :meth:`ObbConfig.to_core
<grasp_pipeline.perception.config.ObbConfig.to_core>`). With a real camera, set your sensor's
figures here once (``--set depth_noise.depth_noise_sigma_m=...``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping

from ..config import load_config
from ..config_ranges import Range, check_ranges


@dataclass(frozen=True)
class DepthNoiseConfig:
    """See ``config/depth_noise.yaml``."""

    depth_noise_sigma_m: float = 0.002
    depth_noise_ref_range_m: float = 0.4
    depth_noise_exponent: float = 2.0

    RANGES: ClassVar[Mapping[str, Range]] = {
        # perception divides by sigma: a noise-free simulated camera is camera.add_noise=false
        "depth_noise_sigma_m": Range(0.0, 0.1, lo_open=True, unit=" m"),
        "depth_noise_ref_range_m": Range(0.0, 100.0, lo_open=True, unit=" m"),
        "depth_noise_exponent": Range(0.0, 4.0),
    }

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        check_ranges(self, "depth_noise")


def load_depth_noise_config(path: str | Path | None = None,
                            overrides: Mapping[str, Any] | None = None) -> DepthNoiseConfig:
    """``config/depth_noise.yaml`` (+ optional user file and overrides)."""
    return load_config(DepthNoiseConfig, "depth_noise", path, overrides)
