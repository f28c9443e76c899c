"""A grasp source of poses given up front (known grasps, a replay, a test):
:class:`FixedGraspSource`."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ... import _core
from .source import GraspRequest


class FixedGraspSource:
    """Grasps given up front; proposes those within ``radius_m`` of the anchor, nearest first."""

    name = "fixed"
    top_down_only = False

    def __init__(self, grasps: Sequence, radius_m: float = 0.05) -> None:
        self.grasps = list(grasps)
        if radius_m <= 0:
            raise ValueError(f"FixedGraspSource radius_m must be > 0, got {radius_m}")
        self.radius_m = float(radius_m)

    @classmethod
    def from_poses(cls, poses: Sequence[tuple[np.ndarray, np.ndarray, float]],
                   radius_m: float = 0.05) -> "FixedGraspSource":
        """From (R 3x3, position (3,), width_m) triples in the BestGrasp convention."""
        return cls([_core.BestGrasp(np.asarray(R, float), np.asarray(p, float), float(w))
                    for R, p, w in poses], radius_m)

    def propose(self, request: GraspRequest) -> list:
        ax, ay = request.anchor_xy
        near = [(float(np.hypot(g.position[0] - ax, g.position[1] - ay)), k, g)
                for k, g in enumerate(self.grasps)]
        return [g for d, _, g in sorted(near) if d <= self.radius_m]
