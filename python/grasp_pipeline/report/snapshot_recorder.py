"""RViz-like PNG snapshots at chosen stages: a subscriber of the event stream.

On a :class:`~grasp_pipeline.orchestration.events.StageEvent` whose name is one of
``stages`` (name → (file name, title)), it draws the perception state the event carries
(latest frame's points, the tracks' boxes and top-down approach arrows). A failing snapshot
never stops the run: it is logged and listed in :attr:`problems`.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from ..orchestration.events import EventBus, StageEvent
from .snapshot import render_snapshot

log = logging.getLogger("grasp_pipeline.snapshot")


def draw_perception(loop, path: Path, title: str) -> str:
    """PNG of a perception loop's latest frame and tracks; returns the path."""
    res = loop.latest.result
    obj, labels = res.object_points()
    boxes, grasps = [], []
    plane = loop.plane
    for tr in loop.tracks():
        e = tr.smoothed
        boxes.append((np.asarray(e.center), np.asarray(e.R_box), np.asarray(e.extents)))
        top = np.asarray(e.center) + 0.5 * e.height_m * np.asarray(plane.n)
        grasps.append((top, -np.asarray(plane.n)))
    return render_snapshot(path, obj, labels, res.environment_points(), boxes, grasps,
                           plane=plane, title=title)


class SnapshotRecorder:
    """Writes ``out_dir/<file>`` when a named stage is published; paths in :attr:`written`."""

    def __init__(self, out_dir, stages: dict[str, tuple[str, str]]) -> None:
        self.out_dir = Path(out_dir)
        self.stages = dict(stages)
        self.written: dict[str, str] = {}
        self.problems: list[str] = []

    def attach(self, events: EventBus) -> "SnapshotRecorder":
        events.subscribe(StageEvent, self.on_stage)
        return self

    def on_stage(self, ev: StageEvent) -> None:
        if ev.name not in self.stages or ev.perception is None or ev.perception.latest is None:
            return
        file_name, title = self.stages[ev.name]
        try:
            self.written[ev.name] = draw_perception(ev.perception, self.out_dir / file_name, title)
        except Exception as exc:  # a full disk must not stop the robot
            msg = f"snapshot {file_name} not written: {type(exc).__name__}: {exc}"
            log.warning("%s", msg)
            self.problems.append(msg)
