"""One job of ``eval``, in the worker process that runs it: the policy is loaded once, then a
few episodes are played in a row (:func:`.rollout.play_episode`), each with its video.

:func:`run_eval_job` never raises: an exception becomes the episode's (or the job's) ``error``.
"""

from __future__ import annotations

import logging
import traceback
from pathlib import Path

log = logging.getLogger(__name__)


def load_policy(spec: str, device: str, settings):
    """``reference`` (the pipeline through the environment) or a LeRobot policy folder."""
    if spec == "reference":
        from .reference_policy import ReferencePolicy

        return ReferencePolicy(settings)
    from .lerobot_policy import LeRobotPolicy

    return LeRobotPolicy(spec, device)


def _saved(row: dict, job: dict) -> dict:
    """``row`` written to the job's results folder at once (atomically): a finished episode
    survives the job's process."""
    from ..report.serialize import write_json

    write_json(Path(job["results_dir"]) / f"episode_{row['index']:05d}.json", row)
    return row


def _episode(env, policy, index: int, seed: int, job: dict) -> dict:
    from .rollout import EpisodeResult, play_episode

    video = None
    if job["videos_dir"] is not None:
        video = Path(job["videos_dir"]) / f"episode_{index:04d}_scene_{seed}.mp4"
    try:
        res = play_episode(env, policy, index, seed, video)
        log.info("episode %d (scene %d) finished: %s after %d steps", index, seed,
                 "success" if res.success else f"failed ({res.failed_stage})", res.steps)
        return _saved(res.as_dict(), job)
    except Exception as exc:  # one episode's failure is a result (e.g. a policy's NaN action)
        error = f"{type(exc).__name__}: {exc}"
        log.error("episode %d (scene %d) raised %s\n%s", index, seed, error, traceback.format_exc())
        return _saved(EpisodeResult(index=index, scene_seed=seed, failed_stage="ERROR",
                                    failure_reason=error, error=error).as_dict(), job)


def run_eval_job(job: dict) -> dict:
    """Play the job's episodes (``job``: index, episodes [(index, scene seed)], policy, device,
    protocol, objects, depth, max_steps, overrides, videos_dir, results_dir); never raises."""
    from ..dataset.record_settings import record_settings
    from .pick_env import PickPlaceEnv

    from .episode_job import run_episode_job

    def open_env():
        settings = record_settings(job["overrides"])
        return PickPlaceEnv(job["protocol"], job["objects"], job["depth"], settings=settings,
                            max_episode_steps=job["max_steps"]), settings

    def player(env, settings):
        policy = load_policy(job["policy"], job["device"], settings)
        return lambda index, seed: _episode(env, policy, index, seed, job)

    return run_episode_job(job, open_env, player)
