"""What happened to each object of a clutter round, beside its geometric bound (evaluation only).

:class:`ObjectOutcomeRecorder` subscribes to the run's events: at the rough view
(``StageEvent("rough_view_done")``, the objects settled, the arm not yet moved) it labels
every object (:mod:`.grasp_bound`); at every look it notes where the objects are; after every
attempt (:class:`~grasp_pipeline.orchestration.events.PickEvent`) which object the attempt was
on and the robot's tracks. After the round, :meth:`~ObjectOutcomeRecorder.rows` gives each
object its outcome (:func:`assign_outcomes`, the first that applies):

* ``picked``: an attempt on it ended with it in the tray;
* ``attempted_failed``: attempted, never picked (stage and reason of its last failed attempt);
* ``displaced``: never attempted, yet off the table at the end (pushed off, carried along);
* ``never_proposed``: the robot's last look skipped the track on it (``why``: the skip's reason —
  the grasp guards, the grasp source proposing nothing, ...);
* ``round_ended``: the round ended on failures or the attempt limit while a track of the last
  look still lay on it (a target not tried yet);
* ``merged``: no track of its own in the last look, but its centre lay inside the box of a
  track on another object (segmentation merged them, or it lay hidden under that one);
* ``round_error``: the round raised before anything above happened to it;
* ``not_seen``: no track of the last look lay on it.

Matching: an attempt is on the object the :class:`~.pick_evaluator.PickEvaluator` followed, or
(an attempt that never started its grasp) the object under its anchor; a track lies on the true
object whose footprint (the convex hull of its collision parts seen from above, where it was at
the look) is nearest its centre, within ``match_distance_m`` (ties: the nearest centre).
:func:`summarize` pools the rows of many rounds (pure).
"""

from __future__ import annotations

import re
from typing import Iterable, Optional

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ..orchestration.declutter import END_ATTEMPTS, END_FAILURES
from ..orchestration.events import EventBus, PickEvent, StageEvent
from ..sim.ground_truth import object_truths
from .config import GraspBoundConfig
from .grasp_bound import CLASSES, LABELS, bounds_of_spec, bounds_of_world, object_shape

#: The outcomes, in the order they are decided.
OUTCOMES = ("picked", "attempted_failed", "displaced", "never_proposed", "round_ended", "merged",
            "round_error", "not_seen")
#: How many never-proposed / failure reasons the summary lists.
TOP_REASONS = 10


# ------------------------------------------------------------------------------ matching


def footprint(vertices: np.ndarray) -> np.ndarray:
    """The (k, 2) convex outline (counter-clockwise) of points seen from above."""
    xy = np.asarray(vertices, float)[:, :2]
    try:
        return xy[ConvexHull(xy).vertices]
    except (QhullError, ValueError):  # a degenerate outline: its points
        return np.unique(xy, axis=0)


def polygon_distance_m(polygon: np.ndarray, p) -> float:
    """Distance [m] from ``p`` (x, y) to a counter-clockwise convex polygon (0 inside)."""
    p = np.asarray(p, float)[:2]
    a = np.asarray(polygon, float)
    if len(a) == 1:
        return float(np.hypot(*(p - a[0])))
    ab, ap = np.roll(a, -1, axis=0) - a, p - a
    if len(a) >= 3 and np.all(ab[:, 0] * ap[:, 1] - ab[:, 1] * ap[:, 0] >= 0.0):
        return 0.0
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-18), 0, 1)
    return float(np.min(np.linalg.norm(ap - t[:, None] * ab, axis=1)))


def in_track_box(xy, track) -> bool:
    """True when ``xy`` lies inside the footprint of ``track``'s box (``R_box`` columns: closing
    direction, its perpendicular, the table's normal; ``extents`` along them)."""
    e = track.smoothed
    local = (np.asarray(xy, float)[:2] - np.asarray(e.center, float)[:2]) @ np.asarray(e.R_box, float)[:2, :2]
    return bool(np.all(np.abs(local) <= 0.5 * np.asarray(e.extents, float)[:2]))


def nearest_object(xy, outlines: dict, centres: dict, limit_m: float) -> Optional[str]:
    """The object whose outline is nearest ``xy`` (ties: the nearest centre), None beyond
    ``limit_m``."""
    best = None
    for name, poly in outlines.items():
        key = (polygon_distance_m(poly, xy), float(np.hypot(*(np.asarray(centres[name])[:2] - np.asarray(xy)[:2]))))
        if best is None or key < best[0]:
            best = (key, name)
    return None if best is None or best[0][0] > limit_m else best[1]


