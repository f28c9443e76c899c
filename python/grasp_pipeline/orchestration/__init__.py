"""Orchestration: the scan, selection, grasp action and pick sequence, on any robot.

Talks to the robot only through :mod:`grasp_pipeline.robot.protocols` (a ``SimWorld`` in the
simulator) and to planning through :class:`MotionClient`; never imports the simulator. The
sub-packages follow the data flow:

* :mod:`.scene` — frames → perception → tracks (:class:`PerceptionLoop`), the scene's points
  and boxes, the selection (:class:`Selector`) and the default targets;
* :mod:`.scanning` — looking at the scene: the active scan (:class:`ActiveScan`, method.md §6), the
  closer look at ambiguous segments, the side view;
* :mod:`.grasping` — where grasps come from: the :class:`GraspSource` protocol
  (:mod:`.grasping.source`) and its sources (any-side, top-down, fixed), selected by
  ``grasp.grasp_source`` (:mod:`.grasping.registry`); the point checks they share;
* :mod:`.execution` — acting: the grasp action (:class:`GraspAction`, method.md §7 + PLACE) and its
  stages (:class:`Stage`), grasp planning, gripper moves, placing into the tray,
  :class:`MotionClient`.

At the top: the runtime (:class:`Runtime`), the events recorders subscribe to
(:class:`EventBus` and the event types of :mod:`.events`), the parameter sets
(:class:`ScanConfig`, :class:`GraspConfig`), one pick (:func:`pick_object` with
:class:`PickContext`) and clearing a table (:mod:`.declutter`). This is the public API:

* :class:`Runtime`, :class:`EventBus` and the event types;
* :class:`PerceptionLoop`, :class:`Selector`, :func:`default_targets`;
* :class:`ActiveScan`; :class:`GraspAction` with :class:`Stage` (``GraspStage``: the same);
* :class:`GraspSource` and :class:`GraspRequest` with :class:`GeometricGraspSource` and
  :class:`FixedGraspSource`;
* :func:`pick_object` with :class:`PickContext`;
* :class:`MotionClient`; :class:`ScanConfig`, :class:`GraspConfig`.
"""

from .config import GraspConfig, ScanConfig
from .events import (EventBus, FrameEvent, GraspEvent, PerceptionEvent, PickEvent, PlanEvent,
                     StageEvent, Tick)
from .execution.grasp_action import GraspAction, GraspStage
from .execution.motion_client import MotionClient
from .execution.stages import Stage
from .grasping.fixed import FixedGraspSource
from .grasping.source import GraspRequest, GraspSource
from .grasping.top_down import GeometricGraspSource
from .pick import PickContext, pick_object
from .runtime import Runtime, Task
from .scanning.scan import ActiveScan, ScanStage
from .scene.perception_loop import PerceptionLoop
from .scene.selection import Selector, SelectResult
from .scene.targets import default_targets

__all__ = [
    "ActiveScan", "EventBus", "FixedGraspSource", "FrameEvent", "GeometricGraspSource",
    "GraspAction", "GraspConfig", "GraspEvent", "GraspRequest", "GraspSource", "GraspStage", "MotionClient",
    "PerceptionEvent", "PerceptionLoop", "PickContext", "PickEvent", "PlanEvent", "Runtime",
    "ScanConfig", "ScanStage", "SelectResult", "Selector", "Stage", "StageEvent", "Task", "Tick",
    "default_targets", "pick_object",
]
