"""The perceived scene handed to planning, built from the perception loop.

Never the simulator's ground truth: the environment points are one perception frame's
environment label, the boxes are the tracker's smoothed estimates.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from ...motion.perceived_scene import PerceivedScene
from .tracks import track_box


def snapshot(loop, exclude_tids=()) -> PerceivedScene:
    """Environment points of the loop's latest frame, a box per current track and the track's
    points in that frame (its scene cloud).

    ``exclude_tids``: tracks of objects already picked — a NADIR track outlives its object
    by ``nadir_hold_s`` and must not block the next motion as a phantom obstacle."""
    latest = loop.latest
    env = latest.result.environment_points() if latest is not None else np.zeros((0, 3))
    excluded = set(exclude_tids)
    tracks = [t for t in loop.tracks() if t.tid not in excluded]
    q: Optional[np.ndarray] = None if latest is None or latest.q is None else np.asarray(latest.q, float)
    cloud = loop.scene_cloud()
    points = [np.zeros((0, 3)) if cloud is None else cloud.of(int(t.tid)) for t in tracks]
    return PerceivedScene(np.asarray(env, dtype=np.float64), [track_box(t) for t in tracks],
                          [int(t.tid) for t in tracks], q,
                          None if latest is None else np.asarray(latest.T_world_camera, float),
                          loop.plane, points, float(loop.band_m))
