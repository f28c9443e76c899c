"""Where in the tray the held object goes: a free spot on the floor with room for the object
and the hand, nearest the preferred one.

The held object is known by its points in the TCP frame (what was perceived of it at the grasp)
and, like the hand and the fingers, by the planner's spheres of it in the TCP frame. The object
keeps the attitude it was carried with; only the TCP's turn about the vertical (``rotations``)
and the position change. At a spot, the object's bottom is released ``release_clearance_m``
above the floor, which fixes how high every hand sphere then is. A spot (cell of the tray's
``spot_cell_m`` grid, the TCP above its centre) with one rotation is **free** when

* every cell under the object's spheres (grown by ``spot_spacing_m``) lies on the tray floor,
  away from the walls, and holds nothing higher than ``seen_min_height_m`` above what lies
  under the object's points (the floor: nothing; see below for what lies in the tray);
* under every hand sphere (grown by ``spot_spacing_m``), the walls and contents stay at least
  ``spot_spacing_m`` below the sphere; outside the tray the walls' height counts.

Where the floor has too few such spots (none left, or the arm cannot reach them), the object
may go onto what lies in the tray, lowest first (the same rules, released above the top of
what is under it), if that is at most ``stack_max_m`` high; with no spot at all the tray is
full: :class:`TrayFull`.

Spots are ranked by their distance to the preferred positions (:func:`preferred_positions`:
corners first, the k-th object starting at the k-th); each kept spot is at least
``spot_separation_m`` from the spots before it, with its free rotations in their given order.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ...exceptions import GraspPipelineError
from .place_config import PlaceConfig
from .tray import TrayContents

log = logging.getLogger("grasp_pipeline.grasp")


class TrayFull(GraspPipelineError):
    """No free spot in the tray for the held object."""


@dataclass(frozen=True)
class HeldShape:
    """The held object's points ``points_tcp`` (N, 3) and the planner's spheres of it
    (``object_centres`` (M, 3), ``object_radii`` (M,)) and of the hand (``hand_centres``
    (S, 3), ``hand_radii`` (S,)), all in the TCP frame."""

    points_tcp: np.ndarray
    object_centres: np.ndarray
    object_radii: np.ndarray
    hand_centres: np.ndarray
    hand_radii: np.ndarray

    def bottom_m(self, R: np.ndarray) -> float:
        """How far the object's lowest point lies below the TCP [m] with the TCP rotation ``R``
        (the same for every turn about the vertical)."""
        return -float((self.points_tcp @ np.asarray(R, float).T)[:, 2].min())

    def size_mm(self) -> str:
        ext = np.ptp(self.points_tcp, axis=0) * 1e3
        return " x ".join(f"{e:.0f}" for e in np.sort(ext)[::-1]) + " mm"


@dataclass(frozen=True)
class Spot:
    """A free spot: the TCP's ``xy`` [m] there and its free ``rotations`` (in preference
    order); ``distance_m`` from the preferred position."""

    xy: np.ndarray
    rotations: tuple
    distance_m: float


#: The preferred positions' order on a 3 x 3 pattern (in the tray floor's axes, -1 / 0 / +1
#: times the pattern's reach): the corners first, then the middles of the sides, then the
#: centre — objects packed against the walls leave the middle free for the next ones.
PATTERN = ((1, 1), (-1, 1), (1, -1), (-1, -1), (0, 1), (0, -1), (1, 0), (-1, 0), (0, 0))


def preferred_positions(geometry, k: int, inset_m: float) -> list:
    """World xy of the 9 preferred positions, the k-th first (then round the pattern):
    ``inset_m`` in from the edges of the tray floor."""
    reach = np.maximum(geometry.half_m - inset_m, 0.0)
    out = []
    for i in range(len(PATTERN)):
        a, b = PATTERN[(k + i) % len(PATTERN)]
        out.append(geometry.center_xy + geometry.axes @ (np.array([a, b]) * reach))
    return out


def _stamp(shape: HeldShape, R: np.ndarray, axes: np.ndarray, cell_m: float, cfg: PlaceConfig):
    """The cells around the TCP's cell (offsets in the tray grid's axes ``axes``) a spot with
    the TCP rotation ``R`` needs: ``obj`` (K, 2) under the object's spheres (grown by the
    spacing); ``under`` (J, 2) under its points (what it will stand on); ``hand`` (L, 2) with
    ``limits`` (L,): the highest content allowed there with the object on the floor [m]."""
    R = np.asarray(R, float)
    s = cfg.spot_spacing_m
    obj = _cells_near((shape.object_centres @ R.T)[:, :2] @ axes, shape.object_radii, s, cell_m)
    under = np.unique(np.floor((shape.points_tcp @ R.T)[:, :2] @ axes / cell_m + 0.5).astype(int), axis=0)
    h_tcp = cfg.release_clearance_m + shape.bottom_m(R)
    C = shape.hand_centres @ R.T
    cells, limits = [], []
    for c, r in zip(C, shape.hand_radii):
        d = _cells_near(c[None, :2] @ axes, np.array([r]), s, cell_m)
        cells.append(d)
        limits.append(np.full(len(d), h_tcp + c[2] - r - s))
    cells, limits = np.vstack(cells), np.concatenate(limits)
    order = np.lexsort((limits, cells[:, 1], cells[:, 0]))
    cells, limits = cells[order], limits[order]
    first = np.r_[True, np.any(cells[1:] != cells[:-1], axis=1)]
    return obj, under, cells[first], limits[first]  # the lowest limit of each cell


def _cells_near(xy: np.ndarray, r: np.ndarray, pad_m: float, cell_m: float) -> np.ndarray:
    """Offsets (K, 2) of the cells (the TCP at the centre of cell (0, 0)) that come within
    ``pad_m`` of a disc of radius ``r`` (N,) around any of ``xy`` (N, 2) [m]."""
    reach = pad_m + 0.5 * np.sqrt(2.0) * cell_m
    lo = np.floor((xy - r[:, None]).min(axis=0) / cell_m - 1 - reach / cell_m).astype(int)
    hi = np.ceil((xy + r[:, None]).max(axis=0) / cell_m + 1 + reach / cell_m).astype(int)
    I, J = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
    off = np.c_[I.ravel(), J.ravel()]
    d = np.linalg.norm(off[:, None] * cell_m - xy[None], axis=2) - r[None]
    return off[np.min(d, axis=1) <= reach]


def _spot_cells(grid, contents_h: np.ndarray, heights: np.ndarray, inside: np.ndarray, stamp,
                rim_m: float, tolerance_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(ok, support), each (nu, nv), for the TCP over each cell's centre: whether the object
    lies inside the walls, rests on the highest thing under its spheres (nothing beside it
    stands higher than what it stands on, give or take ``tolerance_m``) and the hand clears
    the walls and contents with the object on it; the height of what it stands on (0: the
    floor).

    Each test asks for the highest value over a set of cells around each cell (maxima are
    exact, so in any grouping: the same verdicts), taken over runs of cells along a row
    (:func:`_highest`)."""
    obj, under, hand, limits = stamp
    pad = int(max(np.abs(obj).max(initial=0), np.abs(hand).max(initial=0)))
    shape = grid.shape
    C = np.pad(contents_h, pad, constant_values=np.inf)
    inside = np.pad(inside, pad, constant_values=False)
    H = np.pad(heights, pad, constant_values=rim_m)
    # a cell outside the walls under the object counts as infinitely high: never finite
    around = np.maximum(_highest(np.where(inside, C, np.inf), obj, pad, shape), 0.0)
    support = np.maximum(_highest(C, under, pad, shape), 0.0)
    ok = np.isfinite(around) & (around <= support + tolerance_m)
    # every hand cell's height is at most its limit plus the support: per distinct limit (the
    # hand's spheres give a few), the highest of its cells is
    table = _RunMaxima(H)
    for lim in np.unique(limits):
        ok &= _highest(H, hand[limits == lim], pad, shape, table) <= lim + support
    return ok, support


