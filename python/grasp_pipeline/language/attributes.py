"""A perceived object's attributes, as the resolver compares them: colour, shape, size,
position, distance.

Everything comes from perception — the tracker's smoothed box and what the camera saw of the
track (:class:`~.observations.ObservationRecorder`) — never from the simulator's ground truth.
Distances are horizontal, from the **robot base** (the world origin of the robot description).
Sizes are relative to the objects seen (:func:`relative_sizes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Optional, Sequence

import numpy as np

from .colours import colour_name, object_colour
from .config import LanguageConfig
from .shapes import ShapeFeatures, classify, shape_features

#: Colour of an object of which no colour was seen (it matches no colour word).
UNKNOWN_COLOUR = "unknown"


@dataclass(frozen=True)
class PerceivedObject:
    """One perceived object: its track id, words and measurements."""

    tid: int
    colour: str                        # a colour name, or "unknown"
    shape: str                         # box, cylinder, mug, bottle, other
    center_m: tuple[float, float, float]
    extents_m: tuple[float, float, float]   # (width, perp_width, height) of the perceived box
    distance_m: float                  # horizontal distance from the robot base
    rgb: Optional[tuple[float, float, float]] = None   # perceived sRGB 0..1
    features: Optional[ShapeFeatures] = None           # what the shape word was decided from

    @property
    def height_m(self) -> float:
        return float(self.extents_m[2])

    @property
    def volume_m3(self) -> float:
        return float(np.prod(self.extents_m))

    @property
    def xy(self) -> tuple[float, float]:
        return float(self.center_m[0]), float(self.center_m[1])


def perceived_object(tid: int, center, R_box, extents, points: Optional[np.ndarray],
                     colours: Optional[np.ndarray], config: LanguageConfig | None = None,
                     base_xy: Sequence[float] = (0.0, 0.0)) -> PerceivedObject:
    """The attributes of one object from its box and what was seen of it."""
    cfg = config or LanguageConfig()
    rgb = None
    colour = UNKNOWN_COLOUR
    if colours is not None and len(colours):
        rgb = tuple(float(v) for v in object_colour(colours, cfg))
        colour = colour_name(rgb, cfg)
    features = None if points is None or len(points) < 3 else \
        shape_features(points, center, R_box, extents, cfg)
    shape = "other" if features is None else classify(features, cfg)
    c = tuple(float(v) for v in center)
    return PerceivedObject(tid=int(tid), colour=colour, shape=shape, center_m=c,
                           extents_m=tuple(float(v) for v in extents),
                           distance_m=float(np.hypot(c[0] - base_xy[0], c[1] - base_xy[1])), rgb=rgb,
                           features=features)


def _inside(xy: np.ndarray, track, margin_m: float) -> bool:
    """True when ``xy`` lies within the track's box footprint (grown by ``margin_m``)."""
    e = track.smoothed
    d = (np.asarray(xy, float) - np.asarray(e.center, float)[:2]) @ np.asarray(e.R_box, float)[:2, :2]
    return bool(np.all(np.abs(d) <= np.asarray(e.extents, float)[:2] / 2 + margin_m))


def _area(track) -> float:
    return float(np.prod(np.asarray(track.smoothed.extents, float)[:2]))


def stacked_groups(tracks, margin_m: float) -> list[list]:
    """Tracks grouped as one object when one's centre lies in another's footprint: perception
    may keep two tracks of one object seen in two parts (a bottle's neck above its body —
    a depth step of more than the clustering distance — or a mug's inside). Each group is
    led by its track of the largest footprint."""
    order = sorted(tracks, key=_area, reverse=True)
    groups: list[list] = []
    for t in order:
        c = np.asarray(t.smoothed.center, float)[:2]
        home = next((g for g in groups if _inside(c, g[0], margin_m)), None)
        if home is None:
            groups.append([t])
        else:
            home.append(t)
    return groups


def _merged(group, observations):
    """(centre, R_box, extents, points, colours) of one group (its leader's box, the tallest
    height, every member's points and colours)."""
    lead = group[0].smoothed
    extents = np.asarray(lead.extents, float).copy()
    extents[2] = max(float(t.smoothed.extents[2]) for t in group)
    obs = [observations.tracks.get(int(t.tid)) for t in group] if observations is not None else []
    obs = [o for o in obs if o is not None]
    points = np.concatenate([o.points for o in obs]) if obs else None
    colours = np.concatenate([o.colour_samples() for o in obs]) if obs else None
    return lead.center, lead.R_box, extents, points, colours


def perceive_objects(tracks, observations, config: LanguageConfig | None = None,
                     base_xy: Sequence[float] = (0.0, 0.0)) -> list[PerceivedObject]:
    """Attributes of every perceived object (``observations``: an ObservationRecorder or
    None); tracks of one object seen in parts are merged first (:func:`stacked_groups`), the
    object keeps its largest track's id."""
    cfg = config or LanguageConfig()
    out = []
    for group in stacked_groups(list(tracks), cfg.shape_cell_m):
        center, R, extents, points, colours = _merged(group, observations)
        out.append(perceived_object(int(group[0].tid), center, R, extents, points, colours, cfg, base_xy))
    return sorted(out, key=lambda o: o.tid)


def relative_sizes(objects: Sequence[PerceivedObject],
                   config: LanguageConfig | None = None) -> Mapping[int, str]:
    """tid → "small", "large" or "" : the volume of the perceived box against the median
    volume of the objects seen (``size_small_ratio_max`` / ``size_large_ratio_min``)."""
    cfg = config or LanguageConfig()
    if not objects:
        return {}
    median = float(np.median([o.volume_m3 for o in objects]))
    out = {}
    for o in objects:
        ratio = o.volume_m3 / median if median > 0 else 1.0
        out[o.tid] = ("small" if ratio <= cfg.size_small_ratio_max
                      else "large" if ratio >= cfg.size_large_ratio_min else "")
    return out
