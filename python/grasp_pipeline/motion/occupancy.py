"""The perceived obstacles: a voxel occupancy map of the environment points with a
Euclidean distance field, plus oriented boxes (the non-target objects).

This is the octomap equivalent of the original design. Points are binned into voxels
of ``voxel_size_m`` inside the configured workspace box (points outside are ignored:
the robot cannot reach them); the grid spans the occupied voxels' bounding box padded
by ``pad_m`` (the largest distance a query needs) so its size follows the scene, not
the workspace. An exact Euclidean distance transform (the C++ core's; the values of
``scipy.ndimage.distance_transform_edt``) then gives, for every voxel centre, the distance to
the nearest occupied voxel centre, making a sphere query O(1).

Conservative semantics: an occupied voxel stands for a solid cube; a query point is
rounded to its voxel centre. Both roundings are bounded by half a voxel diagonal, so
``distance_m(p) - inflation_m`` (``inflation_m = √3·voxel``) is a lower bound of the
distance from ``p`` to any environment point. Queries outside the grid are farther than
``pad_m`` from every point and return ``inf``.
"""

from __future__ import annotations

import copy
import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from .. import _core
from ..array_rows import rows_where
from .exceptions import EnvironmentCloudError
from .thin_matmul import thin_matmul

log = logging.getLogger(__name__)

#: Near a cleared target region, environment points are kept on a grid this fraction of the
#: voxel size (e.g. 5 mm for 1 cm voxels) instead of the voxel grid.
_CLEARED_FINE_FRACTION = 0.5


def cleared_cell_m(voxel_size_m: float) -> float:
    """The fine grid cell [m] on which environment points near the grasp target are kept."""
    return voxel_size_m * _CLEARED_FINE_FRACTION


def cell_rounding_m(cell_m: float) -> float:
    """How far a point may lie from its ``cell_m`` cell's centre (half the cell's diagonal) [m]."""
    return 0.5 * math.sqrt(3.0) * cell_m


def cleared_rounding_m(voxel_size_m: float) -> float:
    """How far a kept point near the grasp target may lie from its fine-grid cell centre
    (half the cell's diagonal): subtracted from the nearest distances there."""
    return cell_rounding_m(cleared_cell_m(voxel_size_m))


@dataclass(frozen=True)
class OrientedBox:
    """A box obstacle: ``center`` (3,) m, rotation ``R`` (3, 3) (columns = box axes in
    world), full ``extents`` (3,) m along those axes."""

    center: np.ndarray
    R: np.ndarray
    extents: np.ndarray

    def __post_init__(self) -> None:
        c = np.asarray(self.center, dtype=float).reshape(3)
        R = np.asarray(self.R, dtype=float).reshape(3, 3)
        e = np.asarray(self.extents, dtype=float).reshape(3)
        if not (np.all(np.isfinite(c)) and np.all(np.isfinite(R)) and np.all(np.isfinite(e))):
            raise EnvironmentCloudError("object box has NaN/Inf center, rotation or extents")
        if np.any(e < 0):
            raise EnvironmentCloudError(f"object box has negative extents {e}")
        object.__setattr__(self, "center", c)
        object.__setattr__(self, "R", R)
        object.__setattr__(self, "extents", e)

    def inflated(self, pad_m: float) -> "OrientedBox":
        return OrientedBox(self.center, self.R, self.extents + 2.0 * pad_m)

    def local(self, points: np.ndarray) -> np.ndarray:
        """(N, 3) the points' coordinates along the box axes, from its centre
        (:mod:`.thin_matmul`)."""
        return thin_matmul(np.asarray(points, dtype=float) - self.center, self.R)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Boolean mask of the points (N, 3) inside the box (axis by axis: the test of
        ``np.all(np.abs(local) <= 0.5 * extents, axis=-1)``, several times faster)."""
        local, h = self.local(points), 0.5 * self.extents
        inside = np.abs(local[..., 0]) <= h[0]
        for j in (1, 2):
            inside &= np.abs(local[..., j]) <= h[j]
        return inside

    def distance_m(self, points: np.ndarray) -> np.ndarray:
        """Distance of each point (N, 3) to the box (0 inside)."""
        local = self.local(points)
        h = 0.5 * self.extents
        return np.linalg.norm(local - np.clip(local, -h, h), axis=-1)


def boxes_distance_m(boxes: list[OrientedBox], points: np.ndarray) -> np.ndarray:
    """(N,) distance of each point to the nearest box (inf without boxes)."""
    d = np.full(len(points), np.inf)
    for b in boxes:
        d = np.minimum(d, b.distance_m(points))
    return d


def in_box(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(N,) whether each point (N, 3) lies in the axis-aligned box ``lo``..``hi`` (bounds
    included; a NaN coordinate is outside): ``np.all((points >= lo) & (points <= hi), axis=1)``,
    column by column (several times faster than the reduction over the short axis)."""
    inside = (points[:, 0] >= lo[0]) & (points[:, 0] <= hi[0])
    for j in (1, 2):
        inside &= points[:, j] >= lo[j]
        inside &= points[:, j] <= hi[j]
    return inside


