"""Segmentation quality against per-pixel ground truth — **evaluation code only**.

An object is segmented **correctly** in a frame when one perceived cluster holds its points
with purity ≥ ``min_purity`` (0.90: at most 10 % of that cluster's points belong to something
else) and coverage ≥ ``min_coverage`` (0.80 of the object's visible points). It is
**merged** when its best cluster's purity is below ``min_purity`` (the cluster also holds
another object or the environment), **split** when at least two clusters each hold
≥ ``part_fraction`` of its visible points, **missed** when no cluster holds that much.

"Visible points" are the frame's valid pixels that show the object *and* lie above the
scene filter's band (method.md §1.4: points within ``band`` of the table plane are environment by
definition, whatever the segmentation does), so a flat object is not scored on the slice that
no table-top method can separate from the table.

:class:`ScanSegmentationRecorder` scores the frames of the active scan: on each probe's
arrival it turns the camera's per-pixel labels on for one frame and scores every object in
view; each object keeps the score from the probe frame whose camera stood horizontally
nearest to it (its own probe, usually). A closer look's frame (the scan looks again from
nearer above an ambiguous segment, and that view decides) replaces the score of every object
it sees about as centrally as the object's best frame so far (camera offset within
:data:`CLOSER_LOOK_OFFSET_M` of it). Objects seen in no probe frame count as missed.
"""

from __future__ import annotations

import logging
from dataclasses import asdict, dataclass
from typing import Optional

import numpy as np

from ..array_rows import rows_where
from ..orchestration.events import EventBus, FrameEvent, PerceptionEvent, StageEvent
from ..sim.ground_truth import (NO_OBJECT, FrameLabelsError, enable_frame_labels, frame_labels,
                                object_truths)

log = logging.getLogger("grasp_pipeline.evaluation.segmentation")

MIN_PURITY = 0.90
MIN_COVERAGE = 0.80
PART_FRACTION = 0.10
#: Objects with fewer visible points in a frame are not scored in it.
MIN_VISIBLE_POINTS = 30
#: A closer look's frame replaces an object's score when its camera stood at most this much
#: [m] farther (horizontally) from the object than in the object's best frame so far.
CLOSER_LOOK_OFFSET_M = 0.02


@dataclass
class ObjectSegmentation:
    """How one object's visible points were segmented in one frame."""

    object: str
    visible: int
    cluster: Optional[int]        # the perceived cluster holding most of its points
    purity: float
    coverage: float
    parts: int                    # clusters holding >= PART_FRACTION of its points
    correct: bool
    merged: bool
    split: bool
    missed: bool
    camera_offset_m: float = float("nan")   # horizontal camera-object distance of the frame

    def to_dict(self) -> dict:
        return asdict(self)


def score_object(gt: np.ndarray, clusters: np.ndarray, index: int, name: str) -> ObjectSegmentation:
    """Score object ``index`` given per-point ground truth ``gt`` (object index, or
    :data:`NO_OBJECT`) and perceived ``clusters`` (>= 0 cluster id, < 0 not an object point)
    over the same scored points."""
    mine = gt == index
    visible = int(mine.sum())
    ids, counts = np.unique(clusters[mine & (clusters >= 0)], return_counts=True)
    if visible == 0 or ids.size == 0:
        return ObjectSegmentation(name, visible, None, 0.0, 0.0, 0, False, False, False, True)
    k = int(np.argmax(counts))
    best, overlap = int(ids[k]), int(counts[k])
    purity = overlap / int((clusters == best).sum())
    coverage = overlap / visible
    parts = int((counts >= PART_FRACTION * visible).sum())
    correct = purity >= MIN_PURITY and coverage >= MIN_COVERAGE
    return ObjectSegmentation(name, visible, best, round(purity, 4), round(coverage, 4), parts,
                              correct, purity < MIN_PURITY, parts >= 2, parts == 0)


