"""``grasp_pipeline/PickPlace-v0``: pick the named object and put it in the tray (Gymnasium).

One episode is one task on one scene: :meth:`PickPlaceEnv.reset` with a seed builds the scene
``record`` builds for that scene seed (``sparse``: random primitives; ``packed``/``pile``: the
VGN/GIGA clutter protocols of the object set ``objects``), with the arm at its start pose, and
names a target (:mod:`.targets`) in a task sentence worded as ``record`` words its episodes
("pick up the red mug and put it in the tray": :attr:`PickPlaceEnv.task`, also ``info["task"]``).

Observations and actions are the dataset's (:mod:`.interface`, :mod:`.spaces`): the same keys,
shapes, dtypes and units as a ``record`` dataset's ``observation.*`` and ``action`` features;
an action holds for one control period at the dataset's rate. Physics is MuJoCo's, as
everywhere: the gripper holds by friction.

Reward 1 and ``terminated`` when the target rests in the tray (ground truth,
:class:`~grasp_pipeline.evaluation.target_outcome.TargetOutcome`), else 0; ``truncated`` once
``env.yaml`` ``time_limit_s`` (or ``max_episode_steps``) has passed. ``info``: ``task``,
``target`` (its scene name), ``scene_seed``, ``time_s``, ``step``, ``is_success`` (as LeRobot's
evaluation reads it), ``failure_reason`` (at truncation: where the target is), and the robot's
readings that the dataset does not record (``joint_velocity`` [rad/s], ``finger_speed_mps``,
``gripper_force_N``). The same seed gives the same scene, target, observations and — for the
same actions — the same episode.
"""

from __future__ import annotations

import logging
from typing import Any, Optional

import gymnasium as gym
import numpy as np

from ..exceptions import InputError

log = logging.getLogger(__name__)

PROTOCOLS = ("sparse", "packed", "pile")
#: Where a reset without a seed draws its scene seed from.
MAX_SEED = 2**31 - 1


def check_protocol(protocol: str) -> str:
    if protocol not in PROTOCOLS:
        raise InputError(f"protocol must be one of {', '.join(PROTOCOLS)}, got {protocol!r}")
    return protocol


