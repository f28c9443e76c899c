"""The composition root of a run on any robot: the pipeline's parts wired to an object that
implements the robot protocols (``robot/protocols.py``), with the work cell of a description
file (:mod:`.work_cell_file`).

:func:`build_robot_system` checks that the robot has every protocol member, feeds each camera
frame through the frame contract (:func:`~grasp_pipeline.robot.frame_contract.check_frame`)
to the perception loop, and builds motion (planning around the cell's fixtures), the active
scan, the side view and the grasp action. It never imports the simulator: the simulated
composition root (:mod:`.sim_system`) builds on it and adds the simulator's ground truth
for scoring.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional

import numpy as np

from ..exceptions import RobotAdapterError
from ..motion.motion_planner import MotionPlanner
from ..motion.work_cell import WorkCell
from ..orchestration import ActiveScan, EventBus, GraspAction, MotionClient, PerceptionLoop, Runtime
from ..orchestration.scanning.side_view import SideView
from ..orchestration.grasping.opening import max_grasp_width_m
from ..perception import PerceptionSession
from ..perception.scene_volume import SceneVolume
from ..robot.frame_contract import check_frame
from ..robot.protocols import missing_members
from ..settings import Settings
from .work_cell_file import WorkCellSetup

#: The parameter sets a run on a robot uses (none of the simulator's).
ROBOT_SECTIONS = ("scene_filter", "obb", "depth_noise", "motion", "scan", "grasp", "place", "grasp_fit", "grasp_sampler",
                  "declutter", "language", "rerun", "volume")


@dataclass
class RobotSystem:
    """Every running part of one session on a robot. ``score_tracks(tracks)``: ground-truth
    scores of a view's tracks — only a simulated system has them (None: no scoring)."""

    robot: Any
    loop: PerceptionLoop
    rt: Runtime
    motion: MotionClient
    scanner: ActiveScan
    action: GraspAction
    cell: WorkCell
    start_q: np.ndarray
    events: EventBus = field(default_factory=EventBus)
    side_view: Optional[SideView] = None
    setup: Optional[WorkCellSetup] = None
    score_tracks: Optional[Callable[[list], list]] = None
    frame_listener: Optional[Callable] = None

    def close(self) -> None:
        """Stop listening to the robot's camera; the robot itself belongs to the caller."""
        if self.frame_listener is not None:
            self.robot.remove_frame_listener(self.frame_listener)
            self.frame_listener = None


def check_robot(robot: Any) -> None:
    """:class:`RobotAdapterError` naming the protocol members ``robot`` lacks."""
    missing = missing_members(robot)
    if missing:
        raise RobotAdapterError(
            f"the robot {type(robot).__name__} lacks {', '.join(missing)} of the robot protocols "
            "(grasp_pipeline.robot.protocols): implement them in its adapter (docs/real_robot.md)")


def build_robot_system(robot: Any, setup: WorkCellSetup, settings: Settings,
                       events: Optional[EventBus] = None) -> RobotSystem:
    """The pipeline on ``robot`` in the cell ``setup`` (:func:`.work_cell_file.load_work_cell`),
    not started; ``settings`` of (at least) :data:`ROBOT_SECTIONS`. The arm's joints now are
    the start (and home) joints."""
    check_robot(robot)
    return wire(robot, setup, settings, events, RobotSystem)


def wire(robot: Any, setup: WorkCellSetup, settings: Settings, events: Optional[EventBus],
         system_class: type) -> Any:
    """Perception loop fed by the robot's checked frames; motion client; scan; side view;
    grasp action — as a ``system_class`` (:class:`RobotSystem` or a subclass)."""
    events = events if events is not None else EventBus()
    session = PerceptionSession(settings.scene_filter, settings.obb, workspace=setup.workspace(),
                                depth_noise=settings.depth_noise)
    loop = PerceptionLoop(session, settings.scan, ready_camera_pose=robot.camera_pose(), events=events,
                          camera=robot, fit_config=settings.grasp_fit, volume=SceneVolume(settings.volume))

    def on_frame(frame) -> None:  # where a frame enters the pipeline: the contract is checked
        loop.on_frame(check_frame(frame), robot.q)

    robot.add_frame_listener(on_frame)
    try:
        rt = Runtime(robot, events)
        cell = setup.cell
        motion = MotionClient(robot, MotionPlanner(settings.motion), cell.fixtures, events)
        start_q = np.asarray(robot.q, float).copy()
        scanner = ActiveScan(rt, loop, motion, setup.flange_T_camera, settings.scan,
                             max_width_m=max_grasp_width_m(settings.grasp_fit))
        action = GraspAction(rt, loop, motion, settings.grasp, work_cell=cell, home_q=start_q,
                             events=events, place_config=settings.place)
        side_view = SideView(rt, loop, motion, setup.flange_T_camera, settings.volume,
                             settings.scan) if settings.volume.side_view else None
    except BaseException:
        robot.remove_frame_listener(on_frame)
        raise
    return system_class(robot, loop, rt, motion, scanner, action, cell, start_q, events, side_view,
                        setup, None, on_frame)
