"""The run's event stream: what happened, published once, for any number of recorders.

The orchestration publishes; recorders (the video, the snapshots, later dataset and 3-D
recorders) subscribe to the event types they need and never reach into the pipeline's
parts. A subscriber that raises is unsubscribed with a warning: a failing recorder never
stops the robot's work (its failure is listed in :attr:`EventBus.failures`).

Event types (all frozen dataclasses, times in simulated seconds):

* :class:`Tick` — after every control step (for recorders with a rate of their own);
* :class:`FrameEvent` — a camera frame arrived (with the arm joints at capture);
* :class:`PerceptionEvent` — perception processed a frame (the core's result, the tracks);
* :class:`PlanEvent` — a motion was planned and is about to run (with its trajectory);
* :class:`GraspEvent` — the grasp action chose among the candidate grasps of one object;
* :class:`StageEvent` — the run or an action entered a stage (``rough_view``, ``scan``,
  ``PRE_GRASP``, ...), with the perception state for recorders that draw it;
* :class:`PickEvent` — one pick ended (its :class:`~grasp_pipeline.results.PickResult`).
"""

from __future__ import annotations

import logging
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any, Callable, Optional

import numpy as np

log = logging.getLogger("grasp_pipeline.events")


@dataclass(frozen=True)
class Tick:
    time_s: float


@dataclass(frozen=True)
class FrameEvent:
    time_s: float
    frame: Any                       # grasp_pipeline.robot.frame.Frame
    q: Optional[np.ndarray] = None   # arm joints at capture [rad]


@dataclass(frozen=True)
class PerceptionEvent:
    time_s: float
    result: Any                      # grasp_pipeline.perception.FrameResult
    tracks: tuple = ()


@dataclass(frozen=True)
class PlanEvent:
    time_s: float
    kind: str                        # pre_grasp, approach, lift, scan_probe, ...
    method: str                      # direct, RRTConnect, cartesian, ...
    planning_ms: float
    timing_ms: float
    duration_s: float
    trajectory: Any = None           # the motion.trajectory.JointTrajectory about to run


@dataclass(frozen=True)
class GraspEvent:
    """The candidates a grasp source proposed for one object (``_core.BestGrasp``: position =
    contact point, R[:, 0] = approach, R[:, 2] = closing axis, ``width_m``), best first, and
    the one whose motions could be planned (``chosen``: its index; None when none could)."""

    time_s: float
    candidates: tuple = ()
    chosen: Optional[int] = None
    T_grasp: Optional[np.ndarray] = None   # TCP pose at the chosen grasp (4x4), back-off included
    backoff_m: float = 0.0


@dataclass(frozen=True)
class StageEvent:
    time_s: float
    name: str
    detail: str = ""
    perception: Any = None           # the PerceptionLoop, for recorders that draw the scene


@dataclass(frozen=True)
class PickEvent:
    time_s: float
    result: Any                      # grasp_pipeline.results.PickResult (subscribers may add
                                     # evaluation fields before it is reported)
    release_time_s: Optional[float] = None  # when the gripper opened (place or recovery)


Subscriber = Callable[[Any], None]


@dataclass
class EventBus:
    """Publish/subscribe by event type (exact type match)."""

    _subs: dict = field(default_factory=lambda: defaultdict(list))
    failures: list = field(default_factory=list)   # "subscriber: error" of dropped subscribers

    def subscribe(self, event_type: type, fn: Subscriber) -> None:
        self._subs[event_type].append(fn)

    def unsubscribe(self, event_type: type, fn: Subscriber) -> None:
        if fn in self._subs.get(event_type, []):
            self._subs[event_type].remove(fn)

    def wants(self, event_type: type) -> bool:
        """True when someone listens (publishers skip building unwanted events)."""
        return bool(self._subs.get(event_type))

    def publish(self, event: Any) -> None:
        for fn in list(self._subs.get(type(event), ())):
            try:
                fn(event)
            except Exception as exc:  # a recorder must never stop the robot
                name = getattr(fn, "__qualname__", repr(fn))
                log.warning("event subscriber %s failed (%s: %s); it is unsubscribed", name,
                            type(exc).__name__, exc)
                self.failures.append(f"{name}: {type(exc).__name__}: {exc}")
                self.unsubscribe(type(event), fn)
