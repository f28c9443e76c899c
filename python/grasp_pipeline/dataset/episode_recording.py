"""Records an environment's episode as it is played: a Gymnasium wrapper.

:class:`EpisodeRecording` wraps a :class:`~grasp_pipeline.learning.pick_env.PickPlaceEnv` and
keeps, at every ``step``, the observation the policy acted on, the action the environment
applied (clipped to the limits, :mod:`grasp_pipeline.learning.interface`) and its time. It
changes nothing: whoever steps it (a learned policy, the reference policy) plays the same
episode as unwrapped. :meth:`EpisodeRecording.episode` turns the steps into an
:class:`~.episode.Episode` (a frame per step; an episode without steps has none).
"""

from __future__ import annotations

import gymnasium as gym

from .episode import Episode, build_episode


class EpisodeRecording(gym.Wrapper):
    """See the module doc."""

    def __init__(self, env) -> None:
        super().__init__(env)
        self.frames: list = []
        self._obs = None
        self._time_s = 0.0

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self.frames, self._obs, self._time_s = [], obs, float(info["time_s"])
        return obs, info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        applied = self.env.unwrapped.interface.targets.copy()
        self.frames.append((self._time_s, self._obs, applied))
        self._obs, self._time_s = obs, float(info["time_s"])
        return obs, reward, terminated, truncated, info

    def episode(self, outcome: dict) -> Episode:
        """The recorded episode with ``outcome`` (task, success, failed_stage, message, object)."""
        base = self.env.unwrapped
        return build_episode(self.frames, self._obs, outcome, depth=base.depth)
