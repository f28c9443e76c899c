"""The perceived scene as labelled points: what grasp fitting and the support rule look at.

:class:`SceneCloud` holds one frame's valid points in the world frame, thinned to one point per
voxel, each with its *owner*: the track id of the object it belongs to (``>= 0``), the
environment (:data:`ENVIRONMENT`: table, floor, everything that is not an object) or an object
cluster that no track took (:data:`UNTRACKED`). Heights above the table plane come with it.
Built from a :class:`~grasp_pipeline.perception.FrameResult` (per-point labels → estimate →
track id) without touching the simulator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import _core
from ...array_rows import rows_where

ENVIRONMENT = -1
UNTRACKED = -2


@dataclass(frozen=True)
class SceneCloud:
    """``points`` (N, 3) world [m]; ``owner`` (N,) int (track id, :data:`ENVIRONMENT` or
    :data:`UNTRACKED`); ``plane_n`` (3,) and ``plane_c`` the table plane (height of p =
    ``n·p + c``); ``band_m`` the environment band above the plane."""

    points: np.ndarray
    owner: np.ndarray
    plane_n: np.ndarray
    plane_c: float
    band_m: float

    def heights_m(self, points: np.ndarray | None = None) -> np.ndarray:
        """Heights above the table plane [m] of ``points`` (default: all)."""
        p = self.points if points is None else np.asarray(points, dtype=float)
        return p @ self.plane_n + self.plane_c

    def near(self, xy, radius_m: float) -> "SceneCloud":
        """The points within ``radius_m`` horizontally (world x, y) of ``xy``."""
        d = np.hypot(self.points[:, 0] - float(xy[0]), self.points[:, 1] - float(xy[1]))
        keep = d <= radius_m
        return SceneCloud(rows_where(self.points, keep), self.owner[keep], self.plane_n, self.plane_c, self.band_m)

    def of(self, tid: int) -> np.ndarray:
        """The points of track ``tid``."""
        return rows_where(self.points, self.owner == tid)

    def __len__(self) -> int:
        return len(self.points)


def _owner_of_label(raw) -> list[int]:
    """Per object group id (a label >= 0): the track id of the estimate made of that group,
    :data:`UNTRACKED` for a group no estimate names (ids past the list's end too)."""
    lut = {int(lab): int(tid) for lab, tid in zip(raw.estimate_labels, raw.tids)}
    table = [UNTRACKED] * (max((lab for lab in lut if lab >= 0), default=-1) + 1)
    for lab, tid in lut.items():
        if lab >= 0:
            table[lab] = tid
    return table


def cloud_from_frame(result, plane, band_m: float, voxel_m: float) -> SceneCloud:
    """A :class:`SceneCloud` of one processed frame (``result``: ``FrameResult``; ``plane``:
    the locked ``_core.Plane``). Object points take the track id of their cluster's estimate;
    environment points are kept only once the scene filter emits them (method.md §1.5). The
    rows with an owner and finite coordinates, as float64, are thinned to the first of each
    (voxel, owner) pair, pairs in the order of their (voxel index x, y, z, owner) key — what
    ``np.unique`` over that key with ``return_index`` keeps — in one pass of the C++ core."""
    points = np.asarray(result.points).reshape(-1, 3)
    if points.dtype != np.float32:
        points = points.astype(float, copy=False)
    p, o = _core.thin_owned_rows(np.ascontiguousarray(points), np.ascontiguousarray(result.labels, dtype=np.int32),
                                 _owner_of_label(result.raw), bool(result.environment_emitted),
                                 ENVIRONMENT, UNTRACKED, int(_core.LABEL_ENVIRONMENT), float(voxel_m))
    return SceneCloud(p, o, np.asarray(plane.n, dtype=float), float(plane.c), float(band_m))
