"""Objects modelled by their points (a 2.5-D height map) instead of their boxes.

An oriented box is a loose model of a bottle, a bowl or a box seen at an angle: its corners
hold nothing, and in a packed scene a neighbour's empty corner is often exactly where a finger
must go. Here a seen object is the cells of a ``cell_m`` grid (world-anchored) holding its
points, each extended down to the table: what the camera saw of it and the space under that.
Its *tops* (the highest cell of each column) are what a hand coming straight down meets first
(the grasp fit's model); its *columns* (every cell from the top to the table) are the planner's,
which checks spheres in 3-D. The planner keeps its spheres ``collision_margin_m + fine_m`` away
from the cell centres, ``fine_m`` being a cell's rounding (half its diagonal), so every point of
every cell stays at least the margin away.

An object whose points cover less than ``min_seen_fraction`` of its box's footprint (mostly
hidden, or out of view in the latest frame) keeps its box — unless the frame saw through that
footprint: where the points of anything (table, other objects) cover at least
``seen_through_fraction`` of it, the track holds no object of its own there (a duplicate or a
fragment track of a neighbour, an object that has moved) and whatever is there is modelled by
those points. So is an unseen object whose footprint overlaps that of an object modelled by its
points by at least ``duplicate_overlap`` of the smaller one (two objects cannot stand in one
place: it is a second track of the seen one, whose box extends into the shadow behind it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from .exceptions import EnvironmentCloudError
from .occupancy import OrientedBox, cell_rounding_m, cleared_cell_m


def column_tops(points: np.ndarray, cell_m: float) -> np.ndarray:
    """(M, 3) the centre of the highest occupied ``cell_m`` cell (world grid) of each (x, y)
    column holding ``points`` (N, 3) world [m]; empty for no points."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    if len(pts) == 0:
        return np.zeros((0, 3))
    ii = np.floor(pts / cell_m).astype(np.int64)
    order = np.lexsort((ii[:, 2], ii[:, 1], ii[:, 0]))
    ii = ii[order]
    last = np.r_[np.any(ii[1:, :2] != ii[:-1, :2], axis=1), True]
    return (ii[last] + 0.5) * cell_m


@dataclass(frozen=True)
class PointModel:
    """How the planner and the grasp fit model the objects (``motion.yaml``): the grid
    ``cell_m`` [m] (half the occupancy voxel), the share of its box footprint an object's points
    must cover for it to be modelled by them, the share of an unseen object's footprint the
    frame must have seen through for it to be dropped, and the overlap with a seen object's
    footprint that makes it that object's duplicate."""

    cell_m: float
    min_seen_fraction: float
    seen_through_fraction: float
    duplicate_overlap: float

    @classmethod
    def from_motion(cls, config) -> "PointModel":
        """The model of a ``MotionConfig``."""
        return cls(cleared_cell_m(float(config.voxel_size_m)), float(config.object_points_min_seen_fraction),
                   float(config.object_points_seen_through_fraction),
                   float(config.object_points_duplicate_overlap))

    @property
    def boxes_only(self) -> bool:
        return self.min_seen_fraction > 1.0


def _cell_keys(ij: np.ndarray) -> np.ndarray:
    return (ij[:, 0].astype(np.int64) + (1 << 24)) * (1 << 25) + (ij[:, 1].astype(np.int64) + (1 << 24))


def seen_cells(points: np.ndarray, cell_m: float) -> np.ndarray:
    """The sorted keys of the (x, y) cells of a ``cell_m`` grid holding any of ``points`` (N, 3)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    return np.unique(_cell_keys(np.floor(pts[:, :2] / cell_m).astype(np.int64)))


def seen_cells_among(point_sets, candidates: np.ndarray, cell_m: float) -> np.ndarray:
    """The sorted keys among ``candidates`` (cell keys, e.g. :func:`footprint_cells` of a few
    boxes) of the cells holding any point of ``point_sets`` (arrays of (N, 3) points): for
    those cells, what :func:`seen_cells` of all the points holds, without keying (and sorting)
    the points that lie outside the candidates' range of cells."""
    cand = np.unique(np.asarray(candidates, dtype=np.int64))
    if len(cand) == 0:
        return cand
    i, j = cand // (1 << 25) - (1 << 24), cand % (1 << 25) - (1 << 24)
    i_lo, i_hi, j_lo, j_hi = float(i.min()), float(i.max()), float(j.min()), float(j.max())
    keys = []
    for points in point_sets:
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        f = np.floor(pts[:, :2] / cell_m)  # NaN and infinite rows fail every comparison below
        near = (f[:, 0] >= i_lo) & (f[:, 0] <= i_hi) & (f[:, 1] >= j_lo) & (f[:, 1] <= j_hi)
        near[near] = np.isfinite(pts[near, 2])
        keys.append(_cell_keys(f[near].astype(np.int64)))
    return cand[np.isin(cand, np.concatenate(keys))] if keys else cand[:0]


