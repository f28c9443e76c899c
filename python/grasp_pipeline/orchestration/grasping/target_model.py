"""The target as the grasp sampler sees it: its points, their normals, and the space the
camera could not see under them.

From one frame the camera sees an object's top and the sides facing it. The 2.5-D rule of
the grasp checks (the same as the planner's model of the neighbours): what is seen from
above extends straight down — each ``cell_m`` column holding the object's points is filled
from its lowest seen point down to the table, or down to the highest surface seen under it
(another object it lies on). The sampler closes the pads on this solid model; the seen
points' normals come from the camera's view, the filled points' from the solid's shape.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..scene.scene_cloud import SceneCloud

#: Points per normal estimate (the point and its nearest neighbours).
NORMAL_NEIGHBOURS = 10


@dataclass(frozen=True)
class TargetModel:
    """``points`` (N, 3) world [m]: the seen points (thinned) followed by the filled ones;
    ``seen`` (N,) True for the first; ``normals`` (N, 3) unit outward normals (of the seen
    points from the camera's view, of the filled ones from the solid's shape); ``centroid`` (3,) the centre of the object's area
    seen from above at its mid height; ``heights_m`` (N,) above the table."""

    points: np.ndarray
    seen: np.ndarray
    normals: np.ndarray
    centroid: np.ndarray
    heights_m: np.ndarray

    def __len__(self) -> int:
        return len(self.points)


def estimate_normals(points: np.ndarray, viewpoint: np.ndarray, k: int = NORMAL_NEIGHBOURS,
                     at: np.ndarray | None = None, tree: cKDTree | None = None) -> np.ndarray:
    """Unit normals by PCA over the ``k`` nearest of ``points``, oriented towards
    ``viewpoint`` (the camera that saw them): of every point, or of the points ``at`` (M, 3)
    (``tree``: a KD-tree of ``points``, when one is at hand)."""
    pts = np.asarray(points, dtype=float)
    query = pts if at is None else np.asarray(at, dtype=float)
    if len(pts) < 3:
        return np.zeros((len(query), 3))
    k = min(k, len(pts))
    _, idx = (tree or cKDTree(pts)).query(query, k=k)
    nb = pts[idx] - pts[idx].mean(axis=1, keepdims=True)
    cov = np.einsum("nki,nkj->nij", nb, nb)
    _, vecs = np.linalg.eigh(cov)
    normals = vecs[:, :, 0]
    flip = np.einsum("ni,ni->n", normals, np.asarray(viewpoint, float) - query) < 0
    normals[flip] *= -1.0
    return normals


def _cell_keys(points: np.ndarray, cell_m: float) -> np.ndarray:
    ij = np.floor(points[:, :2] / cell_m).astype(np.int64)
    return (ij[:, 0] + (1 << 24)) * (1 << 25) + (ij[:, 1] + (1 << 24))


def thin(points: np.ndarray, cell_m: float) -> np.ndarray:
    """Indices of one point per ``cell_m`` voxel (the first)."""
    if len(points) == 0:
        return np.zeros(0, dtype=np.int64)
    ii = np.floor(points / cell_m).astype(np.int64)
    _, first = np.unique(ii, axis=0, return_index=True)
    return np.sort(first)


def fill_columns(own: np.ndarray, own_h: np.ndarray, other: np.ndarray, other_h: np.ndarray,
                 plane_n: np.ndarray, cell_m: float) -> np.ndarray:
    """(K, 3) points filling each ``cell_m`` column of ``own`` (heights ``own_h`` above the
    table) from its lowest seen point down to the table (height 0) or to the highest ``other``
    point seen under it in that column, one every ``cell_m``."""
    if len(own) == 0:
        return np.zeros((0, 3))
    keys = _cell_keys(own, cell_m)
    ukeys, inv = np.unique(keys, return_inverse=True)
    low = np.full(len(ukeys), np.inf)
    np.minimum.at(low, inv, own_h)
    anchor = np.zeros((len(ukeys), 3))
    anchor_h = np.zeros(len(ukeys))
    anchor[inv], anchor_h[inv] = own, own_h  # any point of a column stands for its (x, y)
    stop = np.zeros(len(ukeys))
    if len(other):
        okeys = _cell_keys(other, cell_m)
        pos = np.clip(np.searchsorted(ukeys, okeys), 0, len(ukeys) - 1)
        below = (ukeys[pos] == okeys) & (other_h < low[pos] - cell_m)
        np.maximum.at(stop, pos[below], other_h[below])
    count = np.maximum(0, np.floor((low - stop) / cell_m).astype(np.int64))
    rep = np.repeat(np.arange(len(ukeys)), count)
    step = np.arange(len(rep)) - np.repeat(np.cumsum(count) - count, count) + 1
    heights = low[rep] - step * cell_m
    n = np.asarray(plane_n, dtype=float)
    return anchor[rep] + (heights - anchor_h[rep])[:, None] * n


def footprint_centroid(points: np.ndarray, heights: np.ndarray, plane_n: np.ndarray,
                       cell_m: float) -> np.ndarray:
    """The centre of the area ``points`` cover seen from above (their ``cell_m`` cells), at
    their mid height: unlike the points' mean, not pulled towards the side the camera saw."""
    keys, first = np.unique(_cell_keys(points, cell_m), return_index=True)
    cells = points[first]
    n = np.asarray(plane_n, dtype=float)
    flat = cells - (heights[first])[:, None] * n
    mid = 0.5 * (float(heights.min()) + float(heights.max()))
    return flat.mean(axis=0) + mid * n


