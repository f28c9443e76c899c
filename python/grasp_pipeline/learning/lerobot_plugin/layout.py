"""The environment's observations in the layout of LeRobot's evaluation loop (``lerobot-eval``):
``{"pixels": {camera: image}, "agent_pos": state}`` — its ``preprocess_observation`` turns these
into ``observation.images.<camera>`` and ``observation.state`` again."""

from __future__ import annotations

import gymnasium as gym
from gymnasium import spaces

from ...dataset.camera_views import CAMERAS
from ..interface import STATE, image_key

GYM_ID = "gym_grasp_pipeline/PickPlace-v0"
STATE_SIZE = 8


class LeRobotLayout(gym.ObservationWrapper):
    """See the module doc."""

    def __init__(self, env) -> None:
        super().__init__(env)
        space = env.observation_space.spaces
        self.observation_space = spaces.Dict({
            "pixels": spaces.Dict({c: space[image_key(c)] for c in CAMERAS}),
            "agent_pos": space[STATE]})

    @property
    def task(self) -> str:
        """The episode's task sentence (LeRobot's loop passes it to language-conditioned policies)."""
        return self.env.unwrapped.task

    @property
    def task_description(self) -> str:
        return self.env.unwrapped.task

    def observation(self, observation: dict) -> dict:
        return {"pixels": {c: observation[image_key(c)] for c in CAMERAS}, "agent_pos": observation[STATE]}


def make_env(**kwargs):
    """The environment (``PickPlaceEnv`` keyword arguments) in LeRobot's layout."""
    from ..pick_env import PickPlaceEnv

    return LeRobotLayout(PickPlaceEnv(**kwargs))
