"""What carries an object (ours): the support rule that extends method.md §2.6's "resting" guard.

method.md §2.6 refuses an object whose lowest *visible* point is more than ``band + resting_margin``
above the table ("floating/stacked"). In clutter that refuses graspable objects: a cup or
bottle whose lower part is hidden behind its neighbours shows only its rim or shoulder, and an
object lying on another one in a pile is not floating. The rule here (written in words in
docs/method.md §2.8, next to method.md §2.6) decides on the perceived points of the scene
(:class:`~.scene_cloud.SceneCloud`):

1. An object method.md §2.6 finds resting stays resting.
2. **Floating** means that the space under the object is seen empty: in at least
   ``see_through_fraction`` of its footprint cells (the grid cells holding its own points,
   shrunk by one cell so that edges do not count) the camera sees a surface (table or another
   object) lower than the object's lowest point by more than ``support_gap_m``. An object
   seen through from above cannot be standing on anything there.
3. Otherwise the object is **supported** when something perceived is under it: points of
   another object whose top lies within ``support_gap_m`` of the object's lowest point, under
   its footprint grown by ``support_ring_m`` ("resting on #k"), or the table (environment
   points) around that footprint with the column below the object hidden from the camera
   ("stands on the table, its lower part hidden").
4. Nothing perceived under or around it (no table, no object): floating.

A supported object is graspable when its other guards pass (height, width); whether its
approach is free is the grasp fitting's and the planner's question (:mod:`.fit`).
Without points of the object in the cloud the method.md §2.6 verdict stands.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ..config import GraspFitConfig
from ..scene.scene_cloud import ENVIRONMENT, SceneCloud

FLOATING_PREFIX = "floating/stacked"


@dataclass(frozen=True)
class SupportVerdict:
    """``supported``; ``why``: a sentence for logs and refusals; ``support_tid``: the track of
    the object it rests on (None: the table or unknown)."""

    supported: bool
    why: str
    support_tid: Optional[int] = None


def _grid(points_xy: np.ndarray, origin: np.ndarray, cell_m: float, shape) -> tuple[np.ndarray, np.ndarray]:
    """(cell indices (N, 2), inside mask (N,)) of points on a grid at ``origin``."""
    ij = np.floor((points_xy - origin) / cell_m).astype(np.int64)
    inside = np.all((ij >= 0) & (ij < np.asarray(shape)), axis=1)
    return ij, inside


def _mask(ij: np.ndarray, inside: np.ndarray, shape) -> np.ndarray:
    m = np.zeros(shape, dtype=bool)
    m[ij[inside, 0], ij[inside, 1]] = True
    return m


def _shift_and(m: np.ndarray) -> np.ndarray:
    """Cells whose four neighbours are set too (one cell of erosion); ``m`` if that empties it."""
    p = np.pad(m, 1)
    inner = m & p[2:, 1:-1] & p[:-2, 1:-1] & p[1:-1, 2:] & p[1:-1, :-2]
    return inner if inner.any() else m


def _dilate(m: np.ndarray, k: int) -> np.ndarray:
    out = m.copy()
    for _ in range(k):
        p = np.pad(out, 1)
        out = out | p[2:, 1:-1] | p[:-2, 1:-1] | p[1:-1, 2:] | p[1:-1, :-2] | \
            p[2:, 2:] | p[:-2, :-2] | p[2:, :-2] | p[:-2, 2:]
    return out


def support_verdict(tid: int, cloud: SceneCloud, config: GraspFitConfig) -> Optional[SupportVerdict]:
    """The rule of the module doc for track ``tid``; None when the cloud has no point of it."""
    own = cloud.owner == tid
    if not np.any(own):
        return None
    cell = config.footprint_cell_m
    k = int(np.ceil(config.support_ring_m / cell))
    origin = cloud.points[own, :2].min(axis=0) - (k + 1) * cell
    shape = tuple(np.floor((cloud.points[own, :2].max(axis=0) - origin) / cell).astype(int) + k + 2)
    ij, inside = _grid(cloud.points[:, :2], origin, cell, shape)
    h = cloud.heights_m()
    bottom = float(h[own].min())
    foot = _mask(ij, inside & own, shape)
    inner = _shift_and(foot)
    others = inside & ~own
    below = _mask(ij, others & (h < bottom - config.support_gap_m), shape) & inner
    if below.sum() >= config.see_through_fraction * inner.sum():
        return SupportVerdict(False, f"floating: lower surfaces seen under {int(below.sum())} of its "
                                     f"{int(inner.sum())} footprint cells, more than "
                                     f"{config.support_gap_m * 1e3:.0f} mm below its lowest point "
                                     f"({bottom * 1e3:.0f} mm above the table)")
    ring = _dilate(foot, k)
    in_ring = np.zeros(len(h), dtype=bool)
    in_ring[others] = ring[ij[others, 0], ij[others, 1]]
    carrying = in_ring & (np.abs(h - bottom) <= config.support_gap_m) & (cloud.owner != ENVIRONMENT)
    if np.any(carrying):
        tids, counts = np.unique(cloud.owner[carrying], return_counts=True)
        t = int(tids[int(np.argmax(counts))])
        return SupportVerdict(True, f"resting on object #{t} (its top within "
                                    f"{config.support_gap_m * 1e3:.0f} mm of this one's lowest point)",
                              t if t >= 0 else None)
    if np.any(in_ring & (cloud.owner == ENVIRONMENT) & (h <= cloud.band_m)):
        return SupportVerdict(True, "stands on the table, its lower part hidden from the camera")
    return SupportVerdict(False, f"floating: nothing perceived under it (lowest point "
                                 f"{bottom * 1e3:.0f} mm above the table)")


def judge_graspable(track, cloud: Optional[SceneCloud], config: GraspFitConfig) -> tuple[bool, list[str]]:
    """(graspable, notes): method.md §2.6's guards with its resting guard replaced by the support
    rule where the cloud allows (see the module doc). Notes explain a refusal."""
    e = track.smoothed
    notes = list(e.notes)
    if e.grasp_ok:
        return True, []
    if e.resting or not (e.height_ok and e.width_ok):
        return False, notes
    return _by_support(track, cloud, config, notes)


WIDTH_NOTE_PREFIX = "width not graspable"


def judge_any_side(track, scene_cloud: Callable[[], Optional[SceneCloud]],
                   config: GraspFitConfig) -> tuple[bool, list[str]]:
    """(graspable, notes) for a grasp source that may approach from any side: method.md §2.6's
    guards without the width guard (whether the hand fits the object from some side is the
    source's question), with the support rule where the cloud allows. ``scene_cloud()`` gives
    the latest scene cloud (None: none); it is asked for only when the support rule judges (a
    pass over the whole frame: a resting or too-low track is settled without it)."""
    e = track.smoothed
    notes = [n for n in e.notes if not n.startswith(WIDTH_NOTE_PREFIX)]
    if not e.height_ok:
        return False, notes
    if e.resting:
        return True, []
    return _by_support(track, scene_cloud(), config, notes)


def _by_support(track, cloud: Optional[SceneCloud], config: GraspFitConfig,
                notes: list[str]) -> tuple[bool, list[str]]:
    """The support rule's verdict on a track the resting guard refused (no cloud or no verdict:
    refused with ``notes``; refused by the rule: its reason first, the floating notes dropped)."""
    verdict = None if cloud is None else support_verdict(int(track.tid), cloud, config)
    if verdict is None:
        return False, notes
    if verdict.supported:
        return True, []
    return False, [verdict.why] + [n for n in notes if not n.startswith(FLOATING_PREFIX)]
