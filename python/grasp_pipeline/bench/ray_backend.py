"""Benchmark jobs on Ray (optional extra ``pip install '.[ray]'``): the same jobs, records and
failure handling as the local :mod:`.scheduler`, spread over a Ray cluster.

Without ``address`` a local Ray instance starts by itself with ``workers`` CPUs; with one
(``--address HOST:6379``) the jobs go to that cluster (started with ``ray start --head`` and
``ray start --address ...`` on each machine, each with this package installed). Each job is
one Ray task with ``num_cpus=1`` in a worker process that runs **only that job**
(``max_calls=1``: a fresh process per job, as OMPL's random generator is seeded once per
process, so results are identical to the local backend for a seed). Workers get the job
environment (:func:`.jobs.worker_env`: ``MUJOCO_GL``, one thread) through Ray's
``runtime_env`` before they import MuJoCo. A task whose worker dies, raises inside Ray or
exceeds ``timeout_s`` costs its job only (a failed record with the reason); tasks are not
retried (a crash would repeat).
"""

from __future__ import annotations

import logging
import os
import sys
import time

from ..exceptions import GraspPipelineError
from .jobs import JobSpec, add_process_cpu, worker_env

log = logging.getLogger(__name__)

#: What ``--backend`` accepts.
BACKENDS = ("local", "ray")


class RayUnavailable(GraspPipelineError):
    """Ray is not installed (it is an optional extra)."""


def import_ray():
    try:
        import ray
    except ImportError as exc:
        raise RayUnavailable("--backend ray needs Ray: pip install 'grasp_pipeline[ray]' "
                             "(or pip install '.[ray]' in a checkout)") from exc
    return ray


def _runtime_env(env: dict) -> dict:
    env = dict(env)
    if os.environ.get("PYTHONPATH"):  # a source checkout run (PYTHONPATH=python)
        env["PYTHONPATH"] = os.environ["PYTHONPATH"]
    return {"env_vars": env}


def _job(run_fn, task: tuple, log_level: int, tag: str) -> dict:
    """The body of a Ray task: run one job in this (fresh) worker process."""
    from ..logs import setup_logging

    setup_logging(log_level, tag=f"[{tag} {task[0]}] ")
    rec = run_fn(task)
    add_process_cpu(rec)
    return rec


def _start(ray, address, workers: int, env: dict):
    if ray.is_initialized():
        return False
    kwargs = {"runtime_env": _runtime_env(env), "include_dashboard": False,
              "logging_level": logging.WARNING, "log_to_driver": True}
    if address is None:
        kwargs["num_cpus"] = int(workers)
    else:
        kwargs["address"] = address
    ray.init(**kwargs)
    return True


class _RayRun:
    """The submitted tasks of one benchmark and their bookkeeping."""

    def __init__(self, ray, spec: JobSpec, timeout_s: float, bar) -> None:
        self.ray, self.spec, self.timeout_s, self.bar = ray, spec, timeout_s, bar
        self.remote = ray.remote(num_cpus=1, max_calls=1, max_retries=0)(_job)
        self.level = logging.getLogger().getEffectiveLevel()
        self.running: dict = {}   # ref -> (task, t0)
        self.results: list[dict] = []

    def submit(self, task: tuple) -> None:
        ref = self.remote.remote(self.spec.run_fn, task, self.level, self.spec.tag)
        self.running[ref] = (task, time.perf_counter())

    def _done(self, ref, rec: dict) -> None:
        self.running.pop(ref)
        self.results.append(rec)
        self.bar.set_postfix_str(self.spec.postfix_fn(self.results))
        self.bar.update(1)

    def collect(self) -> None:
        ready, _ = self.ray.wait(list(self.running), num_returns=1, timeout=1.0)
        for ref in ready:
            task, t0 = self.running[ref]
            try:
                rec = self.ray.get(ref)
            except Exception as exc:  # the worker died, or Ray itself failed the task
                err = f"WorkerDied: {type(exc).__name__}: {str(exc).splitlines()[0][:300]}"
                log.error("job %d: %s", task[0], err)
                rec = self.spec.failed_fn(task, err, time.perf_counter() - t0)
            self._done(ref, rec)
        now = time.perf_counter()
        for ref, (task, t0) in list(self.running.items()):
            if now - t0 > self.timeout_s:
                self.ray.cancel(ref, force=True)
                err = f"Timeout: the job took longer than {self.timeout_s:.0f} s wall time"
                self._done(ref, self.spec.failed_fn(task, err, now - t0))


def run_jobs_ray(tasks: list[tuple], spec: JobSpec, workers: int, timeout_s: float, progress: bool,
                 address=None) -> tuple[list[dict], bool]:
    """Like :func:`.scheduler.run_jobs`, on Ray; at most ``workers`` tasks in flight."""
    from tqdm import tqdm

    ray = import_ray()
    started = _start(ray, address, workers, worker_env())
    bar = tqdm(total=len(tasks), unit="job", desc=f"{spec.desc} (ray)", disable=not progress,
               file=sys.stderr, dynamic_ncols=True)
    run, pending, interrupted = _RayRun(ray, spec, timeout_s, bar), list(tasks), False
    try:
        while pending or run.running:
            while pending and len(run.running) < workers:
                run.submit(pending.pop(0))
            run.collect()
    except KeyboardInterrupt:
        interrupted = True
        for ref in run.running:
            ray.cancel(ref, force=True)
    finally:
        bar.close()
        if started:
            ray.shutdown()
    return sorted(run.results, key=lambda r: r["index"]), interrupted
