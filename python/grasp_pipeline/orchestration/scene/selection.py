"""Selecting an object by position and publishing its best grasp every frame (method.md §5).

``Selector.select(x, y, ...)`` anchors a selection *by position, never by tid* (tids are
re-issued after retirement). Refusals, each with a message: nothing seen yet; nearest
track farther than 2 × gate; the nearest track fails its guards; the grasp cannot be
built. The first three keep any previous selection; a construction failure clears it.
After a selection, :meth:`Selector.on_frame` re-resolves the anchor to the nearest track
every frame and publishes a :class:`_core.BestGrasp` only while it passes the same checks;
failures are logged once per reason, not per frame.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from ... import _core
from .tracks import nearest_track

log = logging.getLogger("grasp_pipeline.select")

NO_NOTES_PLACEHOLDER = "object fails its grasp checks (no details available)"


@dataclass(frozen=True)
class SelectResult:
    """Answer of ``select``: accepted or refused, with a message for the user."""

    ok: bool
    message: str
    grasp: Optional["_core.BestGrasp"] = None
    width_m: Optional[float] = None
    tid: Optional[int] = None


@dataclass
class _Check:
    grasp: Optional["_core.BestGrasp"]
    track: Optional["_core.Track"]
    reason: str  # "" when ok
    kind: str = ""  # reason category: nothing / far / guards / construction (log-once key)
    clears: bool = False  # a construction failure clears the selection


#: ``judge(track) -> (graspable, notes)``: the grasp guards of a track (default: method.md §2.6's
#: ``grasp_ok`` and notes; the perception loop's judge adds the support rule, :mod:`.support`).
Judge = Callable[[object], tuple[bool, list]]


def spec_judge(track) -> tuple[bool, list]:
    """method.md §2.6's verdict of the track's smoothed estimate."""
    est = track.smoothed
    return bool(est.grasp_ok), list(est.notes)


def check_selection(x: float, y: float, tracks: Sequence["_core.Track"], gate_m: Optional[float],
                    plane: Optional["_core.Plane"], fallback_limit_m: Optional[float] = None,
                    judge: Optional[Judge] = None) -> _Check:
    """The checks of method.md §5 for a point (x, y), in order.

    The distance limit is 2 × gate; when the gate is undefined (fewer than two objects in
    the last frame) method.md §5 sets no limit — here ``fallback_limit_m`` applies instead (ours:
    a click far from the only object must not select it). ``judge``: the guards (default
    :func:`spec_judge`)."""
    if not tracks or plane is None:
        return _Check(None, None, "nothing seen yet", "nothing")
    track, dist = nearest_track(tracks, (x, y))
    limit = 2.0 * gate_m if gate_m is not None else fallback_limit_m
    if limit is not None and dist > limit:
        return _Check(None, track, f"no object near ({x:.3f}, {y:.3f}): {dist * 1e3:.0f} mm away, "
                                   f"limit {limit * 1e3:.0f} mm", "far")
    est = track.smoothed
    ok, notes = (judge or spec_judge)(track)
    if not ok:
        return _Check(None, track, " | ".join(notes) if notes else NO_NOTES_PLACEHOLDER, "guards")
    grasp = _core.best_grasp_from_estimate(est, plane)
    if grasp is None:
        return _Check(None, track, f"cannot build a top-down grasp for #{track.tid}: degenerate footprint",
                      "construction", clears=True)
    return _Check(grasp, track, "")


def perpendicular_grasp(track, plane, max_width_m: float):
    """The 90°-rotated top-down grasp (closing across the other side), or None.

    A square has two equivalent closing directions (method.md §2.3); for any footprint, when the
    preferred (narrow-side) grasp cannot be planned — a neighbour blocks the hand — closing
    across the other side is the next best grasp (ours). Offered only when that side fits
    the gripper with its opening margin: ``perp_width ≤ max_width_m``."""
    e = track.smoothed
    if e.perp_width_m > max_width_m:
        return None
    Rb = np.asarray(e.R_box)
    n = np.asarray(plane.n)
    R_rot = np.column_stack([Rb[:, 1], -Rb[:, 0], Rb[:, 2]])
    R = _core.top_down_rotation(R_rot, n)
    if R is None:
        return None
    R = np.asarray(R).copy()
    R[:, 0] *= -1.0
    R[:, 2] *= -1.0
    return _core.BestGrasp(R, np.asarray(e.center), float(e.perp_width_m))


@dataclass
class Selector:
    """Holds the anchor and publishes best grasps (method.md §5)."""

    fallback_limit_m: Optional[float] = None  # distance limit while the gate is undefined
    judge: Optional[Judge] = None  # the grasp guards of a track (None: method.md §2.6's)
    anchor: Optional[tuple[float, float]] = None
    best_grasp: Optional["_core.BestGrasp"] = None
    best_grasp_time_s: Optional[float] = None
    published: int = 0
    _warned: set = field(default_factory=set)

    def select(self, x: float, y: float, tracks: Sequence["_core.Track"], gate_m: Optional[float],
               plane: Optional["_core.Plane"]) -> SelectResult:
        """Anchor a selection at (x, y) [m, world]; see the module doc for refusals."""
        if not (np.isfinite(x) and np.isfinite(y)):
            return SelectResult(False, f"select: x and y must be finite numbers, got ({x}, {y})")
        chk = check_selection(x, y, tracks, gate_m, plane, self.fallback_limit_m, self.judge)
        if chk.reason:
            if chk.clears:
                self.clear()
            log.warning("select (%.3f, %.3f) refused: %s", x, y, chk.reason)
            return SelectResult(False, chk.reason, tid=chk.track.tid if chk.track else None)
        self.anchor = (float(x), float(y))
        self._warned.clear()
        self.best_grasp, self.best_grasp_time_s = None, None
        self.published = 0
        g = chk.grasp
        msg = (f"selected #{chk.track.tid} at ({g.position[0]:.3f}, {g.position[1]:.3f}, "
               f"{g.position[2]:.3f}), width {g.width_m * 1e3:.1f} mm")
        log.info("%s", msg)
        return SelectResult(True, msg, grasp=g, width_m=g.width_m, tid=chk.track.tid)

    def clear(self) -> None:
        self.anchor = None
        self.best_grasp, self.best_grasp_time_s = None, None
        self.published = 0
        self._warned.clear()

    def on_frame(self, tracks: Sequence["_core.Track"], gate_m: Optional[float],
                 plane: Optional["_core.Plane"], time_s: float) -> Optional["_core.BestGrasp"]:
        """Re-resolve the anchor; publish (store) the best grasp if it passes the checks."""
        if self.anchor is None:
            return None
        chk = check_selection(self.anchor[0], self.anchor[1], tracks, gate_m, plane,
                              self.fallback_limit_m, self.judge)
        if chk.reason:
            if chk.kind not in self._warned:
                self._warned.add(chk.kind)
                log.warning("best grasp not published: %s", chk.reason)
            return None
        self.best_grasp, self.best_grasp_time_s = chk.grasp, time_s
        self.published += 1
        return chk.grasp
