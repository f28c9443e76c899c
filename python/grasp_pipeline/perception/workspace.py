"""The workspace of a camera session: where objects may be (real captures).

A real capture sees far beyond the table: floors, walls, furniture metres away, where the
depth noise of a structured-light / ToF camera is several centimetres. Points outside the
workspace are dropped before the scene filter, like NaN rows (they are labelled invalid and
counted in the frame's ``num_invalid``; the frame keeps its organization):

- ``workspace_max_range_m`` > 0: points farther than this from the camera;
- ``workspace_crop_box_m`` = ``[xmin, xmax, ymin, ymax, zmin, zmax]`` in ``world`` [m]:
  points outside the box (an empty list: no box).

Both are off by default (the simulated cell needs neither). ``grasp-pipeline perceive`` sets
them from ``--max-range-m`` / ``--crop``, or from a ``workspace:`` section of ``--config``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Mapping, Optional

import numpy as np

from ..config import load_config
from ..config_ranges import Range, check_ranges, require


@dataclass(frozen=True)
class WorkspaceConfig:
    """See ``config/workspace.yaml``."""

    workspace_max_range_m: float = 0.0
    workspace_crop_box_m: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        self.validate()

    @property
    def enabled(self) -> bool:
        return self.workspace_max_range_m > 0 or len(self.workspace_crop_box_m) > 0

    RANGES: ClassVar[Mapping[str, Range]] = {
        "workspace_max_range_m": Range(0.0, 1000.0, unit=" m (0: no limit)"),
        "workspace_crop_box_m": Range(-1000.0, 1000.0, unit=" m"),
    }

    def validate(self) -> None:
        check_ranges(self, "workspace")
        box = tuple(self.workspace_crop_box_m)
        require(not box or len(box) == 6, "workspace", "workspace_crop_box_m", list(box),
                "6 numbers [xmin, xmax, ymin, ymax, zmin, zmax] in m (or [] for no box)")
        require(not box or all(box[2 * a] < box[2 * a + 1] for a in range(3)), "workspace",
                "workspace_crop_box_m", list(box),
                "each minimum below its maximum ([xmin, xmax, ymin, ymax, zmin, zmax])")

    def outside(self, points: np.ndarray, camera_position) -> np.ndarray:
        """(N,) bool: finite rows outside the workspace (NaN rows are not counted)."""
        pts = np.asarray(points)
        out = np.zeros(len(pts), dtype=bool)
        if self.workspace_max_range_m > 0:
            d = pts.astype(np.float64, copy=False) - np.asarray(camera_position, np.float64)
            with np.errstate(invalid="ignore"):
                out |= np.einsum("ij,ij->i", d, d) > self.workspace_max_range_m ** 2
        if self.workspace_crop_box_m:
            b = np.asarray(self.workspace_crop_box_m, np.float64).reshape(3, 2)
            with np.errstate(invalid="ignore"):
                inside = np.all((pts >= b[:, 0]) & (pts <= b[:, 1]), axis=1)
            out |= ~inside & np.isfinite(pts).all(axis=1)
        return out

    def apply(self, points: np.ndarray, camera_position) -> tuple[np.ndarray, int]:
        """(points with the rows outside set to NaN, how many) — the caller's array is not
        modified; it is returned as is when nothing is outside (or the workspace is off)."""
        if not self.enabled:
            return points, 0
        out = self.outside(points, camera_position)
        n = int(out.sum())
        if n == 0:
            return points, 0
        kept = np.array(points, copy=True)
        kept[out] = np.nan
        return kept, n


def load_workspace_config(path: str | Path | None = None,
                          overrides: Optional[Mapping[str, Any]] = None) -> WorkspaceConfig:
    """``config/workspace.yaml`` (+ optional user file and overrides)."""
    return load_config(WorkspaceConfig, "workspace", path, overrides)
