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

from ... import _core
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


def _spot_cells(grid, contents_h: np.ndarray, heights: np.ndarray, inside: np.ndarray,
                shape: HeldShape, R: np.ndarray, axes: np.ndarray, cfg: PlaceConfig,
                rim_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(ok, support), each (nu, nv), for the TCP over each cell's centre with the TCP rotation
    ``R``: whether the object lies inside the walls, rests on the highest thing under its
    spheres (nothing beside it stands higher than what it stands on, give or take
    ``seen_min_height_m``) and the hand clears the walls and contents with the object on it; the
    height of what it stands on (0: the floor).

    The cells come from the object's spheres (grown by ``spot_spacing_m``), the cells under its
    points and the hand's spheres with, per sphere, the highest content allowed under it with
    the object on the floor; the per-cell maxima over them run in the C++ core
    (``_core.tray_spot_cells``)."""
    R = np.asarray(R, float)
    s = cfg.spot_spacing_m
    object_xy = (shape.object_centres @ R.T)[:, :2] @ axes
    under = np.floor((shape.points_tcp @ R.T)[:, :2] @ axes / grid.cell_m + 0.5).astype(np.int64)
    h_tcp = cfg.release_clearance_m + shape.bottom_m(R)
    C = shape.hand_centres @ R.T
    # row by row, as (1, 2) @ (2, 2) products: a batched product may round its sums otherwise,
    # and a cell at the edge of a sphere's reach would change
    hand_xy = np.vstack([c[None, :2] @ axes for c in C]) if len(C) else np.zeros((0, 2))
    hand_r = np.asarray(shape.hand_radii, float)
    return _core.tray_spot_cells(
        np.ascontiguousarray(contents_h, dtype=float), np.ascontiguousarray(heights, dtype=float),
        np.ascontiguousarray(inside, dtype=bool), float(rim_m), float(grid.cell_m),
        np.ascontiguousarray(object_xy, dtype=float), np.ascontiguousarray(shape.object_radii, dtype=float),
        np.ascontiguousarray(under), np.ascontiguousarray(hand_xy, dtype=float),
        np.ascontiguousarray(hand_r), np.ascontiguousarray(h_tcp + C[:, 2] - hand_r - s, dtype=float),
        float(s), float(cfg.seen_min_height_m))


def _free(contents: TrayContents, shape: HeldShape, rotations, cfg: PlaceConfig):
    """(grid, [floor, on the lowest, on the others], each (R, nu, nv)): where the object and
    the hand fit with each rotation — on the floor; on what lies lowest in the tray, then on
    the rest up to ``stack_max_m`` high, for when no floor spot can be reached or none is left."""
    grid = contents.geometry.grid(cfg.spot_cell_m)
    contents_h = contents.heights(grid)
    heights = np.maximum(contents_h, grid.wall_heights)
    axes, rim = contents.geometry.axes, contents.geometry.rim_m
    inside = ~grid.wall_mask()
    res = [_spot_cells(grid, contents_h, heights, inside, shape, R, axes, cfg, rim) for R in rotations]
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
    centres = grid.centres()
    spots: list[Spot] = []
    for free in layers:
        for p in preferred:  # the nearest free spot to each preferred position ...
            _add_spots(spots, centres, free, rotations, p, 1, cfg)
        _add_spots(spots, centres, free, rotations, preferred[0], cfg.arrival_spots, cfg)  # ... then any
    return spots


def _add_spots(spots: list, centres: np.ndarray, free: np.ndarray, rotations, near, n: int,
               cfg: PlaceConfig) -> None:
    """Add up to ``n`` spots of ``free`` (R, nu, nv), nearest ``near`` first, each at least
    ``spot_separation_m`` from those in ``spots``, until there are ``arrival_spots``
    (``centres``: the grid's cell centres, (nu, nv, 2) world xy)."""
    cells = np.argwhere(np.any(free, axis=0))
    xy = centres[cells[:, 0], cells[:, 1]]
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
