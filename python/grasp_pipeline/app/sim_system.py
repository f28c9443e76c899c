"""The composition root of a simulated run: a ``SimWorld`` wired to the pipeline's parts.

The wiring is the generic one of :mod:`.robot_system` (any robot); the simulator adds what only
it has: the work cell read from its model (``config/work_cell.yaml`` holds the same values) and
the ground truth that scores a run (:meth:`System.attach_evaluation`, ``score_tracks``)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..exceptions import InputError
from ..orchestration import EventBus
from ..robot.description import flange_T_camera
from ..settings import Settings
from ..sim.scene_spec import SceneSpec
from ..sim.scenes import random_scene, reference_scene
from ..sim.world import SimWorld
from .robot_system import RobotSystem, wire
from .work_cell_file import WorkCellSetup

#: The parameter sets a simulated run uses.
SECTIONS = ("scene_filter", "obb", "camera", "depth_noise", "sim", "clutter", "motion", "scan", "grasp", "place",
            "grasp_fit", "grasp_sampler", "declutter", "video", "language", "rerun", "volume")


@dataclass
class System(RobotSystem):
    """Every running part of one headless simulated session; :attr:`world` is the robot."""

    @property
    def world(self) -> SimWorld:
        """The simulated world (the robot of this system)."""
        return self.robot

    def attach_evaluation(self) -> None:
        """Subscribe the ground-truth evaluation of each pick (:class:`~grasp_pipeline.evaluation.
        pick_evaluator.PickEvaluator`) to the events."""
        from ..evaluation.pick_evaluator import PickEvaluator

        PickEvaluator(self.world).attach(self.events)

    def close(self) -> None:
        super().close()
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
        if isinstance(objects, (str, Path)):
            models = object_set(objects)
        else:  # a sequence as it is (a built-in set builds only what the scene draws)
            models = objects if isinstance(objects, Sequence) else list(objects)
        return build(models, seed, settings.clutter, settings.sim)
    raise InputError(f"scene must be one of {', '.join(SCENES)}, got {scene!r}")


def sim_work_cell(world) -> WorkCellSetup:
    """The work cell as the simulated model has it: table, tray boxes, tray centre and the
    camera mount (``config/work_cell.yaml`` holds the same values, a test checks it)."""
    return WorkCellSetup(world.work_cell, flange_T_camera(world.model), source="the simulated model")


def build_system(spec, settings: Settings, events: EventBus | None = None, robot=None) -> System:
    """World + camera → perception loop; motion client; scan; grasp action (not started).
    ``robot``: build on this robot (the protocols of ``robot/protocols.py`` plus ``model``,
    ``work_cell`` and ``close()``, e.g. a learning environment's adapter) instead of a new
    ``SimWorld`` of ``spec``; only a new ``SimWorld`` scores views (``score_tracks``)."""
    world = robot if robot is not None else SimWorld(spec, settings.sim, settings.camera,
                                                     depth_noise=settings.depth_noise)
    try:
        system = wire(world, sim_work_cell(world), settings, events, System)
    except BaseException:
        world.close()
        raise
    if robot is None:
        from ..evaluation import scoring

        system.score_tracks = lambda tracks: scoring.score_estimates(world, tracks, settings.obb.width_tol_m)
    return system