def _near_xy(points: np.ndarray, ref: np.ndarray, margin_m: float) -> np.ndarray:
    """(N,) whether each of ``points`` lies within the horizontal (world x, y) bounding box of
    ``ref`` grown by ``margin_m``."""
    lo = [ref[:, j].min() - margin_m for j in (0, 1)]
    hi = [ref[:, j].max() + margin_m for j in (0, 1)]
    near = (points[:, 0] >= lo[0]) & (points[:, 0] <= hi[0])
    near &= points[:, 1] >= lo[1]
    near &= points[:, 1] <= hi[1]
    return near


def target_model(cloud: SceneCloud, tid: int, viewpoint: np.ndarray, cell_m: float,
                 max_points: int, unknown=None, max_cell_m: float = 0.009) -> TargetModel | None:
    """The :class:`TargetModel` of track ``tid`` in ``cloud`` (None without points of it):
    its seen points thinned to one per ``cell_m`` voxel and its hidden columns filled every
    ``cell_m``; when that makes more than ``max_points``, the whole model is thinned on a
    coarser grid (never beyond ``max_cell_m``: a pad's strip must still hold points wherever
    the object is). ``unknown(points)``: True where no camera has seen the space — with it,
    only the unseen part of a column is filled (what a camera saw through is known to be
    empty: under a leaning box, say)."""
    mask = cloud.owner == int(tid)
    own = cloud.points[mask]
    if len(own) < 3:
        return None
    other = np.compress(~mask, cloud.points, axis=0)  # points[~mask], faster
    other_h = cloud.heights_m(other)
    cell = float(cell_m)
    # only points in the target's columns can stop a column's fill: those within two of the
    # largest cells of its points (across, horizontally) hold every one
    near = _near_xy(other, own, 2.0 * max(cell, float(max_cell_m)))
    other, other_h = other[near], other_h[near]
    tree = cKDTree(own)
    while True:
        keep = thin(own, cell)
        seen = own[keep]
        nrm = estimate_normals(own, viewpoint, at=seen, tree=tree)
        seen_h = cloud.heights_m(seen)
        filled = fill_columns(seen, seen_h, other, other_h, cloud.plane_n, cell)
        if unknown is not None and len(filled):
            filled = filled[np.asarray(unknown(filled), dtype=bool)]
        if len(seen) + len(filled) <= max_points or cell >= max_cell_m:
            break
        cell = min(cell * 1.25, max_cell_m)
    pts = np.vstack([seen, filled])
    flags = np.r_[np.ones(len(seen), bool), np.zeros(len(filled), bool)]
    nrm = np.vstack([nrm, solid_normals(pts, len(seen))])
    return TargetModel(pts, flags, nrm, footprint_centroid(seen, seen_h, cloud.plane_n, cell_m),
                       cloud.heights_m(pts))


def solid_normals(points: np.ndarray, first: int, k: int = 2 * NORMAL_NEIGHBOURS) -> np.ndarray:
    """(N - first, 3) normals of the filled points ``points[first:]`` of a solid model: PCA
    over their ``k`` nearest model points, pointing away from that neighbourhood's centroid
    (on the solid's boundary the neighbours lie inside; the side of a column sheet gets the
    side's normal)."""
    filled = points[first:]
    if len(filled) == 0 or len(points) < 3:
        return np.zeros((len(filled), 3))
    k = min(k, len(points))
    _, idx = cKDTree(points).query(filled, k=k)
    nb = points[idx]
    mean = nb.mean(axis=1)
    cen = nb - mean[:, None, :]
    _, vecs = np.linalg.eigh(np.einsum("nki,nkj->nij", cen, cen))
    normals = vecs[:, :, 0]
    flip = np.einsum("ni,ni->n", normals, filled - mean) < 0
    normals[flip] *= -1.0
    return normals
