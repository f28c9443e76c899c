"""One job of ``record``, in the worker process that runs it: a few episodes in a row.

Each episode is an episode of the environment (:class:`~grasp_pipeline.learning.pick_env.PickPlaceEnv`,
reset with the episode's scene seed) played by the reference policy
(:class:`~grasp_pipeline.learning.reference_policy.ReferencePolicy`: the pipeline acting only
through ``step(action)``) and recorded as it is played (:class:`.episode_recording.EpisodeRecording`).
It succeeds when the environment says so (the target rests in the tray). A kept episode
(successful ones; every one with ``keep_failed``) is written at once as a LeRobot dataset of
its own in the work folder (:func:`.shards.write_shard`).

:func:`run_record_job` never raises: an exception becomes the episode's ``error``.
"""

from __future__ import annotations

import logging
import time
import traceback
from pathlib import Path
from typing import Optional

log = logging.getLogger(__name__)


def _rerun_prepare(path: Optional[str], settings):
    """The reference policy's ``prepare``: a Rerun recording of the episode (or None)."""
    if path is None:
        return None, []
    from ..report.rerun_recorder import RerunRecorder

    recorders: list = []

    def prepare(system) -> None:
        recorders.append(RerunRecorder(path, system.world, settings.rerun).attach(system.events))

    return prepare, recorders


def _failure(out, env) -> tuple[str, str]:
    """(failed stage, message) of a failed episode: the policy's account, where the target is."""
    where = env.unwrapped.where()
    return out.failed_stage or "UNKNOWN", f"{out.message}; the target is {where}" if where else out.message


def record_episode(env, settings, index: int, scene_seed: int, job: dict) -> dict:
    """Play, record and (when kept) write one episode; its outcome row."""
    from ..learning.reference_policy import ReferencePolicy
    from .episode_recording import EpisodeRecording
    from .shards import write_shard

    t0 = time.perf_counter()
    rec = EpisodeRecording(env)
    obs, info = rec.reset(seed=scene_seed)
    prepare, recorders = _rerun_prepare(job["recordings"].get(str(index)), settings)
    try:
        out = ReferencePolicy(settings, prepare=prepare).run_episode(rec, obs, info)
    finally:
        for r in recorders:
            r.close()
    success = bool(out.terminated)
    stage, message = ("", "") if success else _failure(out, rec)
    outcome = {"task": info["task"], "success": success, "failed_stage": stage, "message": message,
               "object": info["target"]}
    row = {"index": index, "scene_seed": scene_seed, **outcome, "length": len(rec.frames),
           "steps": out.steps, "sim_s": float(env.unwrapped.world.time_s), "shard": None}
    if rec.frames and (success or job["keep_failed"]):
        extra = {"scene_seed": scene_seed, "attempt": index}
        row["shard"] = str(write_shard(Path(job["work_dir"]), index, scene_seed, rec.episode(outcome),
                                       extra, settings.record, job["depth"]))
    row["wall_s"] = time.perf_counter() - t0
    log.info("episode %d (scene %d) finished: %s, %d frames%s", index, scene_seed,
             "success" if success else f"failed ({stage})", len(rec.frames),
             ", kept" if row["shard"] else "")
    return row


def _episode_or_error(env, settings, index: int, seed: int, job: dict) -> dict:
    try:
        return record_episode(env, settings, index, seed, job)
    except Exception as exc:  # one episode's failure is a result, not a crash of the job
        error = f"{type(exc).__name__}: {exc}"
        log.error("episode %d (scene %d) raised %s\n%s", index, seed, error, traceback.format_exc())
        return {"index": index, "scene_seed": seed, "success": False, "error": error, "shard": None}


def run_record_job(job: dict) -> dict:
    """Run the job's episodes (``job``: index, episodes [(index, scene seed)], protocol,
    objects, keep_failed, depth, overrides, work_dir, recordings {index: .rrd path});
    never raises."""
    from ..learning.episode_job import run_episode_job
    from ..learning.pick_env import PickPlaceEnv
    from .record_settings import record_settings

    def open_env():
        settings = record_settings(job["overrides"])
        return PickPlaceEnv(job["protocol"], job["objects"], job["depth"], settings=settings), settings

    return run_episode_job(job, open_env, lambda env, settings: lambda index, seed:
                           _episode_or_error(env, settings, index, seed, job))