# ------------------------------------------------------------------------------ outcomes


def _failed_outcome(tried: list) -> dict:
    last = tried[-1]
    return {"outcome": "attempted_failed", "stage": last.get("stage"), "reason": last.get("reason")}


def assign_outcomes(names: Iterable[str], attempts: list, skipped: list, last_look: set,
                    ended_early: bool, errored: bool, off_table: set, inside_tracks: set = frozenset()) -> dict:
    """{name: {"outcome", "attempts", and "stage"/"reason" or "why" where they apply}}.

    ``attempts``: the round's attempts in order, each ``{"object", "success", "stage",
    "reason"}`` (``object``: the true object or None); ``skipped``: the last look's skipped
    tracks, ``{"object", "why"}``; ``last_look``: the objects a track of the last look lay
    on; ``ended_early``: the round ended on failures or the attempt limit; ``errored``: it
    raised; ``off_table``: the objects not on the table at the end; ``inside_tracks``: the
    objects whose centre lay inside the box of a track of the last look."""
    out = {}
    for name in names:
        tried = [a for a in attempts if a.get("object") == name]
        whys = [s["why"] for s in skipped if s.get("object") == name]
        if any(a.get("success") for a in tried):
            row = {"outcome": "picked"}
        elif tried:
            row = _failed_outcome(tried)
        elif name in off_table:
            row = {"outcome": "displaced"}
        elif whys:
            row = {"outcome": "never_proposed", "why": " | ".join(dict.fromkeys(whys))}
        elif ended_early and name in last_look:
            row = {"outcome": "round_ended"}
        elif name in inside_tracks and name not in last_look:
            row = {"outcome": "merged"}
        elif errored:
            row = {"outcome": "round_error"}
        else:
            row = {"outcome": "not_seen"}
        out[name] = {**row, "attempts": len(tried)}
    return out


def object_rows(bounds: dict, outcomes: dict, models: dict) -> list:
    """One row per object: name, model, its bound (:meth:`~.grasp_bound.GraspBound.to_dict`)
    and its outcome."""
    return [{"name": name, "model": models.get(name), **bounds[name].to_dict(), **outcomes[name]}
            for name in bounds]


def rows_without_run(spec, config: GraspBoundConfig, models: dict, error: Optional[str]) -> list:
    """The rows of a round that never ran its pipeline (its process died, or it raised before
    the rough view): the bounds where the scene placed the objects, nothing attempted."""
    bounds = bounds_of_spec(spec, config)
    outcomes = assign_outcomes(bounds, [], [], set(), False, bool(error), set())
    return object_rows(bounds, outcomes, models)


def _ended_early(end_reason: str) -> bool:
    return str(end_reason or "").startswith((END_FAILURES, END_ATTEMPTS))


class ObjectOutcomeRecorder:
    """Subscribe with :meth:`attach` (after the pick evaluator); :meth:`rows` after the round.

    ``on_table(world) -> set of names``: the objects still on the table (ground truth)."""

    def __init__(self, world, loop, config: GraspBoundConfig, on_table) -> None:
        self.world, self.loop, self.config, self.on_table = world, loop, config, on_table
        self.shapes = {o.name: object_shape(o) for o in world.scene.objects}
        self.bounds: Optional[dict] = None
        self.outlines: dict = {}
        self.centres: dict = {}
        self.attempt_objects: list = []

    def attach(self, events: EventBus) -> "ObjectOutcomeRecorder":
        events.subscribe(StageEvent, self.on_stage)
        events.subscribe(PickEvent, self.on_pick)
        return self

    def on_stage(self, ev: StageEvent) -> None:
        if ev.name == "rough_view_done" and self.bounds is None:
            self.bounds = bounds_of_world(self.world, self.config, self.shapes)
            self._note_places()
        elif ev.name == "look_again":
            self._note_places()

    def _note_places(self) -> None:
        """Where the objects are at this look (outlines seen from above, centres)."""
        truths = object_truths(self.world)
        self.outlines = {t.name: footprint(self.shapes[t.name].posed(t.T_world_object).vertices) for t in truths}
        self.centres = {t.name: t.position_m for t in truths}

    def match(self, xy) -> Optional[str]:
        if not self.outlines:
            self._note_places()
        return nearest_object(xy, self.outlines, self.centres, self.config.match_distance_m)

    def on_pick(self, ev: PickEvent) -> None:
        row = ev.result
        self.attempt_objects.append(row.object or (self.match(row.anchor) if row.anchor else None))

    def rows(self, attempts: list, skipped: list, end_reason: str, error: Optional[str],
             models: dict) -> list:
        """The objects' rows (:func:`object_rows`); ``attempts``: the benchmark's attempt rows
        (``success``, ``stage``, ``reason``) in order; ``skipped``: the run report's
        ``targets_skipped``; ``end_reason``: the robot's own. The robot's tracks now are those of
        its last look (a round ends right after a look, or right after an attempt)."""
        bounds = self.bounds if self.bounds is not None else bounds_of_world(self.world, self.config, self.shapes)
        names = self.attempt_objects + [None] * max(0, len(attempts) - len(self.attempt_objects))
        tried = [{**a, "object": n} for a, n in zip(attempts, names)]
        skips = [{"object": self.match(s["center"]), "why": s.get("why", "")} for s in skipped or []]
        tracks = list(self.loop.tracks())
        last_look = {self.match(t.smoothed.center) for t in tracks} - {None}
        inside = {n for n, c in self.centres.items() if any(in_track_box(c, t) for t in tracks)}
        off = set(bounds) - set(self.on_table(self.world))
        outcomes = assign_outcomes(bounds, tried, skips, last_look, _ended_early(end_reason), bool(error), off,
                                   inside)
        return object_rows(bounds, outcomes, models)