class _RunMaxima:
    """Maxima of an array over runs of consecutive columns: level ``l`` holds, at column ``j``,
    the largest of columns ``j .. j + 2**l - 1`` (a sparse table); a run of any length is the
    larger of two overlapping power-of-two runs."""

    def __init__(self, a: np.ndarray) -> None:
        self.levels = [a]

    def level(self, length: int) -> tuple[np.ndarray, int]:
        """(the level of the longest power-of-two run within ``length``, that run's length)."""
        lv = length.bit_length() - 1
        while len(self.levels) <= lv:
            prev, half = self.levels[-1], 1 << (len(self.levels) - 1)
            self.levels.append(np.maximum(prev[:, :-half], prev[:, half:]))
        return self.levels[lv], 1 << lv


def _row_runs(offsets: np.ndarray) -> list[tuple[int, int, int]]:
    """The cells ``offsets`` (K, 2) as runs (du, first dv, last dv) of consecutive dv."""
    o = offsets[np.lexsort((offsets[:, 1], offsets[:, 0]))]
    breaks = np.flatnonzero((np.diff(o[:, 0]) != 0) | (np.diff(o[:, 1]) != 1)) + 1
    starts, ends = np.r_[0, breaks], np.r_[breaks, len(o)] - 1
    return [(int(o[a, 0]), int(o[a, 1]), int(o[b, 1])) for a, b in zip(starts, ends)]


