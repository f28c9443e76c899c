"""What lies in the tray, as the robot knows it: the objects it placed there, refreshed by what
the camera sees when it looks in.

The tray is the work cell's floor box (its footprint, its top) and the fixtures standing on it
(the walls). Its contents are named objects ``placed/<k>``, each the column tops of its points
(cell centres of a world-anchored ``cell_m`` grid, as the planner models objects by their
points, :mod:`grasp_pipeline.motion.object_points`):

* **released**: the held object's points at the release pose, dropped straight down onto what
  is under them (the floor or an object placed earlier);
* **seen**: a look into the tray replaces them. Its points over the floor (not on the walls)
  higher than ``min_height_m`` are split into connected regions; a region takes the name of
  the object whose footprint it overlaps most (that object's cells the look did not see are
  kept), or a new name. An object whose footprint the look saw without finding anything
  there has left (it fell elsewhere); one the look did not see stays as it was.

Heights are measured along the world vertical from the floor's top (the tray stands level).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import ndimage

from ... import _core
from ...array_rows import rows_where

from ...motion.object_points import column_tops
from ...motion.occupancy import OrientedBox
from ...motion.work_cell import WorkCell, footprint_distance_m

PLACED_PREFIX = "placed/"
#: Share of an object's footprint a look must see to judge whether it is still there.
SEEN_ENOUGH = 0.5


@dataclass(frozen=True)
class TrayGeometry:
    """The tray floor's footprint (``center_xy``, unit ``axes`` (2, 2) as columns in world
    x/y, ``half_m`` along them), its top height ``floor_z_m`` and the ``walls`` (fixtures
    standing higher than the floor over its footprint)."""

    center_xy: np.ndarray
    axes: np.ndarray
    half_m: np.ndarray
    floor_z_m: float
    walls: tuple[OrientedBox, ...] = ()

    @classmethod
    def from_work_cell(cls, cell: WorkCell) -> "TrayGeometry":
        floor = cell.tray_floor
        if floor is None or cell.tray_center_m is None:
            raise ValueError("the work cell has no tray (tray_floor / tray_center_m)")
        R = np.asarray(floor.R, float)
        k = np.argsort(np.abs(R[2]))[:2]  # the two most horizontal box axes
        axes = R[:2, k] / np.linalg.norm(R[:2, k], axis=0)
        half = 0.5 * np.asarray(floor.extents, float)[k]
        floor_z = float(cell.tray_center_m[2])
        walls = tuple(b for b in cell.fixtures if _top_z(b) > floor_z + 1e-3
                      and _overlaps_footprint(b, floor))
        return cls(np.asarray(floor.center[:2], float), axes, half, floor_z, walls)

    @property
    def rim_m(self) -> float:
        """Height of the highest wall above the floor [m] (0 without walls)."""
        return max((_top_z(w) - self.floor_z_m for w in self.walls), default=0.0)

    def grid(self, cell_m: float) -> "TrayGrid":
        return TrayGrid(self, float(cell_m))


def _top_z(box: OrientedBox) -> float:
    return float(box.center[2] + 0.5 * np.abs(np.asarray(box.R)[2]) @ np.asarray(box.extents))


def _footprint_distances(box: OrientedBox, xy: np.ndarray) -> np.ndarray:
    """(N,) signed horizontal distance of each ``xy`` (N, 2) to the upright box's footprint
    (< 0 inside; :func:`~grasp_pipeline.motion.work_cell.footprint_distance_m` for many)."""
    d = np.c_[np.asarray(xy, float) - np.asarray(box.center[:2]), np.zeros(len(xy))]
    over = np.abs(d @ np.asarray(box.R))[:, :2] - 0.5 * np.asarray(box.extents)[:2]
    outside = np.linalg.norm(np.maximum(over, 0.0), axis=1)
    return np.where(outside > 0.0, outside, over.max(axis=1))


def _overlaps_footprint(box: OrientedBox, floor: OrientedBox) -> bool:
    return footprint_distance_m(floor, np.asarray(box.center[:2])) <= 0.5 * float(np.max(box.extents))


@dataclass(frozen=True)
class TrayGrid:
    """Square cells of ``cell_m`` over the floor's footprint, in the floor's axes."""

    geometry: TrayGeometry
    cell_m: float

    @property
    def shape(self) -> tuple[int, int]:
        n = np.maximum(1, np.floor(2.0 * self.geometry.half_m / self.cell_m).astype(int))
        return int(n[0]), int(n[1])

    def index(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) integer cell indices of world ``xy`` (N, 2) (may lie outside the grid).

        The rotation into the floor's axes is written out per component: a BLAS
        ``(N, 2) @ (2, 2)`` product costs several times more (its threads wait on each other
        when the cores are busy) for the same sums.
        """
        g = self.geometry
        d = np.asarray(xy, float).reshape(-1, 2) - g.center_xy
        uv = np.empty_like(d)
        for j in range(2):
            uv[:, j] = d[:, 0] * g.axes[0, j] + d[:, 1] * g.axes[1, j]
        uv += g.half_m
        return np.floor(uv / self.cell_m).astype(np.int64)

    def cells_of(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The finite ``points`` (N, 3) world that fall in a cell of the grid, in their order,
        as float (M, 3), and their cell indices (M, 2).

        A whole camera frame mostly lies outside the tray: a bounding test on world x/y (the
        footprint's axis-aligned box, a cell wider on each side) drops those points before
        the per-point work; the points it keeps are indexed as by :meth:`index` (one pass of
        the C++ core, the same sums in the same order).
        """
        pts = np.asarray(points).reshape(-1, 3)
        if len(pts) == 0:
            return np.zeros((0, 3)), np.zeros((0, 2), dtype=np.int64)
        if pts.dtype not in (np.float32, np.float64):
            pts = pts.astype(float)
        g = self.geometry
        lo, hi = self._bounds_xy()
        nu, nv = self.shape
        rows, ij = _core.points_in_grid_cells(np.ascontiguousarray(pts), g.center_xy, g.axes, g.half_m,
                                              self.cell_m, nu, nv, lo, hi)
        return np.take(pts, rows, axis=0).astype(float, copy=False), ij

    def _bounds_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """World x/y box around every cell of the grid (with a cell's margin)."""
        g = self.geometry
        reach = np.abs(g.axes) @ g.half_m + self.cell_m
        return g.center_xy - reach, g.center_xy + reach

    def centres(self) -> np.ndarray:
        """(nu, nv, 2) world xy of every cell's centre."""
        g = self.geometry
        nu, nv = self.shape
        u = (np.arange(nu) + 0.5) * self.cell_m - g.half_m[0]
        v = (np.arange(nv) + 0.5) * self.cell_m - g.half_m[1]
        U, V = np.meshgrid(u, v, indexing="ij")
        return g.center_xy + U[..., None] * g.axes[:, 0] + V[..., None] * g.axes[:, 1]

    def inside(self, ij: np.ndarray) -> np.ndarray:
        nu, nv = self.shape
        return (ij[:, 0] >= 0) & (ij[:, 0] < nu) & (ij[:, 1] >= 0) & (ij[:, 1] < nv)

    def heights(self, points: np.ndarray) -> np.ndarray:
        """(nu, nv) the highest point of each cell above the floor [m], NaN where none."""
        pts, ij = self.cells_of(points)
        out = np.full(self.shape, -np.inf)
        flat = ij[:, 0] * self.shape[1] + ij[:, 1]  # ufunc.at is much faster on one index
        np.maximum.at(out.reshape(-1), flat, pts[:, 2] - self.geometry.floor_z_m)
        out[np.isinf(out)] = np.nan
        return out

    @cached_property
    def wall_heights(self) -> np.ndarray:
        """(nu, nv) the top of the walls above the floor in the cells they stand on (or
        touch), 0 elsewhere."""
        out = np.zeros(self.shape)
        c = self.centres().reshape(-1, 2)
        for w in self.geometry.walls:
            on = (_footprint_distances(w, c) <= 0.5 * self.cell_m).reshape(self.shape)
            out[on] = np.maximum(out[on], _top_z(w) - self.geometry.floor_z_m)
        return out

    def wall_mask(self) -> np.ndarray:
        """(nu, nv) cells a wall stands on (or touches)."""
        return self.wall_heights > 0.0

    def dilate(self, mask: np.ndarray, radius_m: float) -> np.ndarray:
        """``mask`` grown by ``radius_m`` (a disc of cells)."""
        r = int(np.ceil(radius_m / self.cell_m))
        if r <= 0:
            return mask.copy()
        y, x = np.ogrid[-r:r + 1, -r:r + 1]
        return ndimage.binary_dilation(mask, structure=(x * x + y * y) <= r * r)


@dataclass(frozen=True)
class PlacedObject:
    """One object in the tray: ``tops`` (M, 3) world, the column tops of its points."""

    name: str
    tops: np.ndarray

    def box(self, floor_z_m: float) -> OrientedBox:
        """Its bounding box from the floor up (axes: its footprint's principal directions)."""
        xy = self.tops[:, :2]
        c = xy.mean(axis=0)
        _, _, vt = np.linalg.svd(xy - c, full_matrices=False) if len(xy) > 1 else (0, 0, np.eye(2))
        a = vt[0] / np.linalg.norm(vt[0])
        R = np.array([[a[0], -a[1], 0.0], [a[1], a[0], 0.0], [0.0, 0.0, 1.0]])
        local = (xy - c) @ R[:2, :2]
        lo, hi = local.min(axis=0), local.max(axis=0)
        top = float(self.tops[:, 2].max())
        mid = c + R[:2, :2] @ (0.5 * (lo + hi))
        ext = np.r_[hi - lo, top - floor_z_m]
        return OrientedBox(np.r_[mid, 0.5 * (top + floor_z_m)], R, np.maximum(ext, 1e-3))


class TrayContents:
    """The named objects in the tray (see the module doc); ``cell_m``: the grid of their
    column tops (the planner's point-model cell); ``min_height_m``: points higher than this
    above the floor are contents."""

    def __init__(self, geometry: TrayGeometry, cell_m: float, min_height_m: float) -> None:
        self.geometry = geometry
        self.cell_m = float(cell_m)
        self.min_height_m = float(min_height_m)
        self.objects: dict[str, PlacedObject] = {}
        self._count = 0

    def _new_name(self) -> str:
        name = f"{PLACED_PREFIX}{self._count}"
        self._count += 1
        return name

    def heights(self, grid: TrayGrid) -> np.ndarray:
        """(nu, nv) the top of the contents above the floor in each cell of ``grid`` [m]
        (0: nothing there); the walls are not included."""
        if not self.objects:
            return np.zeros(grid.shape)
        tops = np.vstack([o.tops for o in self.objects.values()])
        h = grid.heights(tops + np.array([0.0, 0.0, 0.5 * self.cell_m]))  # a cell's top face
        # a column top stands for its whole cell: spread it over the (finer or coarser) grid
        h = ndimage.maximum_filter(np.nan_to_num(h, nan=0.0),
                                   size=max(1, int(np.ceil(self.cell_m / grid.cell_m))))
        return np.maximum(h, 0.0)

    def add_released(self, points_world: np.ndarray) -> PlacedObject:
        """Register the object released with ``points_world`` (N, 3): dropped straight down
        onto what lies under it."""
        pts = np.asarray(points_world, float).reshape(-1, 3)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            raise ValueError("add_released: no finite points")
        grid = self.geometry.grid(self.cell_m)
        ij = grid.index(pts[:, :2])
        ok = grid.inside(ij)
        under = self.heights(grid)[ij[ok, 0], ij[ok, 1]]
        support = float(under.max()) if len(under) else 0.0
        pts = pts + np.array([0.0, 0.0, self.geometry.floor_z_m + support - float(pts[:, 2].min())])
        obj = PlacedObject(self._new_name(), column_tops(pts, self.cell_m))
        self.objects[obj.name] = obj
        return obj

    def update_from_look(self, points_world: np.ndarray) -> list[str]:
        """Replace what the look saw (see the module doc); returns the names that left."""
        grid = self.geometry.grid(self.cell_m)
        pts, ij = grid.cells_of(points_world)
        on_wall = grid.dilate(grid.wall_mask(), self.cell_m)[ij[:, 0], ij[:, 1]]
        pts, ij = rows_where(pts, ~on_wall), rows_where(ij, ~on_wall)
        seen = np.zeros(grid.shape, dtype=bool)
        seen[ij[:, 0], ij[:, 1]] = True
        high = pts[:, 2] - self.geometry.floor_z_m > self.min_height_m
        regions = _regions(grid, ij[high])
        return self._replace(grid, seen, regions, pts[high], ij[high])

    def _replace(self, grid: TrayGrid, seen: np.ndarray, labels: np.ndarray, pts: np.ndarray,
                 ij: np.ndarray) -> list[str]:
        old = {n: _cells_mask(grid, o.tops) for n, o in self.objects.items()}
        point_label = labels[ij[:, 0], ij[:, 1]] if len(ij) else np.zeros(0, dtype=int)
        new: dict[str, PlacedObject] = {}
        sizes = np.bincount(labels.reshape(-1))[1:] if labels.max() > 0 else np.zeros(0)
        for lab in np.argsort(-sizes) + 1:
            region = labels == lab
            name = max((n for n in old if n not in new and np.any(old[n] & region)),
                       key=lambda n: int(np.count_nonzero(old[n] & region)), default=None)
            tops = column_tops(pts[point_label == lab], self.cell_m)
            if name is not None:  # keep what the look did not see of it
                unseen = ~_cells_mask_of(grid, self.objects[name].tops, seen)
                tops = np.vstack([tops, self.objects[name].tops[unseen]])
            name = name or self._new_name()
            new[name] = PlacedObject(name, tops)
        gone = []
        for n, mask in old.items():
            if n in new:
                continue
            if np.count_nonzero(mask & seen) >= SEEN_ENOUGH * max(1, np.count_nonzero(mask)):
                gone.append(n)
            else:
                new[n] = self.objects[n]
        self.objects = new
        return gone


def _regions(grid: TrayGrid, ij: np.ndarray) -> np.ndarray:
    """(nu, nv) labels (0: none) of the connected regions of the cells ``ij``; single cells
    on their own are noise."""
    mask = np.zeros(grid.shape, dtype=bool)
    if len(ij):
        mask[ij[:, 0], ij[:, 1]] = True
    labels, n = ndimage.label(mask, structure=np.ones((3, 3), dtype=bool))
    sizes = np.bincount(labels.reshape(-1), minlength=n + 1)
    keep = np.nonzero(sizes[1:] >= 2)[0] + 1
    lut = np.zeros(n + 1, dtype=np.int64)
    lut[keep] = np.arange(1, len(keep) + 1)
    return lut[labels]


def _cells_mask(grid: TrayGrid, tops: np.ndarray) -> np.ndarray:
    mask = np.zeros(grid.shape, dtype=bool)
    ij = grid.index(tops[:, :2])
    ok = grid.inside(ij)
    mask[ij[ok, 0], ij[ok, 1]] = True
    return mask


def _cells_mask_of(grid: TrayGrid, tops: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """(M,) whether each of ``tops`` lies in a cell of ``mask``."""
    ij = grid.index(tops[:, :2])
    ok = grid.inside(ij)
    out = np.zeros(len(tops), dtype=bool)
    out[ok] = mask[ij[ok, 0], ij[ok, 1]]
    return out
