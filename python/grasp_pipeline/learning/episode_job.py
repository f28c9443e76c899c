"""The frame of a worker job of ``record`` and ``eval``: one environment, a few episodes in a
row, the environment closed at the end, and a job that never raises (an exception becomes the
job's ``error``; the episodes played before it stay)."""

from __future__ import annotations

import logging
import time
import traceback
from typing import Callable

log = logging.getLogger(__name__)


def run_episode_job(job: dict, open_env: Callable, player: Callable) -> dict:
    """Play ``job["episodes"]`` ([(index, scene seed)]) in one environment.

    ``open_env()`` -> (env, settings); ``player(env, settings)`` -> ``play(index, seed)`` that
    returns the episode's row. Returns {index, episodes, error, timings}."""
    t0, cpu0 = time.perf_counter(), time.process_time()
    rows, error, env = [], None, None
    try:
        env, settings = open_env()
        play = player(env, settings)
        for index, seed in job["episodes"]:
            rows.append(play(index, seed))
    except Exception as exc:
        error = f"{type(exc).__name__}: {exc}"
        log.error("job %d raised %s\n%s", job["index"], error, traceback.format_exc())
    finally:
        if env is not None:
            env.close()
    return {"index": job["index"], "episodes": rows, "error": error,
            "timings": {"wall_s": time.perf_counter() - t0, "job_cpu_s": time.process_time() - cpu0}}