def _highest(a: np.ndarray, offsets: np.ndarray, pad: int, shape: tuple[int, int],
             table: _RunMaxima | None = None) -> np.ndarray:
    """(nu, nv) for each cell, the largest of ``a`` (the grid padded by ``pad``) over the
    cells at ``offsets`` (K, 2) from it (-inf without offsets); ``table``: ``a``'s run maxima."""
    nu, nv = shape
    out = np.full(shape, -np.inf)
    if len(offsets) == 0:
        return out
    table = table if table is not None else _RunMaxima(a)
    for du, first, last in _row_runs(np.asarray(offsets)):
        lv, w = table.level(last - first + 1)
        rows = slice(pad + du, pad + du + nu)
        np.maximum(out, lv[rows, pad + first:pad + first + nv], out=out)
        if w < last - first + 1:
            np.maximum(out, lv[rows, pad + last - w + 1:pad + last - w + 1 + nv], out=out)
    return out


def _free(contents: TrayContents, shape: HeldShape, rotations, cfg: PlaceConfig):
    """(grid, [floor, on the lowest, on the others], each (R, nu, nv)): where the object and
    the hand fit with each rotation — on the floor; on what lies lowest in the tray, then on
    the rest up to ``stack_max_m`` high, for when no floor spot can be reached or none is left."""
    grid = contents.geometry.grid(cfg.spot_cell_m)
    contents_h = contents.heights(grid)
    heights = np.maximum(contents_h, grid.wall_heights)
    axes, rim = contents.geometry.axes, contents.geometry.rim_m
    res = [_spot_cells(grid, contents_h, heights, ~grid.wall_mask(),
                       _stamp(shape, R, axes, grid.cell_m, cfg), rim, cfg.seen_min_height_m)
           for R in rotations]
    ok, support = np.array([r[0] for r in res]), np.array([r[1] for r in res])
    floor = ok & (support <= cfg.seen_min_height_m)
    on_top = ok & ~floor & (support <= cfg.stack_max_m)
    lowest = on_top & (support <= float(support[on_top].min(initial=0.0)) + cfg.seen_min_height_m)
    if not np.any(floor | on_top):
        raise TrayFull(f"the tray is full: no room for the held object ({shape.size_mm()}) and "
                       f"the hand, on the floor or on the {len(contents.objects)} object(s) in it "
                       f"up to {cfg.stack_max_m * 1e3:.0f} mm high")
    if not np.any(floor):
        log.warning("the tray's floor has no room left for the held object (%s): it goes onto "
                    "what lies there, %.0f mm high", shape.size_mm(),
                    float(support[on_top].min()) * 1e3)
    return grid, [floor, lowest, on_top & ~lowest]


def free_spots(contents: TrayContents, shape: HeldShape, rotations, preferred: list,
               cfg: PlaceConfig) -> list[Spot]:
    """Up to ``arrival_spots`` free spots (module doc): the floor's spot nearest each of the
    ``preferred`` positions in turn, then its others nearest the first; then the same on what
    lies in the tray, lowest first; :class:`TrayFull` when there is none."""
    grid, layers = _free(contents, shape, rotations, cfg)
    spots: list[Spot] = []
    for free in layers:
        for p in preferred:  # the nearest free spot to each preferred position ...
            _add_spots(spots, grid, free, rotations, p, 1, cfg)
        _add_spots(spots, grid, free, rotations, preferred[0], cfg.arrival_spots, cfg)  # ... then any
    return spots


def _add_spots(spots: list, grid, free: np.ndarray, rotations, near, n: int, cfg: PlaceConfig) -> None:
    """Add up to ``n`` spots of ``free`` (R, nu, nv), nearest ``near`` first, each at least
    ``spot_separation_m`` from those in ``spots``, until there are ``arrival_spots``."""
    cells = np.argwhere(np.any(free, axis=0))
    xy = grid.centres()[cells[:, 0], cells[:, 1]]
    dist = np.linalg.norm(xy - np.asarray(near)[:2], axis=1)
    added = 0
    for k in np.argsort(dist, kind="stable"):
        if len(spots) >= cfg.arrival_spots or added >= n:
            return
        if all(np.linalg.norm(xy[k] - s.xy) >= cfg.spot_separation_m for s in spots):
            i, j = cells[k]
            spots.append(Spot(xy[k].copy(), tuple(R for R, f in zip(rotations, free) if f[i, j]),
                              float(dist[k])))
            added += 1
