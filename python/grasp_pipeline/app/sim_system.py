"""The composition root of a simulated run: a ``SimWorld`` wired to the pipeline's parts."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np

from ..exceptions import InputError
from ..motion.motion_planner import MotionPlanner
from ..motion.work_cell import WorkCell
from ..orchestration import (ActiveScan, EventBus, GraspAction, MotionClient, PerceptionLoop,
                             Runtime)
from ..orchestration.grasping.opening import max_grasp_width_m
from ..orchestration.scanning.side_view import SideView
from ..perception import PerceptionSession
from ..perception.scene_volume import SceneVolume
from ..robot.description import flange_T_camera
from ..settings import Settings
from ..sim.scene_spec import SceneSpec
from ..sim.scenes import random_scene, reference_scene
from ..sim.world import SimWorld

#: The parameter sets a simulated run uses.
SECTIONS = ("scene_filter", "obb", "camera", "depth_noise", "sim", "clutter", "motion", "scan", "grasp", "place",
            "grasp_fit", "grasp_sampler", "declutter", "video", "language", "rerun", "volume")


@dataclass
class System:
    """Every running part of one headless session."""

    world: SimWorld
    loop: PerceptionLoop
    rt: Runtime
    motion: MotionClient
    scanner: ActiveScan
    action: GraspAction
    cell: WorkCell
    start_q: np.ndarray
    events: EventBus = field(default_factory=EventBus)
    side_view: Optional[SideView] = None

    def close(self) -> None:
        self.world.close()


#: Scene names ``run`` accepts (``sparse`` is another name for ``random``).
SCENES = ("reference", "random", "sparse", "packed", "pile")


def make_scene(scene, seed: int, settings: Settings, objects="builtin"):
    """The reference scene (method.md §8), a seeded random (sparse) scene of primitives, a seeded
    ``packed`` or ``pile`` scene (VGN/GIGA protocols) of the object set ``objects``
    (``builtin`` or a folder/file, :func:`grasp_pipeline.objects.catalog.object_set`, or the
    list of object models it gave), or ``scene`` itself when it is a
    :class:`~grasp_pipeline.sim.scene_spec.SceneSpec`."""
    if isinstance(scene, SceneSpec):
        return scene
    if scene == "reference":
        return reference_scene(settings.sim)
    if scene in ("random", "sparse"):
        return random_scene(seed, config=settings.sim)
    if scene in ("packed", "pile"):
        from ..objects.catalog import object_set
        from ..sim.clutter_scenes import packed_scene, pile_scene

        build = packed_scene if scene == "packed" else pile_scene
        models = object_set(objects) if isinstance(objects, (str, Path)) else list(objects)
        return build(models, seed, settings.clutter, settings.sim)
    raise InputError(f"scene must be one of {', '.join(SCENES)}, got {scene!r}")


def build_system(spec, settings: Settings, events: EventBus | None = None, robot=None) -> System:
    """World + camera → perception loop; motion client; scan; grasp action (not started).
    ``robot``: build on this robot (the protocols of ``robot/protocols.py`` plus ``model``,
    ``work_cell`` and ``close()``, e.g. a learning environment's adapter) instead of a new
    ``SimWorld`` of ``spec``."""
    events = events if events is not None else EventBus()
    world = robot if robot is not None else SimWorld(spec, settings.sim, settings.camera,
                                                     depth_noise=settings.depth_noise)
    try:
        session = PerceptionSession(settings.scene_filter, settings.obb, depth_noise=settings.depth_noise)
        loop = PerceptionLoop(session, settings.scan, ready_camera_pose=world.camera_pose(),
                              events=events, camera=world, fit_config=settings.grasp_fit,
                              volume=SceneVolume(settings.volume))
        world.add_frame_listener(lambda f: loop.on_frame(f, world.q))
        rt = Runtime(world, events)
        cell = world.work_cell
        motion = MotionClient(world, MotionPlanner(settings.motion), cell.fixtures, events)
        start_q = np.asarray(world.q, float).copy()
        scanner = ActiveScan(rt, loop, motion, flange_T_camera(world.model), settings.scan,
                             max_width_m=max_grasp_width_m(settings.grasp_fit))
        action = GraspAction(rt, loop, motion, settings.grasp, work_cell=cell, home_q=start_q,
                             events=events, place_config=settings.place)
        side_view = SideView(rt, loop, motion, flange_T_camera(world.model), settings.volume,
                             settings.scan) if settings.volume.side_view else None
    except BaseException:
        world.close()
        raise
    return System(world, loop, rt, motion, scanner, action, cell, start_q, events, side_view)
