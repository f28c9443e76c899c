"""Orchestration: the scan, selection, grasp action and pick sequence, on any robot.

Talks to the robot only through :mod:`grasp_pipeline.robot.protocols` (a ``SimWorld`` in the
simulator) and to planning through :class:`MotionClient`; never imports the simulator. The
composition root (``grasp_pipeline.app``) builds the parts; this is the public API:

* :class:`Runtime` — cooperative tasks on the robot's clock; :class:`EventBus` and the event
  types of :mod:`.events` that recorders subscribe to;
* :class:`PerceptionLoop` — frames → perception → tracks → best grasp; :class:`Selector`;
* :class:`ActiveScan` — SPEC 6; :class:`GraspAction` — SPEC 7 + PLACE;
* :class:`GraspSource` with :class:`GeometricGraspSource` and :class:`FixedGraspSource`;
* :func:`pick_object` with :class:`PickContext`; :func:`default_targets`;
* :class:`MotionClient`; :class:`ScanConfig`, :class:`GraspConfig`.
"""

from .config import GraspConfig, ScanConfig
from .events import (EventBus, FrameEvent, GraspEvent, PerceptionEvent, PickEvent, PlanEvent,
                     StageEvent, Tick)
from .grasp_action import GraspAction, GraspStage
from .grasp_source import FixedGraspSource, GeometricGraspSource, GraspRequest, GraspSource
from .motion_client import MotionClient
from .perception_loop import PerceptionLoop
from .pick import PickContext, pick_object
from .runtime import Runtime, Task
from .scan import ActiveScan, ScanStage
from .selection import Selector, SelectResult
from .targets import default_targets

__all__ = [
    "ActiveScan", "EventBus", "FixedGraspSource", "FrameEvent", "GeometricGraspSource",
    "GraspAction", "GraspConfig", "GraspEvent", "GraspRequest", "GraspSource", "GraspStage", "MotionClient",
    "PerceptionEvent", "PerceptionLoop", "PickContext", "PickEvent", "PlanEvent", "Runtime",
    "ScanConfig", "ScanStage", "SelectResult", "Selector", "StageEvent", "Task", "Tick",
    "default_targets", "pick_object",
]
