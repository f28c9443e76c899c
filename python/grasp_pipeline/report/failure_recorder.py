"""PNGs of every failed pick: what perception saw and what the scene looked like — a
subscriber of the event stream (used by ``bench clutter``; any run may attach it).

On a :class:`~grasp_pipeline.orchestration.events.PickEvent` whose pick failed (not held, or
not in the tray when a ground-truth evaluation subscribed before this recorder) it writes
``attempt_<k>_<stage>_perception.png`` (the RViz-like view of the perception state at the
last stage the pick entered: points, boxes, approach arrows) and, when a ``render`` callable
is given (a third-person camera), ``attempt_<k>_<stage>_scene.png`` of the world right after
the attempt; when ``render_object`` is given (``render_object(row)`` → an image of where the
attempt's object went, or None) and the attempt failed after its grasp (PLACE, or reported
placed but not in the tray), ``attempt_<k>_<stage>_object.png``. The paths are added to the
pick's ``snapshots``. A failing write is logged and
listed in :attr:`problems`; it never stops the run.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable, Optional

from ..orchestration.events import EventBus, PickEvent, StageEvent
from ..orchestration.execution.stages import Stage
from .snapshot_recorder import draw_perception

log = logging.getLogger("grasp_pipeline.snapshot")

#: Failed stages after which the object is somewhere other than where it was grasped.
AFTER_GRASP = (Stage.PLACE, Stage.VERIFY)


class FailureSnapshotRecorder:
    """Writes the PNGs of failed picks into ``out_dir``; ``render() -> (H, W, 3) uint8``."""

    def __init__(self, out_dir, render: Optional[Callable] = None,
                 render_object: Optional[Callable] = None) -> None:
        self.out_dir = Path(out_dir)
        self.render = render
        self.render_object = render_object
        self.attempts = 0
        self.loop = None            # the perception loop of the latest stage event
        self.problems: list[str] = []

    def attach(self, events: EventBus) -> "FailureSnapshotRecorder":
        events.subscribe(StageEvent, self.on_stage)
        events.subscribe(PickEvent, self.on_pick)
        return self

    def on_stage(self, ev: StageEvent) -> None:
        if ev.perception is not None:
            self.loop = ev.perception

    def on_pick(self, ev: PickEvent) -> None:
        self.attempts += 1
        row = ev.result
        if row.success and row.placed and not row.failed_stage:
            return
        stage = row.failed_stage or (Stage.VERIFY if row.success else "failed")
        stem = f"attempt_{self.attempts:02d}_{stage.lower()}"
        title = f"attempt {self.attempts}: {stage} failed"
        self._write(row, stem + "_perception.png", lambda p: self._perception(p, title))
        if self.render is not None:
            self._write(row, stem + "_scene.png", self._scene)
        if self.render_object is not None and stage in AFTER_GRASP:
            self._write(row, stem + "_object.png", lambda p: self._object(p, row))

    def _perception(self, path: Path, title: str) -> None:
        if self.loop is None or self.loop.latest is None:
            raise RuntimeError("no perception state to draw")
        draw_perception(self.loop, path, title)

    def _scene(self, path: Path) -> None:
        self._image(path, self.render())

    def _object(self, path: Path, row) -> None:
        image = self.render_object(row)
        if image is None:
            raise RuntimeError(f"the attempt names no object of the scene ({row.object!r})")
        self._image(path, image)

    @staticmethod
    def _image(path: Path, image) -> None:
        import imageio.v3 as iio

        iio.imwrite(path, image)

    def _write(self, row, name: str, write: Callable[[Path], None]) -> None:
        path = self.out_dir / name
        try:
            self.out_dir.mkdir(parents=True, exist_ok=True)
            write(path)
            row.snapshots.append(str(path))
        except Exception as exc:  # a full disk must not stop the robot
            msg = f"failure snapshot {name} not written: {type(exc).__name__}: {exc}"
            log.warning("%s", msg)
            self.problems.append(msg)