class PickPlaceEnv(gym.Env):
    """See the module doc. ``overrides``: ``(config_file, sets)`` as the commands' ``--config``
    and ``--set``; ``image_size`` / ``fps``: as ``record``'s options; ``settings``: loaded
    settings (instead of ``overrides``)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 15}

    def __init__(self, protocol: str = "sparse", objects: str = "builtin", depth: bool = False,
                 image_size: Optional[int] = None, fps: Optional[int] = None,
                 max_episode_steps: Optional[int] = None, overrides: tuple = (None, ()),
                 settings=None, render_mode: Optional[str] = "rgb_array") -> None:
        from ..sim.gl_backend import configure_gl

        configure_gl()  # before anything imports MuJoCo: observations are rendered headless
        from ..dataset.record_settings import record_overrides, record_settings
        from .interface import control_steps
        from .spaces import action_space, observation_space

        self.protocol, self.objects, self.depth = check_protocol(protocol), str(objects), bool(depth)
        self.settings = settings or record_settings(record_overrides(overrides, fps, image_size))
        rec = self.settings.record
        self.fps = int(rec.record_fps_hz)
        self.metadata = {**self.metadata, "render_fps": self.fps}
        self.render_mode = render_mode
        self.observation_space = observation_space(rec, self.depth)
        self.action_space = action_space(rec)
        if max_episode_steps is not None and int(max_episode_steps) < 1:
            raise InputError(f"max_episode_steps must be >= 1, got {max_episode_steps}")
        self._max_episode_steps = int(max_episode_steps or control_steps(self.settings.env.time_limit_s, self.fps))
        self.world = self.interface = self.outcome = None
        self.scene = self.target = None
        self.task = ""
        self.scene_seed: Optional[int] = None
        self._obs: Optional[dict] = None
        self._models = None

    # ---- LeRobot reads the task from these ------------------------------------------
    @property
    def task_description(self) -> str:
        return self.task

    @property
    def control_period_s(self) -> float:
        return 1.0 / self.fps

    @property
    def sensors(self):
        """The current episode's read-only sensors (:class:`.sensors.SimSensors`)."""
        from .sensors import SimSensors

        if self.world is None:
            raise gym.error.ResetNeeded("call reset() first")
        return SimSensors(self.world)

    def object_models(self):
        """The object set of packed and pile scenes, loaded once (``objects``); a bad folder
        raises :class:`~grasp_pipeline.objects.model.MeshError` naming the file."""
        if self.protocol == "sparse":
            return self.objects
        if self._models is None:
            from ..objects.catalog import object_set

            self._models = object_set(self.objects)
        return self._models

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        scene_seed = int(seed) if seed is not None else int(self.np_random.integers(MAX_SEED))
        self._close_world()
        self._build(scene_seed, (options or {}).get("target"))
        self._obs = self.interface.observation()
        return self._obs, self._info(False, "")

    def _build(self, scene_seed: int, target_name: Optional[str]) -> None:
        from ..app.sim_system import make_scene
        from ..evaluation.target_outcome import TargetOutcome
        from ..sim.world import SimWorld
        from .interface import ControlInterface
        from .targets import choose_target

        s = self.settings
        spec = make_scene(self.protocol, scene_seed, s, self.object_models())
        target, task = self._target(spec, scene_seed, target_name, choose_target)
        world = SimWorld(spec, s.sim, s.camera, depth_noise=s.depth_noise)
        try:
            self.interface = ControlInterface(world, s.record, self.depth)
            self.outcome = TargetOutcome(world, target.name, s.env.rest_speed_mps,
                                         s.env.rest_angular_speed_rad_s)
        except BaseException:
            world.close()
            raise
        self.world, self.scene, self.scene_seed, self.target, self.task = world, spec, scene_seed, target, task

    def _target(self, spec, scene_seed: int, name: Optional[str], choose):
        from ..dataset.tasks import task_text

        if name is None:
            return choose(spec.objects, scene_seed, self.settings.record.task_template,
                          self.settings.env.unique_target)
        by_name = {o.name: o for o in spec.objects}
        if name not in by_name:
            raise InputError(f"reset option target={name!r} is not an object of scene {scene_seed}; "
                             f"its objects: {', '.join(by_name)}")
        return by_name[name], task_text(self.settings.record.task_template, by_name[name])

    def step(self, action):
        if self.world is None:
            raise gym.error.ResetNeeded("call reset() before step()")
        self.interface.apply(action)
        self._obs = self.interface.observation()
        success = self.outcome.rests_in_tray()
        truncated = not success and self.interface.steps >= self._max_episode_steps
        reason = ""
        if truncated:
            reason = (f"time limit ({self._max_episode_steps} steps, {self.world.time_s:.1f} s) "
                      f"reached; the target is {self.outcome.where()}")
        return self._obs, float(success), bool(success), bool(truncated), self._info(success, reason)

    def _info(self, success: bool, reason: str) -> dict[str, Any]:
        w = self.world
        return {"task": self.task, "target": self.target.name, "scene_seed": self.scene_seed,
                "time_s": float(w.time_s), "step": int(self.interface.steps),
                "is_success": bool(success), "failure_reason": reason,
                "joint_velocity": np.asarray(w.qd, dtype=np.float32),
                "finger_speed_mps": float(w.finger_speed_mps),
                "gripper_force_N": float(w.gripper_force_N)}

    def where(self) -> str:
        """Where the target is now, in words (for an episode's failure reason)."""
        return "" if self.outcome is None else self.outcome.where()

    def render(self):
        """The scene camera's image of the latest observation (``rgb_array``)."""
        from .interface import image_key

        return None if self._obs is None else self._obs[image_key("scene")]

    def _close_world(self) -> None:
        if self.interface is not None:
            self.interface.close()
        if self.world is not None:
            self.world.close()
        self.world = self.interface = self.outcome = None

    def close(self) -> None:
        self._close_world()
        super().close()