def _sorted_unique(keys: np.ndarray) -> np.ndarray:
    """``np.unique(keys)`` of a 1-D integer array, by a plain sort (several times faster)."""
    keys = np.sort(keys)
    first = np.empty(len(keys), dtype=bool)
    first[:1] = True
    np.not_equal(keys[1:], keys[:-1], out=first[1:])
    return keys[first]


def distance_field_m(occupied: np.ndarray, voxel_size_m: float) -> np.ndarray:
    """float32 field (the grid's shape): the distance [m] from each voxel centre to the nearest
    occupied voxel centre (0 on an occupied voxel); ``occupied`` holds one voxel at least.

    The same values as ``(ndimage.distance_transform_edt(~occupied) * voxel_size_m)
    .astype(np.float32)``, computed for less by the C++ core: the exact integer squared distance
    in voxels of every voxel (a separable transform) and ``sqrt(k) * voxel_size_m`` of those
    integers with the same float64 operations, so the same float32 values."""
    return _core.distance_field(np.ascontiguousarray(occupied, dtype=bool), float(voxel_size_m))


class OccupancyMap:
    """Voxelised environment points with a Euclidean distance field.

    Build with :meth:`from_points`. ``distance_m(points)`` → distance (m) from each
    query point's voxel centre to the nearest occupied voxel centre (``inf`` outside the
    grid or for an empty map). Subtract :attr:`inflation_m` for a guaranteed lower bound.
    """

    def __init__(self, origin_m: np.ndarray, voxel_size_m: float, occupied: np.ndarray,
                 pad_m: float, points: np.ndarray | None = None) -> None:
        self.origin_m = np.asarray(origin_m, dtype=float)
        self.voxel_size_m = float(voxel_size_m)
        self.occupied = occupied
        self.pad_m = float(pad_m)
        self._points = np.zeros((0, 3)) if points is None else points
        self.inflation_m = math.sqrt(3.0) * self.voxel_size_m
        self.shape = np.array(occupied.shape, dtype=np.int64)
        self.num_occupied = int(np.count_nonzero(occupied))
        self._field = distance_field_m(occupied, self.voxel_size_m) if self.num_occupied else None
        self._cleared: tuple[OrientedBox, object] | None = None
        self._cleared_views: dict[bytes, "OccupancyMap"] = {}

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_points(cls, points: np.ndarray, voxel_size_m: float, workspace_min_m, workspace_max_m,
                    pad_m: float, max_points: int, max_voxels: int) -> "OccupancyMap":
        """Voxelise environment points (N, 3) in ``world``.

        Non-finite points are dropped, points outside the workspace box are ignored. An
        empty cloud is a valid, empty map (free space). Raises EnvironmentCloudError for
        a malformed array, more than ``max_points`` points, or a grid over ``max_voxels``.
        """
        pts = np.asarray(points)
        if pts.size == 0:
            pts = pts.reshape(0, 3)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise EnvironmentCloudError(f"environment points must be an (N, 3) array, got shape {pts.shape}")
        if len(pts) > max_points:
            raise EnvironmentCloudError(
                f"environment cloud has {len(pts)} points, over the limit of {max_points} "
                "(motion.max_environment_points); down-sample it first")
        lo_ws = np.asarray(workspace_min_m, dtype=float)
        hi_ws = np.asarray(workspace_max_m, dtype=float)
        v = float(voxel_size_m)
        pad_vox = int(math.ceil(pad_m / v)) + 1
        if len(pts) == 0:
            return cls(lo_ws, v, np.zeros((1, 1, 1), dtype=bool), pad_m, np.zeros((0, 3)))
        # the finite points inside the workspace box (bounds included), their voxels
        # floor((p - lo) / v), and the grid of those voxels padded by pad_vox: the C++ core's
        kept, first, shape, occ = _core.voxelize_points(np.ascontiguousarray(pts, dtype=float), lo_ws, hi_ws,
                                                        v, pad_vox, int(max_voxels))
        if len(kept) == 0:
            return cls(lo_ws, v, np.zeros((1, 1, 1), dtype=bool), pad_m, kept)
        if occ is None:
            raise EnvironmentCloudError(
                f"occupancy grid would need {int(np.prod(shape))} voxels of {v * 100:.1f} cm "
                f"({shape.tolist()}), over the limit of {max_voxels} (motion.max_grid_voxels); "
                "crop the cloud or use a larger voxel_size_m")
        return cls(lo_ws + first * v, v, occ, pad_m, kept)

    # ------------------------------------------------------------------ queries
    def _lookup(self, field: np.ndarray | None, origin: np.ndarray, shape: np.ndarray,
                points: np.ndarray) -> np.ndarray:
        if field is None:
            return np.full(len(points), np.inf)
        idx = np.floor((points - origin) / self.voxel_size_m).astype(np.int64)
        inside = np.all((idx >= 0) & (idx < shape), axis=1)
        out = np.full(len(points), np.inf)
        ii = idx[inside]
        out[inside] = field[ii[:, 0], ii[:, 1], ii[:, 2]]
        return out

    def distance_m(self, points: np.ndarray, cleared: bool = False) -> np.ndarray:
        """(N,) distance from each point's voxel centre to the nearest occupied voxel.

        ``cleared=True`` (only on a view from :meth:`with_cleared_region`) answers as if
        the voxels inside the cleared box were free, for queries within ``pad_m`` of it.
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        d = self._lookup(self._field, self.origin_m, self.shape, points)
        if cleared and self._cleared is not None:
            box, tree = self._cleared
            near = box.distance_m(points) <= self.pad_m
            if np.any(near):
                if tree is None:
                    d[near] = np.inf
                else:
                    dd, _ = tree.query(points[near], distance_upper_bound=self.pad_m)
                    # point distances (minus the fine-grid rounding); + inflation keeps
                    # "distance_m - inflation_m" a lower bound
                    fine = cleared_rounding_m(self.voxel_size_m)
                    d[near] = dd - fine + self.inflation_m
        return d

    def with_cleared_region(self, box: OrientedBox) -> "OccupancyMap":
        """A view of this map whose ``distance_m(..., cleared=True)`` treats the voxels
        inside ``box`` as free (the grasp target's region). The original is unchanged; the view
        of one box is built once per map (asking again for the same box returns it).

        Near the box (within ``pad_m``) distances come from a k-d tree over the environment
        points outside the box, kept on a fine grid (half a voxel): nearly exact distances
        (fine rounding subtracted, ``inflation_m`` added so subtracting it stays correct), so
        the hand may come as close to the table beside the target as the margin allows.
        """

        box_key = b"".join(np.ascontiguousarray(a, dtype=float).tobytes()
                           for a in (box.center, box.R, box.extents))
        cached = self._cleared_views.get(box_key)
        if cached is not None:
            return cached
        view = copy.copy(self)
        view._cleared_views = {}
        pts = self._points
        half = 0.5 * np.abs(box.R) @ box.extents + 2.0 * self.pad_m
        near = np.abs(pts[:, 0] - box.center[0]) <= half[0]  # column by column: the same test
        for j in (1, 2):
            near &= np.abs(pts[:, j] - box.center[j]) <= half[j]
        pts = rows_where(pts, near)
        pts = pts[~box.contains(pts)]
        # de-duplicate on a fine grid (its rounding is subtracted from the distances)
        f = cleared_cell_m(self.voxel_size_m)
        if len(pts):
            ii = np.floor((pts - box.center) / f).astype(np.int64)
            lo = np.array([ii[:, j].min() for j in range(3)])  # column by column: faster
            ii -= lo
            dims = np.array([ii[:, j].max() for j in range(3)]) + 1
            key = _sorted_unique((ii[:, 0] * dims[1] + ii[:, 1]) * dims[2] + ii[:, 2])
            ii = np.stack([key // (dims[1] * dims[2]), (key // dims[2]) % dims[1], key % dims[2]], axis=1)
            pts = box.center + (ii + lo + 0.5) * f
        view._cleared = (box, cKDTree(pts) if len(pts) else None)
        self._cleared_views[box_key] = view
        return view

    # ------------------------------------------------------------------ export
    @property
    def distance_field_m(self) -> np.ndarray | None:
        """The float32 distance field (grid ``shape``, C order; None for an empty map)."""
        return self._field

    def cleared_region(self) -> tuple[OrientedBox, np.ndarray, float] | None:
        """For a view from :meth:`with_cleared_region`: the cleared box, the kept points
        (M, 3) near it, and their rounding ``fine_m`` (subtracted from nearest distances);
        None on a plain map."""
        if self._cleared is None:
            return None
        box, tree = self._cleared
        pts = np.zeros((0, 3)) if tree is None else np.asarray(tree.data, dtype=float)
        return box, pts, cleared_rounding_m(self.voxel_size_m)

    def __repr__(self) -> str:
        return (f"OccupancyMap({self.num_occupied} occupied voxels of {self.voxel_size_m * 100:.1f} cm, "
                f"grid {self.shape.tolist()})")
