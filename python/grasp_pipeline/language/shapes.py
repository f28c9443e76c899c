"""Shape words from a perceived object: box, cylinder (also "can"), mug, bottle or other.

Input: the object's box (centre, ``R_box`` = [closing direction, its perpendicular, table
normal], extents = (width, perp_width, height); method.md §2.4) and the world points seen of it
over the frames. In the box frame the points give a top-view **height map** (the highest
point in each ``shape_cell_m`` cell) and a **footprint** (their convex hull on the table):

* ``fill`` — footprint area / its bounding rectangle: a rectangle fills 1, a disc π/4;
* ``top_fraction`` — share of the footprint's cells whose highest point is within
  ``shape_top_band_m`` of the top: ≈ 1 for a flat top, small for a bottle (only its neck
  reaches the top) or a mug (only its rim);
* ``corner`` — how far the footprint's points reach beyond the ellipse inscribed in their
  bounding rectangle (≈ 1 for a disc, up to √2 at a rectangle's corners);
* ``centre_drop`` — how far below the top the centre cells' highest points lie, as a share
  of the height (cells never seen count as fully hollow): ≈ 0 for anything solid, large for
  an open container (mug, bowl).

Rules, in order: hollow (``centre_drop ≥ shape_hollow_drop_min``) → **mug** when it stands
tall (height ≥ ``shape_mug_height_ratio_min`` × narrow width; a bowl is "other"); a round
footprint, a top that is mostly below the top band and a height ≥
``shape_bottle_height_ratio_min`` × width → **bottle**; a flat top with a rectangular
footprint (fill ≥ ``shape_rect_fill_min``) → **box**, with a round one (fill ≤
``shape_round_fill_max``, corner ≤ ``shape_round_corner_max``, width/perp ≥
``shape_round_aspect_min``) → **cylinder**; anything else → **other**.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from .config import LanguageConfig


@dataclass(frozen=True)
class ShapeFeatures:
    """The measurements the shape rules use (see the module doc)."""

    fill: float
    top_fraction: float
    centre_drop: float
    aspect: float          # narrow / wide footprint span
    corner: float          # 98th percentile of the footprint points' ellipse radius
    height_ratio: float    # height / narrow footprint span


def _local(points: np.ndarray, center, R_box) -> np.ndarray:
    return (np.asarray(points, float) - np.asarray(center, float)) @ np.asarray(R_box, float)


def _fill(xy: np.ndarray, spans: np.ndarray) -> float:
    if len(xy) < 3 or spans.min() <= 0:
        return float("nan")
    try:
        return float(ConvexHull(xy).volume / (spans[0] * spans[1]))  # 2-D "volume" = area
    except QhullError:
        return float("nan")


def _corner(xy: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """How far the footprint reaches beyond the ellipse inscribed in its bounding rectangle:
    the 98th percentile of ``sqrt((x/a)² + (y/b)²)`` (≈ 1 for a disc, up to √2 for a
    rectangle's corners)."""
    half = np.maximum((hi - lo) / 2, 1e-9)
    r = np.linalg.norm((xy - (lo + hi) / 2) / half, axis=1)
    return float(np.quantile(r, 0.98))


def _height_map(local: np.ndarray, cell_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(cell centres (K, 2), highest z per cell (K,)) of the occupied cells."""
    keys = np.floor(local[:, :2] / cell_m).astype(np.int64)
    uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
    top = np.full(len(uniq), -np.inf)
    np.maximum.at(top, inverse.ravel(), local[:, 2])
    return (uniq + 0.5) * cell_m, top


def shape_features(points: np.ndarray, center, R_box, extents,
                   config: LanguageConfig | None = None) -> ShapeFeatures:
    """The measurements of one object (``points``: (N, 3) world points seen of it; those
    outside its box's footprint, e.g. of a neighbour merged with it in some frame, are
    left out). The top is the 98th percentile of the cells' highest points."""
    cfg = config or LanguageConfig()
    width, perp, height = (float(e) for e in extents[:3])
    local = _local(points, center, R_box)
    half = np.array([width, perp]) / 2 + cfg.shape_cell_m
    local = local[np.all(np.abs(local[:, :2]) <= half, axis=1)]
    narrow = min(width, perp)
    if len(local) < 3 or height <= 0 or narrow <= 0:
        nan = float("nan")
        return ShapeFeatures(nan, nan, nan, nan, nan, nan)
    cells, top = _height_map(local, cfg.shape_cell_m)
    top_z = float(np.quantile(top, 0.98))
    top_fraction = float(np.mean(top >= top_z - cfg.shape_top_band_m))
    # the centre region: a disc of 30 % of the narrow half-width around the box centre
    central = np.linalg.norm(cells, axis=1) <= 0.3 * narrow / 2 + cfg.shape_cell_m / 2
    drop = 1.0 if not central.any() else \
        float(np.clip((top_z - np.median(top[central])) / height, 0.0, 1.0))
    lo, hi = local[:, :2].min(axis=0), local[:, :2].max(axis=0)
    spans = hi - lo
    return ShapeFeatures(fill=_fill(local[:, :2], spans),
                         top_fraction=top_fraction, centre_drop=drop,
                         aspect=narrow / max(width, perp), height_ratio=height / narrow,
                         corner=_corner(local[:, :2], lo, hi))


def classify(f: ShapeFeatures, config: LanguageConfig | None = None) -> str:
    """The shape word of measured features (rules in the module doc)."""
    cfg = config or LanguageConfig()
    if not np.isfinite(f.fill):
        return "other"
    round_ = (f.fill <= cfg.shape_round_fill_max and f.corner <= cfg.shape_round_corner_max
              and f.aspect >= cfg.shape_round_aspect_min)
    if f.centre_drop >= cfg.shape_hollow_drop_min:
        return "mug" if f.height_ratio >= cfg.shape_mug_height_ratio_min else "other"
    if round_ and f.top_fraction < cfg.shape_bottle_top_max \
            and f.height_ratio >= cfg.shape_bottle_height_ratio_min:
        return "bottle"
    if f.top_fraction >= cfg.shape_flat_top_min:
        if f.fill >= cfg.shape_rect_fill_min:
            return "box"
        if round_:
            return "cylinder"
    return "other"


def shape_word(points: np.ndarray, center, R_box, extents,
               config: LanguageConfig | None = None) -> str:
    """box, cylinder, mug, bottle or other for one perceived object."""
    return classify(shape_features(points, center, R_box, extents, config), config)