def footprint_cells(box: OrientedBox, cell_m: float) -> np.ndarray:
    """The keys of the ``cell_m`` cells whose centres lie in ``box``'s footprint (its two most
    horizontal axes, projected on the floor)."""
    R, e, c = np.asarray(box.R, float), np.asarray(box.extents, float), np.asarray(box.center, float)
    k = np.argsort(np.abs(R[2]))[:2]
    corners = np.array([c[:2] + sa * 0.5 * e[k[0]] * R[:2, k[0]] + sb * 0.5 * e[k[1]] * R[:2, k[1]]
                        for sa in (-1, 1) for sb in (-1, 1)])
    lo = np.floor(corners.min(axis=0) / cell_m).astype(np.int64)
    hi = np.floor(corners.max(axis=0) / cell_m).astype(np.int64)
    I, J = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
    ij = np.c_[I.ravel(), J.ravel()]
    centres = (ij + 0.5) * cell_m - c[:2]
    inside = np.ones(len(ij), dtype=bool)
    for a in k:
        axis = R[:2, a] / max(float(np.linalg.norm(R[:2, a])), 1e-12)
        inside &= np.abs(centres @ axis) <= 0.5 * e[a] * float(np.linalg.norm(R[:2, a]))
    return _cell_keys(ij[inside])


def footprint_overlap(a: OrientedBox, b: OrientedBox, cell_m: float) -> float:
    """The share of the smaller of the two boxes' footprints (``cell_m`` cells) that lies in
    the other's."""
    ca, cb = footprint_cells(a, cell_m), footprint_cells(b, cell_m)
    if len(ca) == 0 or len(cb) == 0:
        return 0.0
    return float(np.count_nonzero(np.isin(ca, cb))) / min(len(ca), len(cb))


def seen_through(box: OrientedBox, seen: np.ndarray, cell_m: float) -> float:
    """The share of ``box``'s footprint cells among the ``seen`` cell keys (:func:`seen_cells`)."""
    cells = footprint_cells(box, cell_m)
    return float(np.mean(np.isin(cells, seen))) if len(cells) else 0.0


def seen_fraction(tops: np.ndarray, box: OrientedBox, cell_m: float) -> float:
    """The share of ``box``'s footprint (the extents along its two most horizontal axes)
    covered by the columns ``tops`` (each ``cell_m`` square)."""
    k = np.argsort(np.abs(np.asarray(box.R, float)[2]))[:2]
    area = float(np.prod(np.asarray(box.extents, float)[k]))
    if area <= 0.0:
        return 1.0
    return min(1.0, len(tops) * cell_m * cell_m / area)


def columns(tops: np.ndarray, plane_n, plane_c: float, cell_m: float) -> np.ndarray:
    """(K, 3) the cell centres of every column from each top (``tops`` (M, 3), cell centres)
    down to the table plane (height ``n·p + c`` = 0): the cells under what was seen."""
    tops = np.asarray(tops, dtype=float).reshape(-1, 3)
    if len(tops) == 0:
        return tops
    n = np.asarray(plane_n, dtype=float)
    if abs(n[2]) < 1e-6:
        return tops
    z_table = -(float(plane_c) + tops[:, :2] @ n[:2]) / n[2]
    k = np.maximum(0, np.floor((tops[:, 2] - z_table) / cell_m).astype(np.int64)) + 1
    rep = np.repeat(np.arange(len(tops)), k)
    step = np.arange(len(rep)) - np.repeat(np.cumsum(k) - k, k)
    out = tops[rep].copy()
    out[:, 2] -= step * cell_m
    return out


@dataclass(frozen=True)
class ObjectPoints:
    """The planner's point obstacles: ``points`` (N, 3) world [m], cell centres of a grid of
    ``cell_m``; queries reach ``pad_m`` (at least the largest sphere radius + margin +
    rounding; farther points answer ``inf``)."""

    points: np.ndarray
    cell_m: float
    pad_m: float

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float).reshape(-1, 3)
        if not np.all(np.isfinite(pts)):
            raise EnvironmentCloudError("object points hold NaN/Inf")
        if not (self.cell_m > 0 and self.pad_m > 0):
            raise EnvironmentCloudError(f"object points need cell_m > 0 and pad_m > 0, got "
                                        f"{self.cell_m}, {self.pad_m}")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "_tree", cKDTree(pts) if len(pts) else None)

    @property
    def fine_m(self) -> float:
        return cell_rounding_m(self.cell_m)

    def distance_m(self, query: np.ndarray) -> np.ndarray:
        """(Q,) nearest point distance minus :attr:`fine_m` (a lower bound of the distance to
        the cells), ``inf`` where no point is nearer than ``pad_m``."""
        query = np.asarray(query, dtype=float).reshape(-1, 3)
        if self._tree is None:
            return np.full(len(query), np.inf)
        d, _ = self._tree.query(query, distance_upper_bound=self.pad_m)
        return d - self.fine_m

    def core_arrays(self) -> dict:
        """The ``points`` argument of ``_core.CollisionScene`` (bounding box, points, reach)."""
        lo, hi = (self.points.min(axis=0), self.points.max(axis=0)) if len(self.points) else \
            (np.zeros(3), np.zeros(3))
        return {"center_m": 0.5 * (lo + hi), "rotation": np.eye(3), "extents_m": hi - lo,
                "points_m": self.points, "pad_m": self.pad_m, "fine_m": self.fine_m}
