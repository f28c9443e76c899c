"""One episode of a policy in the environment, closed loop, and what came of it.

A learned policy (:class:`~.lerobot_policy.LeRobotPolicy`) is stepped here: observation ->
action -> ``env.step`` until the environment ends the episode. The reference policy
(:class:`~.reference_policy.ReferencePolicy`) steps the environment itself through the robot
protocols; both play through the same wrappers (the video, a recording). The video of an
episode (:class:`EpisodeVideo`: the scene and wrist images of each observation side by side,
at the environment's rate) is written under a ``.partial`` name and renamed once the episode
is over, so a finished video is always complete.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Optional

import gymnasium as gym
import numpy as np

from .interface import image_key

PARTIAL = ".partial"


class EpisodeVideo(gym.Wrapper):
    """Writes the observations' images of one episode to ``path`` (``finish`` renames it)."""

    def __init__(self, env, path: Path) -> None:
        from ..report.video import VideoWriter

        super().__init__(env)
        self.path = Path(path)
        self.partial = self.path.with_name(self.path.stem + PARTIAL + self.path.suffix)
        self.writer = VideoWriter(self.partial, fps=env.unwrapped.fps, prefer=("mp4",))

    def _frame(self, obs: dict) -> None:
        self.writer.append(np.concatenate([obs[image_key("scene")], obs[image_key("wrist")]], axis=1))

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self._frame(obs)
        return obs, info

    def step(self, action):
        out = self.env.step(action)
        self._frame(out[0])
        return out

    def finish(self) -> Optional[str]:
        """Close the video and give it its name; its path (None without frames)."""
        self.writer.close()
        if not self.writer.frames or self.writer.path is None:
            return None
        Path(self.writer.path).rename(self.path)
        return str(self.path)

    def discard(self) -> None:
        """Close and delete the unfinished video (an episode that did not end)."""
        self.writer.close()
        if self.writer.path is not None:
            Path(self.writer.path).unlink(missing_ok=True)


@dataclass
class EpisodeResult:
    """One evaluated episode."""

    index: int
    scene_seed: int
    task: str = ""
    target: str = ""
    target_model: str = ""
    success: bool = False
    terminated: bool = False
    truncated: bool = False
    failed_stage: str = ""
    failure_reason: str = ""
    target_state: str = ""
    steps: int = 0
    sim_s: float = 0.0
    wall_s: float = 0.0
    video: Optional[str] = None
    error: Optional[str] = None
    extra: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return asdict(self)


def target_model(obj) -> str:
    """What "per object" groups by: the mesh model's name, else the primitive's kind."""
    return getattr(getattr(obj, "mesh", None), "name", None) or obj.kind


def play_learned(env, policy, obs: dict, info: dict) -> tuple[bool, bool, dict, int]:
    """Step ``policy`` until the episode ends: (terminated, truncated, last info, steps)."""
    policy.reset()
    steps, terminated, truncated = 0, False, False
    while not (terminated or truncated):
        obs, _reward, terminated, truncated, info = env.step(policy.act(obs, info["task"]))
        steps += 1
    return bool(terminated), bool(truncated), info, steps


def play_episode(env, policy, index: int, scene_seed: int, video: Optional[Path] = None) -> EpisodeResult:
    """Reset ``env`` to the scene of ``scene_seed`` and play ``policy`` (learned or the reference)."""
    t0 = time.perf_counter()
    wrapped = EpisodeVideo(env, video) if video is not None else env
    obs, info = wrapped.reset(seed=scene_seed)
    base = env.unwrapped
    res = EpisodeResult(index=index, scene_seed=scene_seed, task=info["task"], target=info["target"],
                        target_model=target_model(base.target))
    try:
        _play(wrapped, policy, obs, info, res)
    except BaseException:
        if video is not None:
            wrapped.discard()
        raise
    if video is not None:
        res.video = wrapped.finish()
    res.success, res.target_state = bool(res.terminated), base.where()
    if not res.success and res.failed_stage != "TIME_LIMIT":
        res.failure_reason = f"{res.failure_reason}; the target is {res.target_state}".lstrip("; ")
    res.sim_s, res.wall_s = float(base.world.time_s), time.perf_counter() - t0
    return res


def _play(env, policy, obs: dict, info: dict, res: EpisodeResult) -> None:
    if getattr(policy, "name", "") == "reference":
        out = policy.run_episode(env, obs, info)
        res.terminated, res.truncated, res.steps = out.terminated, out.truncated, out.steps
        res.failed_stage, res.failure_reason = out.failed_stage, out.message
        res.extra = {"description": out.description}
    else:
        res.terminated, res.truncated, info, res.steps = play_learned(env, policy, obs, info)
        res.failed_stage = "" if res.terminated else "TIME_LIMIT"
        res.failure_reason = info.get("failure_reason", "")
