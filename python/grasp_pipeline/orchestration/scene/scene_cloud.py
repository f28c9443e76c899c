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


def voxel_thin(points: np.ndarray, owner: np.ndarray, voxel_m: float) -> tuple[np.ndarray, np.ndarray]:
    """One point (the first) per (voxel, owner) pair, in the order of their (voxel index x,
    y, z, owner) — ``np.unique`` over that key with ``return_index``, computed by the C++
    core's radix sort. ``points``: (N, 3) finite; ``owner``: (N,) integers."""
    if len(points) == 0:
        return points, owner
    first = _core.first_per_voxel(np.ascontiguousarray(points, dtype=np.float64),
                                  np.ascontiguousarray(owner, dtype=np.int64), float(voxel_m))
    return np.take(points, first, axis=0), np.take(owner, first)


def cloud_from_frame(result, plane, band_m: float, voxel_m: float) -> SceneCloud:
    """A :class:`SceneCloud` of one processed frame (``result``: ``FrameResult``; ``plane``:
    the locked ``_core.Plane``). Object points take the track id of their cluster's estimate;
    environment points are kept only once the scene filter emits them (method.md §1.5)."""
    labels = np.asarray(result.labels)
    raw = result.raw
    owner = np.full(len(labels), UNTRACKED, dtype=np.int64)
    lut = {int(lab): int(tid) for lab, tid in zip(raw.estimate_labels, raw.tids)}
    obj = labels >= 0
    if lut and np.any(obj):
        top = max(int(labels.max()), max(lut)) + 1
        table = np.full(top, UNTRACKED, dtype=np.int64)
        for lab, tid in lut.items():
            if lab >= 0:
                table[lab] = tid
        owner[obj] = table[labels[obj]]
    env = np.asarray(result.environment_mask)
    owner[env] = ENVIRONMENT
    keep = np.flatnonzero(obj | env)  # converted to float, tested finite: only these rows
    pts = np.take(np.asarray(result.points).reshape(-1, 3), keep, axis=0).astype(float, copy=False)
    finite = np.isfinite(pts[:, 0]) & np.isfinite(pts[:, 1]) & np.isfinite(pts[:, 2])
    if not finite.all():
        pts, keep = pts[finite], keep[finite]
    p, o = voxel_thin(pts, owner[keep], voxel_m)
    return SceneCloud(p, o, np.asarray(plane.n, dtype=float), float(plane.c), float(band_m))
