"""What the camera saw of each tracked object, gathered from the run's event stream.

Perception labels every input row of a frame (``FrameResult.labels``: the object group id
of each point) and tells which track each group's estimate updated (``raw.estimate_labels[i]``
→ ``raw.tids[i]``). The camera's frames are organized (row ``v*W + u`` is pixel (u, v)) and
carry an aligned colour image, so a group's rows give both its world points and the colour
of each. :class:`ObservationRecorder` subscribes to :class:`FrameEvent` (to keep the colour
image of the frame being processed) and :class:`PerceptionEvent` (labels, tids) and keeps,
per track id, up to ``colour_samples_per_frame`` colour samples per frame and a voxel-thinned
union of the world points over all frames (objects do not move while they are looked at;
after a pick, call :meth:`forget`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..orchestration.events import EventBus, FrameEvent, PerceptionEvent
from .config import LanguageConfig


@dataclass
class TrackObservation:
    """Colour samples (N, 3) uint8 and world points (M, 3) of one track."""

    colours: list = field(default_factory=list)
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    frames: int = 0

    def colour_samples(self) -> np.ndarray:
        return np.concatenate(self.colours) if self.colours else np.zeros((0, 3), np.uint8)


class ObservationRecorder:
    """Per-track colour samples and points from the frames perception processed."""

    def __init__(self, config: LanguageConfig | None = None, seed: int = 0) -> None:
        self.config = config or LanguageConfig()
        self.tracks: dict[int, TrackObservation] = {}
        self._frame = None
        self._rng = np.random.default_rng(seed)

    def attach(self, events: EventBus) -> "ObservationRecorder":
        events.subscribe(FrameEvent, self.on_frame)
        events.subscribe(PerceptionEvent, self.on_perception)
        return self

    def forget(self) -> None:
        """Drop everything seen (the objects may have moved)."""
        self.tracks.clear()

    def on_frame(self, event: FrameEvent) -> None:
        self._frame = event.frame

    def on_perception(self, event: PerceptionEvent) -> None:
        frame, res = self._frame, event.result
        if frame is None or frame.points_world is not res.points:
            return  # not the frame this result belongs to
        raw = res.raw
        labels = np.asarray(res.labels)
        rgb = None if frame.rgb is None else np.asarray(frame.rgb).reshape(-1, 3)
        for label, tid in zip(raw.estimate_labels, raw.tids):
            rows = np.flatnonzero(labels == label)
            if len(rows):
                self._add(int(tid), rows, res.points, rgb)

    def _add(self, tid: int, rows: np.ndarray, points: np.ndarray, rgb) -> None:
        cfg = self.config
        obs = self.tracks.setdefault(tid, TrackObservation())
        obs.frames += 1
        if rgb is not None:
            pick = rows if len(rows) <= cfg.colour_samples_per_frame else \
                self._rng.choice(rows, cfg.colour_samples_per_frame, replace=False)
            obs.colours.append(rgb[pick].copy())
        union = np.concatenate([obs.points, np.asarray(points[rows], float)])
        obs.points = thin(union, cfg.shape_voxel_m, cfg.shape_max_points, self._rng)


def thin(points: np.ndarray, voxel_m: float, max_points: int, rng: np.random.Generator) -> np.ndarray:
    """One point per ``voxel_m`` voxel (the first), then at most ``max_points`` at random."""
    if len(points) == 0:
        return points
    keys = np.floor(points / voxel_m).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    kept = points[np.sort(first)]
    if len(kept) > max_points:
        kept = kept[np.sort(rng.choice(len(kept), max_points, replace=False))]
    return kept
