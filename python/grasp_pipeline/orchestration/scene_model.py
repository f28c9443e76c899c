"""The perceived scene handed to planning: environment points + object boxes from tracks.

Never the simulator's ground truth: the environment points are one perception frame's
environment label, the boxes are the tracker's smoothed estimates.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..motion.occupancy import OrientedBox


@dataclass
class SceneSnapshot:
    """Obstacles for planning, frozen at one instant."""

    environment_points: np.ndarray
    capture_q: Optional[np.ndarray]
    boxes: list = field(default_factory=list)   # OrientedBox per track
    tids: list = field(default_factory=list)    # tid of each box

    def index_of(self, tid: int) -> Optional[int]:
        return self.tids.index(tid) if tid in self.tids else None


def track_box(track) -> OrientedBox:
    e = track.smoothed
    return OrientedBox(np.asarray(e.center), np.asarray(e.R_box), np.asarray(e.extents))


def snapshot(loop, capture_q: Optional[np.ndarray], exclude_tids=()) -> SceneSnapshot:
    """Environment points of the loop's latest frame and a box per current track.

    ``exclude_tids``: tracks of objects already picked — a NADIR track outlives its object
    by ``nadir_hold_s`` and must not block the next motion as a phantom obstacle."""
    env = loop.latest.result.environment_points() if loop.latest is not None else np.zeros((0, 3))
    env = np.asarray(env, dtype=np.float64)
    tracks = [t for t in loop.tracks() if t.tid not in set(exclude_tids)]
    return SceneSnapshot(env, None if capture_q is None else np.asarray(capture_q, float),
                         [track_box(t) for t in tracks], [t.tid for t in tracks])


def without_fragments(scene: SceneSnapshot, target_tid: int, margin_m: float) -> SceneSnapshot:
    """Drop tracks whose centre lies on the target's footprint (+ ``margin_m``): they are
    pieces of the target seen from another angle (a partly occluded view starts a track of
    its own), not neighbours — real objects cannot stand inside each other."""
    k = scene.index_of(target_tid)
    if k is None:
        return scene
    t = scene.boxes[k]
    reach = 0.5 * float(np.hypot(t.extents[0], t.extents[1])) + margin_m
    keep = [i for i, b in enumerate(scene.boxes)
            if i == k or float(np.linalg.norm(b.center[:2] - t.center[:2])) > reach]
    return SceneSnapshot(scene.environment_points, scene.capture_q,
                         [scene.boxes[i] for i in keep], [scene.tids[i] for i in keep])
