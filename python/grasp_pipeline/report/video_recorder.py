"""An MP4 of the run: a subscriber of the event stream that renders at its own rate.

It listens to :class:`~grasp_pipeline.orchestration.events.Tick` and calls ``render()``
(any callable returning an (H, W, 3) image, e.g. ``grasp_pipeline.sim.scene_view.SceneView``)
every ``1/fps`` simulated seconds. A failing encoder or renderer never stops the robot: the
recorder stops recording, logs a warning and says so in :attr:`problem`.
"""

from __future__ import annotations

import logging
from typing import Callable, Optional

import numpy as np

from ..orchestration.events import EventBus, Tick
from .video import VideoWriter

log = logging.getLogger("grasp_pipeline.video")


class VideoRecorder:
    """Frames from ``render()`` every ``1/fps`` s of the run's time into a :class:`VideoWriter`."""

    def __init__(self, render: Callable[[], np.ndarray], path, fps: float = 10.0,
                 on_close: Optional[Callable[[], None]] = None) -> None:
        self.render = render
        self.on_close = on_close
        self.period_s = 1.0 / fps
        self.next_s: Optional[float] = None
        self.writer = VideoWriter(path, fps=fps)
        self.problem: Optional[str] = None
        self._events: Optional[EventBus] = None

    def attach(self, events: EventBus) -> "VideoRecorder":
        self._events = events
        events.subscribe(Tick, self.on_tick)
        return self

    def on_tick(self, ev: Tick) -> None:
        if self.next_s is not None and ev.time_s + 1e-9 < self.next_s:
            return
        self.next_s = (ev.time_s if self.next_s is None else self.next_s) + self.period_s
        try:
            self.writer.append(np.asarray(self.render()))
        except Exception as exc:  # disk full, encoder gone: the robot carries on
            self._fail(f"video recording stopped at t={ev.time_s:.2f} s: {type(exc).__name__}: {exc}")

    def _fail(self, message: str) -> None:
        self.problem = message
        log.warning("%s", message)
        if self._events is not None:
            self._events.unsubscribe(Tick, self.on_tick)

    def close(self) -> Optional[str]:
        """Finish the file; returns its path (None when nothing usable was written)."""
        if self._events is not None:
            self._events.unsubscribe(Tick, self.on_tick)
        try:
            self.writer.close()
            if self.on_close is not None:
                self.on_close()
        except Exception as exc:
            self.problem = self.problem or f"video could not be finished: {type(exc).__name__}: {exc}"
            log.warning("%s", self.problem)
            return None
        return None if self.writer.path is None else str(self.writer.path)
