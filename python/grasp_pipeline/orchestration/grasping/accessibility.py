"""Which object of a cluttered table is easiest to reach (ours): free space for the fingers.

A top-down grasp closes along one horizontal axis; the two fingers come down just outside
the object on that axis. :func:`accessibility_m` measures, on the table plane, the free space
around those two finger footprints: the smallest distance from either footprint (a rectangle
``finger_thickness_m`` × ``finger_width_m``, placed ``open_margin_m / 2`` outside the object's
box along the closing axis) to any *other* object's box footprint — negative when they
overlap — for the preferred closing axis and, when the fingers open the whole margin around it
(``max_width_m``: :func:`~.opening.full_margin_width_m`), the perpendicular one;
the better of the two counts. Picking the most accessible object first frees its neighbours
(VGN-style declutter order is by grasp quality; ours is by this clearance).
"""

from __future__ import annotations

import numpy as np

from ...robot.description import HandClearances


def _rect(center: np.ndarray, axis: np.ndarray, half_along: float, half_across: float) -> np.ndarray:
    """(4, 2) corners of a rectangle with ``axis`` (unit, 2-D) and half extents."""
    perp = np.array([-axis[1], axis[0]])
    return np.array([center + sa * half_along * axis + sb * half_across * perp
                     for sa, sb in ((1, 1), (1, -1), (-1, -1), (-1, 1))])


def _overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test of two convex polygons (corner arrays, in order)."""
    for poly in (a, b):
        for k in range(len(poly)):
            edge = poly[(k + 1) % len(poly)] - poly[k]
            n = np.array([-edge[1], edge[0]])
            pa, pb = a @ n, b @ n
            if pa.max() < pb.min() or pb.max() < pa.min():
                return False
    return True


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    t = np.clip(float((p - a) @ ab) / max(float(ab @ ab), 1e-18), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * ab)))


def polygon_distance_m(a: np.ndarray, b: np.ndarray) -> float:
    """Distance between two convex polygons; 0 when they overlap."""
    if _overlap(a, b):
        return 0.0
    d = [_point_segment(p, q[k], q[(k + 1) % len(q)]) for p, q in ((x, b) for x in a) for k in range(len(q))]
    d += [_point_segment(p, q[k], q[(k + 1) % len(q)]) for p, q in ((x, a) for x in b) for k in range(len(q))]
    return min(d)


def box_footprint(center, R, extents) -> np.ndarray:
    """(4, 2) footprint corners of an upright oriented box (world x, y)."""
    R = np.asarray(R, dtype=float)
    axis = R[:2, 0] / max(float(np.linalg.norm(R[:2, 0])), 1e-12)
    e = np.asarray(extents, dtype=float)
    return _rect(np.asarray(center, dtype=float)[:2], axis, 0.5 * e[0], 0.5 * e[1])


def _finger_clearance(center, axis, half_width, half_across, neighbours, hand, margin_m) -> float:
    off = half_width + 0.5 * margin_m + 0.5 * hand.finger_thickness_m
    fingers = [_rect(center + s * off * axis, axis, 0.5 * hand.finger_thickness_m,
                     0.5 * hand.finger_width_m) for s in (1.0, -1.0)]
    if not neighbours:
        return float("inf")
    return min(polygon_distance_m(f, nb) for f in fingers for nb in neighbours)


def accessibility_m(target, others, hand: HandClearances, open_margin_m: float,
                    max_width_m: float) -> float:
    """Free space [m] around the fingers of the best top-down grasp of ``target`` among the
    ``others`` (tracks: ``smoothed.center``, ``R_box``, ``extents``); ``inf`` alone."""
    e = target.smoothed
    R = np.asarray(e.R_box, dtype=float)
    ext = np.asarray(e.extents, dtype=float)
    c = np.asarray(e.center, dtype=float)[:2]
    nbs = [box_footprint(o.smoothed.center, o.smoothed.R_box, o.smoothed.extents) for o in others]
    ax = R[:2, 0] / max(float(np.linalg.norm(R[:2, 0])), 1e-12)
    best = _finger_clearance(c, ax, 0.5 * ext[0], 0.5 * ext[1], nbs, hand, open_margin_m)
    if ext[1] <= max_width_m:
        perp = np.array([-ax[1], ax[0]])
        best = max(best, _finger_clearance(c, perp, 0.5 * ext[1], 0.5 * ext[0], nbs, hand, open_margin_m))
    return best


def rank_by_accessibility(targets: list, tracks: list, hand: HandClearances, open_margin_m: float,
                          max_width_m: float, enough_m: float) -> list:
    """``targets`` ((x, y), nearest the base first) reordered by the accessibility of the track
    nearest each, most free space first; clearances beyond ``enough_m`` count as equal (a
    stable sort: those keep the nearest-first order)."""
    if len(tracks) < 2:
        return list(targets)

    def score(xy) -> float:
        d = [float(np.hypot(t.smoothed.center[0] - xy[0], t.smoothed.center[1] - xy[1])) for t in tracks]
        k = int(np.argmin(d))
        return accessibility_m(tracks[k], tracks[:k] + tracks[k + 1:], hand, open_margin_m, max_width_m)

    scores = [min(score(xy), enough_m) for xy in targets]
    order = sorted(range(len(targets)), key=lambda i: -scores[i])
    return [targets[i] for i in order]
