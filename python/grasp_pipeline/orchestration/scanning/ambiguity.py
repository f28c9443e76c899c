"""Segments the active scan should look at more closely before deciding (ours).

A segment is *ambiguous* when its footprint could be more than one object or one the grasp
cannot take as it is seen:

- **wide**: its box is wider than the gripper's usable opening in every horizontal direction
  (two neighbours merged into one cluster look like this, and so does one large object);
- **non-convex**: its points' top-view outline fills less than ``min_solidity`` of its convex
  hull (two objects meeting at a corner, an L-shaped block, a mug's handle). Not a default
  rule: seen from closer, single non-convex objects split (a mug's handle from its body, an
  L into its arms) and the later picks suffered (measured in the grasp-fit scene test).

:func:`ambiguity` says which (or None). The scan then lowers the camera above the segment
(:mod:`.scan`): nearer, a gap of a few millimetres spans more pixels and the depth noise is
smaller, so the segmentation of that view decides.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..config import ScanConfig


def outline_solidity(points_xy: np.ndarray, cell_m: float) -> Optional[float]:
    """Occupied area / convex-hull area of ``points_xy`` (N, 2) [m] on a ``cell_m`` grid
    (each occupied cell counts whole, against the hull of the cells' corners, so that a
    filled rectangle scores 1). None with fewer than 3 distinct cells."""
    cells = np.unique(np.floor(np.asarray(points_xy, float) / cell_m).astype(np.int64), axis=0)
    if len(cells) < 3:
        return None
    corners = (cells[:, None, :] + np.array([[0, 0], [0, 1], [1, 0], [1, 1]])[None]).reshape(-1, 2)
    try:
        hull_cells = ConvexHull(corners.astype(float)).volume  # 2-D: area, in cells
    except QhullError:  # all cells in one row: a line is convex
        return 1.0
    return float(len(cells) / hull_cells) if hull_cells > 0 else None


def ambiguity(track, points: Optional[np.ndarray], max_width_m: float,
              config: ScanConfig) -> Optional[str]:
    """Why the segment of ``track`` needs a closer look (``"wide: ..."``, ``"non-convex: ..."``)
    or None. ``points``: the track's points (N, 3) world [m] (None/empty: only the box rule);
    ``max_width_m``: the widest object the gripper takes; only the rules named in
    ``config.closer_look_rules`` apply."""
    ext = np.asarray(track.smoothed.extents, float)
    narrow = float(min(ext[0], ext[1]))
    if "wide" in config.closer_look_rules and narrow > max_width_m:
        return (f"wide: footprint {1e3 * ext[0]:.0f} x {1e3 * ext[1]:.0f} mm, wider than the "
                f"gripper's {1e3 * max_width_m:.0f} mm in every direction")
    if ("non_convex" not in config.closer_look_rules or points is None
            or len(points) < config.closer_look_min_points):
        return None
    solidity = outline_solidity(np.asarray(points, float)[:, :2], config.closer_look_cell_m)
    if solidity is not None and solidity < config.closer_look_min_solidity:
        return (f"non-convex: outline fills {100 * solidity:.0f} % of its hull "
                f"(< {100 * config.closer_look_min_solidity:.0f} %)")
    return None
