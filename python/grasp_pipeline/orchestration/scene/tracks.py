"""Small helpers on the tracker's tracks: nearest by position, box, report summary."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from ...motion.occupancy import OrientedBox
from ...results import TrackSummary


def nearest_track(tracks: Sequence, xy) -> tuple[Optional[object], float]:
    """The track whose smoothed centre is horizontally nearest ``xy`` [m], and its distance
    (``(None, inf)`` without tracks)."""
    best, best_d = None, float("inf")
    x, y = float(xy[0]), float(xy[1])
    for t in tracks:
        d = float(np.hypot(t.smoothed.center[0] - x, t.smoothed.center[1] - y))
        if d < best_d:
            best, best_d = t, d
    return best, best_d


def track_box(track) -> OrientedBox:
    """The track's smoothed estimate as an oriented box."""
    e = track.smoothed
    return OrientedBox(np.asarray(e.center), np.asarray(e.R_box), np.asarray(e.extents))


def track_summary(track) -> TrackSummary:
    e = track.smoothed
    return TrackSummary(tid=int(track.tid), quality=track.quality.name,
                        pca_tilt_deg=float(e.pca_tilt_deg), center=[float(x) for x in e.center],
                        extents=[float(x) for x in e.extents],
                        theta_deg=float(np.degrees(e.theta_rad)), grasp_ok=bool(e.grasp_ok),
                        notes=list(e.notes))