def score_frame(gt_labels: np.ndarray, perceived: np.ndarray, above_band: np.ndarray,
                names: list[str]) -> list[ObjectSegmentation]:
    """Every object with at least :data:`MIN_VISIBLE_POINTS` visible points in the frame.

    ``gt_labels``: (N,) object index per pixel row; ``perceived``: (N,) perception's labels
    (>= 0 object group); ``above_band``: (N,) the rows that count (valid and above the band)."""
    gt = np.where(above_band, gt_labels, NO_OBJECT)
    clusters = np.where(above_band, perceived, -1)
    out = []
    for index, name in enumerate(names):
        if int((gt == index).sum()) >= MIN_VISIBLE_POINTS:
            out.append(score_object(gt, clusters, index, name))
    return out


def summarize(scores: list[ObjectSegmentation], objects: int) -> dict:
    """Counts over one or more rounds; ``objects``: how many objects were placed (those never
    scored count as missed)."""
    correct = sum(s.correct for s in scores)
    return {"objects": objects, "scored": len(scores), "correct": correct,
            "correct_rate": None if objects == 0 else round(correct / objects, 4),
            "merged": sum(s.merged for s in scores), "split": sum(s.split for s in scores),
            "missed": objects - len(scores) + sum(s.missed for s in scores)}


class ScanSegmentationRecorder:
    """Scores segmentation in the probe frames of the first active scan (see the module doc).

    Subscribe with :meth:`attach`; read :attr:`best` (object name → its score) afterwards."""

    def __init__(self, world, band_m: float) -> None:
        self.world = world
        self.band_m = float(band_m)
        self.active = False      # between the rough view and the end of the scan
        self.armed = False       # a probe arrived: score the next labelled frame
        self.closer = False      # ... and it was a closer look's
        self.frame = None
        self.best: dict[str, ObjectSegmentation] = {}

    def attach(self, events: EventBus) -> "ScanSegmentationRecorder":
        events.subscribe(StageEvent, self.on_stage)
        events.subscribe(FrameEvent, self.on_frame)
        events.subscribe(PerceptionEvent, self.on_perception)
        return self

    def on_stage(self, ev: StageEvent) -> None:
        if ev.name == "rough_view_done":
            self.active = True
        elif ev.name == "scan_done":
            self.active = self.armed = False
            enable_frame_labels(self.world, False)
        elif ev.name in ("probe_arrived", "closer_look_arrived") and self.active:
            self.armed, self.closer = True, ev.name == "closer_look_arrived"
            enable_frame_labels(self.world, True)

    def on_frame(self, ev: FrameEvent) -> None:
        self.frame = ev.frame if self.armed else None

    def on_perception(self, ev: PerceptionEvent) -> None:
        if not self.armed or self.frame is None:
            return
        try:
            gt = frame_labels(self.world, self.frame).reshape(-1)
        except FrameLabelsError:  # captured before the labels were on: wait for the next
            return
        self.armed = False
        enable_frame_labels(self.world, False)
        self._score(gt, ev.result)

    def _score(self, gt: np.ndarray, result) -> None:
        plane = result.table
        pts = np.asarray(result.points, dtype=float)
        valid = np.isfinite(pts[:, 0])
        above = np.zeros(len(pts), dtype=bool)
        if plane is not None:
            d = rows_where(pts, valid) @ np.asarray(plane.n, float) + float(plane.c)
            above[np.flatnonzero(valid)] = d > self.band_m
        names = [o.name for o in self.world.scene.objects]
        cam = np.asarray(self.frame.T_world_camera)[:2, 3]
        truths = {t.name: t.position_m for t in object_truths(self.world)}
        for s in score_frame(gt, np.asarray(result.labels), above, names):
            s.camera_offset_m = round(float(np.linalg.norm(truths[s.object][:2] - cam)), 4)
            old = self.best.get(s.object)
            slack = CLOSER_LOOK_OFFSET_M if self.closer else 0.0
            if old is None or s.camera_offset_m < old.camera_offset_m + slack:
                self.best[s.object] = s