# ------------------------------------------------------------------------------ summary


def _fraction(num: int, den: int) -> Optional[float]:
    return None if den == 0 else round(num / den, 4)


def why_category(why: str, max_len: int = 240) -> str:
    """A skip reason without its numbers and track ids, so that one cause counts once."""
    text = re.sub(r"\(\s*[-+\d.eE]+\s*,\s*[-+\d.eE]+\s*\)\s*", "", str(why or ""))  # (x, y)
    text = re.sub(r"#\d+", "#", text)
    text = re.sub(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", "N", text)
    text = re.sub(r"\s+", " ", text).strip(" ,;.:")
    return (text[:max_len].rstrip() + "…" if len(text) > max_len else text) or "unspecified"


def _top(values: Iterable[str]) -> dict:
    counts: dict = {}
    for v in values:
        counts[v] = counts.get(v, 0) + 1
    return dict(sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))[:TOP_REASONS])


def _graspable(objects: list, key: str) -> dict:
    """Per class, the objects graspable under it (the classes are nested)."""
    return {c: [o for o in objects if o.get(key) in LABELS[: i + 1]] for i, c in enumerate(CLASSES)}


def summarize(objects: list) -> dict:
    """The benchmark's view of many rounds' object rows: label counts, the declutter rate
    against each bound (objects picked among those graspable under it / those graspable),
    outcomes per label, the most common never-proposed and failure reasons."""
    n = len(objects)
    picked = lambda group: sum(o.get("outcome") == "picked" for o in group)  # noqa: E731
    g, g_alone = _graspable(objects, "label"), _graspable(objects, "label_width_only")
    out = {"objects": n, "labels": {lb: sum(o.get("label") == lb for o in objects) for lb in LABELS},
           "graspable": {c: len(v) for c, v in g.items()},
           "graspable_fraction": {c: _fraction(len(v), n) for c, v in g.items()},
           "graspable_width_only": {c: len(v) for c, v in g_alone.items()},
           "graspable_width_only_fraction": {c: _fraction(len(v), n) for c, v in g_alone.items()},
           "picked": picked(objects)}
    for c, group in g.items():
        out[f"dr_{c}"] = _fraction(picked(group), len(group))
    out["dr_width_only"] = {c: _fraction(picked(group), len(group)) for c, group in g_alone.items()}
    out["picked_outside_bound"] = sum(o.get("outcome") == "picked" and o.get("label") == "none" for o in objects)
    out["outcomes"] = {k: sum(o.get("outcome") == k for o in objects) for k in OUTCOMES}
    out["label_by_outcome"] = {lb: {k: sum(o.get("label") == lb and o.get("outcome") == k for o in objects)
                                    for k in OUTCOMES} for lb in LABELS}
    out["never_proposed_reasons"] = _top(why_category(w) for o in objects if o.get("outcome") == "never_proposed"
                                         for w in str(o.get("why") or "").split(" | "))
    out["attempted_failed_reasons"] = _top(f"{o.get('stage')}: {o.get('reason')}" for o in objects
                                           if o.get("outcome") == "attempted_failed")
    return out
