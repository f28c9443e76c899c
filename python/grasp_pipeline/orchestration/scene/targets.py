"""Which perceived objects to pick when the user names none (ours).

Every track over the table top (not over or near the tray: placed objects, its rim) that was
seen in the rough view or measured from above and passes its grasp checks — nearest to the
robot base first. Each track left out is listed with the reason (a piece of the tray's rim is
too wide; a glimpse of the far table from a probe pose was never measured from above).
"""

from __future__ import annotations

import numpy as np

from ... import _core
from ...motion.work_cell import WorkCell


def _skip_reason(track, cell: WorkCell, fixture_margin_m: float, rough_tids: set,
                 judge=None) -> str | None:
    c = np.asarray(track.smoothed.center[:2], float)
    note = cell.pick_target_note(c, fixture_margin_m)
    if note is None and track.tid not in rough_tids and track.quality != _core.ViewQuality.NADIR:
        note = (f"#{track.tid} was first seen during the scan ({track.quality.name.lower()} view) "
                "and never measured from above")
    if note is None:
        ok, notes = judge(track) if judge is not None else (track.smoothed.grasp_ok, track.smoothed.notes)
        note = None if ok else ("; ".join(notes) or "grasp checks failed")
    return note


def rough_view_ids(rough_centers: dict[int, tuple[float, float]], tracks,
                   takeover_m: float) -> set[int]:
    """The ids that count as "seen in the rough view" after the scan.

    ``rough_centers``: track id -> (x, y) [m] of the rough view's tracks. A track born later
    whose centre lies within ``takeover_m`` of a rough track that no longer exists took that
    track's place (the tracker lost the object during the scan, e.g. half in view at a
    neighbour's probe, and found it again under a new id): it is the same object and counts
    as seen in the rough view."""
    alive = {int(t.tid) for t in tracks}
    ids = set(rough_centers) & alive
    gone = [np.asarray(c, float) for tid, c in rough_centers.items() if tid not in alive]
    for t in tracks:
        c = np.asarray(t.smoothed.center[:2], float)
        if int(t.tid) not in rough_centers and any(np.hypot(*(c - g)) <= takeover_m for g in gone):
            ids.add(int(t.tid))
    return ids


def default_targets(tracks, cell: WorkCell, fixture_margin_m: float,
                    rough_tids: set, judge=None) -> tuple[list[tuple[float, float]], list[dict]]:
    """(targets (x, y) nearest the base first, skipped tracks with ``tid``/``center``/``why``).

    ``rough_tids``: the tracks of the rough view (the objects the scan set out to measure);
    ``judge(track) -> (graspable, notes)``: the grasp guards (default: method.md §2.6's)."""
    targets, skipped = [], []
    for t in tracks:
        c = np.asarray(t.smoothed.center[:2], float)
        note = _skip_reason(t, cell, fixture_margin_m, rough_tids, judge)
        if note is None:
            targets.append(c)
        else:
            skipped.append({"tid": int(t.tid), "center": [float(c[0]), float(c[1])], "why": note})
    targets.sort(key=lambda c: float(np.hypot(*c)))
    return [(float(c[0]), float(c[1])) for c in targets], skipped
