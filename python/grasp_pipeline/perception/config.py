"""Typed parameter sets of the perception core (SPEC 1.6 and 2.7).

Field names and defaults are SPEC's; the YAML files are ``config/scene_filter.yaml``
and ``config/obb.yaml``. Range checks live in one place, the C++ core's
``validate()``, which names the offending parameter; ``validate()`` here forwards
to it and turns its ValueError into :class:`ConfigError`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..config import load_config
from ..exceptions import ConfigError


def _to_core(cfg: Any, core_cls: type) -> Any:
    params = core_cls()
    for f in dataclasses.fields(cfg):
        setattr(params, f.name, getattr(cfg, f.name))
    return params


@dataclass(frozen=True)
class SceneFilterConfig:
    """SPEC 1.6: table plane search, persistence and clustering."""

    plane_dist_thresh: float = 0.008
    plane_max_tilt_deg: float = 10.0
    plane_ransac_iters: int = 200
    plane_fit_max_points: int = 4000
    plane_min_inlier_ratio: float = 0.15
    plane_max_count: int = 3
    plane_dominance: float = 0.70
    plane_lock: bool = True
    plane_lock_after: int = 5
    plane_update_tol_deg: float = 5.0
    plane_update_tol_m: float = 0.03
    plane_init_frames: int = 30
    cluster_eps: float = 0.015
    cluster_min_points: int = 20
    cluster_min_extent: float = 0.01
    cluster_max_extent: float = 0.30
    band: float = 0.01
    cluster_voxel_m: float = 0.003
    seed: int = 0

    def to_core(self):
        """The C++ ``SceneFilterParams`` with these values (validated)."""
        from .. import _core

        params = _to_core(self, _core.SceneFilterParams)
        try:
            params.validate()
        except ValueError as exc:
            raise ConfigError(f"scene_filter: {exc}") from None
        return params

    def validate(self) -> None:
        self.to_core()


@dataclass(frozen=True)
class ObbConfig:
    """SPEC 2.7 (perception part): object estimate, guards and tracker."""

    depth_noise_sigma: float = 0.002
    top_slice_sigmas: float = 4.0
    top_slice_iters: int = 3
    n_theta: int = 361
    width_tol_m: float = 0.002
    isotropy_ratio_max: float = 1.10
    gripper_open: float = 0.08
    min_graspable_width: float = 0.005
    min_height: float = 0.005
    resting_margin: float = 0.008
    side_seen_sigmas: float = 3.0
    window: int = 7
    assoc_gate_frac: float = 0.5
    max_age_s: float = 2.0
    nadir_hold_s: float = 10.0
    nadir_angle_max_deg: float = 5.0
    nadir_min_distance_m: float = 0.25

    def to_core(self):
        """The C++ ``ObbParams`` with these values (validated)."""
        from .. import _core

        params = _to_core(self, _core.ObbParams)
        try:
            params.validate()
        except ValueError as exc:
            raise ConfigError(f"obb: {exc}") from None
        return params

    def validate(self) -> None:
        self.to_core()


def load_scene_filter_config(path: str | Path | None = None,
                             overrides: Mapping[str, Any] | None = None) -> SceneFilterConfig:
    """``config/scene_filter.yaml`` (+ optional user file and overrides)."""
    return load_config(SceneFilterConfig, "scene_filter", path, overrides)


def load_obb_config(path: str | Path | None = None,
                    overrides: Mapping[str, Any] | None = None) -> ObbConfig:
    """``config/obb.yaml`` (+ optional user file and overrides)."""
    return load_config(ObbConfig, "obb", path, overrides)
