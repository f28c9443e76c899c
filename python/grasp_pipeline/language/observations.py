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
    """Colour samples (N, 3) uint8 and world points (M, 3) of one track; ``keys`` are the
    points' voxel keys (sorted; the points in the same order)."""

    colours: list = field(default_factory=list)
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    keys: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
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
        rows = np.flatnonzero(labels >= 0)          # object rows only (a small part of a frame)
        row_labels = labels[rows]
        rgb = None if frame.rgb is None else np.asarray(frame.rgb).reshape(-1, 3)
        for label, tid in zip(raw.estimate_labels, raw.tids):
            mine = rows[row_labels == label]
            if len(mine):
                self._add(int(tid), mine, res.points, rgb)

    def _add(self, tid: int, rows: np.ndarray, points: np.ndarray, rgb) -> None:
        cfg = self.config
        obs = self.tracks.setdefault(tid, TrackObservation())
        obs.frames += 1
        if rgb is not None:
            pick = rows if len(rows) <= cfg.colour_samples_per_frame else \
                self._rng.choice(rows, cfg.colour_samples_per_frame, replace=False)
            obs.colours.append(rgb[pick].copy())
        add_points(obs, np.asarray(points[rows], float), cfg.shape_voxel_m, cfg.shape_max_points,
                   self._rng)


#: Voxel indices are packed into one int64 key: 21 bits per axis (about ±2 km at 2 mm).
_KEY_BITS = 21
_KEY_OFFSET = 1 << (_KEY_BITS - 1)


def voxel_keys(points: np.ndarray, voxel_m: float) -> np.ndarray:
    """One int64 per point: its ``voxel_m`` voxel's indices packed together."""
    k = np.floor(points / voxel_m).astype(np.int64) + _KEY_OFFSET
    return (k[:, 0] << (2 * _KEY_BITS)) | (k[:, 1] << _KEY_BITS) | k[:, 2]


def add_points(obs: TrackObservation, new: np.ndarray, voxel_m: float, max_points: int,
               rng: np.random.Generator) -> None:
    """Add the points of voxels not yet held (one point per voxel), then keep at most
    ``max_points`` at random. Incremental: sorting only the new points' keys."""
    if len(new) == 0:
        return
    keys, first = np.unique(voxel_keys(new, voxel_m), return_index=True)
    pos = np.searchsorted(obs.keys, keys)
    held = np.zeros(len(keys), bool)
    inside = pos < len(obs.keys)
    held[inside] = obs.keys[pos[inside]] == keys[inside]
    obs.keys = np.insert(obs.keys, pos[~held], keys[~held])
    obs.points = np.insert(obs.points, pos[~held], new[first[~held]], axis=0)
    if len(obs.keys) > max_points:
        keep = np.sort(rng.choice(len(obs.keys), max_points, replace=False))
        obs.keys, obs.points = obs.keys[keep], obs.points[keep]
