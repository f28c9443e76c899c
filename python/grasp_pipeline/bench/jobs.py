"""What a benchmark job is, whichever backend runs it (:mod:`.scheduler`: spawned processes on
this machine; :mod:`.ray_backend`: Ray tasks): the job's functions (:class:`JobSpec`), the
environment of a worker process (one thread, the parent's GL backend) and the CPU time a job's
process adds to its record."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from typing import Callable

#: Environment of the worker processes: one thread each (set before they import numpy).
SINGLE_THREAD_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "BLIS_NUM_THREADS": "1",
    "LP_NUM_THREADS": "0",  # Mesa llvmpipe (software EGL/OSMesa): rasterize on the calling thread
}


@dataclass(frozen=True)
class JobSpec:
    """How to run one kind of job.

    ``run_fn(task) -> dict`` runs in the child (a module-level function: it is pickled);
    ``failed_fn(task, error, wall_s) -> dict`` makes the record of a job whose process died or
    timed out (in the parent); ``postfix_fn(records) -> str`` the progress bar's text.
    Every ``task`` is a tuple whose first element is the job's index; every record a dict
    with the job's ``index``."""

    run_fn: Callable
    failed_fn: Callable
    postfix_fn: Callable = lambda records: ""
    desc: str = "bench"
    tag: str = "job"       # log lines of a worker start with "[<tag> <index>] "
    jobs_per_worker: int = 1  # jobs a worker process runs one after the other (1: a fresh process each)


#: Jobs per worker process of the simulated benchmarks: the start-up (interpreter, imports,
#: about a second of CPU) is paid once per this many rounds or scenes; a bound, so that
#: whatever a long series of jobs might accumulate in one process stays small.
SIM_JOBS_PER_WORKER = 10


def begin_job() -> None:
    """Put this worker process in the state a fresh process has for its next job: OMPL's
    random generator is seeded again by the job's first planner (every other input of a job
    is built by the job)."""
    from ..motion.planner import reseed_next_planner

    reseed_next_planner()


def worker_env() -> dict:
    """The environment of a worker: one thread, the parent's GL backend."""
    from ..sim.gl_backend import configure_gl  # chooses MUJOCO_GL here (probes once) if unset

    env = dict(SINGLE_THREAD_ENV)
    env["MUJOCO_GL"] = configure_gl() or os.environ.get("MUJOCO_GL") or "disable"
    return env


def add_process_cpu(rec: dict, since_s: float = 0.0) -> None:
    """CPU seconds the job cost its process (all threads), from ``since_s`` (the process CPU
    time when the worker's previous job ended; 0: the process start, so the first job of a
    worker carries the start-up and imports): what the job costs on an otherwise idle core,
    whatever else loads the machine."""
    if isinstance(rec.get("timings"), dict):
        rec["timings"]["process_cpu_s"] = time.process_time() - since_s
