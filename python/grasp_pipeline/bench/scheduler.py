"""Benchmark jobs in freshly spawned processes, W at a time, with a progress bar.

Used by ``bench grasp`` (one job = one scene) and ``bench clutter`` (one job = one round).

Every job runs in its **own** freshly spawned process (``multiprocessing`` "spawn" start
method — MuJoCo's EGL/OSMesa contexts must not be forked), at most ``W`` at a time. A fresh
process per job matters for determinism: OMPL's random generator is seeded once per process,
so a worker that ran an earlier job would plan the next one from a different random state,
and the results would depend on the scheduling. Children inherit ``MUJOCO_GL`` (the parent's
choice, see :mod:`grasp_pipeline.sim.gl_backend`) and ``PYTHONPATH``, and are limited to one
thread each (``OMP_NUM_THREADS=1`` and the BLAS equivalents), so ``W`` workers use ``W``
cores. A job whose function raises is the function's business (it should return a failed
record); a child that dies (signal, segfault) or exceeds ``timeout_s`` is recorded through
``failed_fn`` and the benchmark goes on. Ctrl-C / SIGTERM stops the running jobs — SIGINT first
(unless Ctrl-C reached them already), so each run holds its arm and writes its report saying
interrupted, then SIGKILL for what still runs after :data:`STOP_GRACE_S` — and returns the
records finished so far. What a job is (:class:`~.jobs.JobSpec`) and the workers' environment:
:mod:`.jobs`.
"""

from __future__ import annotations

import logging
import os
import signal
import sys
import time
from contextlib import contextmanager
from typing import Optional

from ..signals import interrupts_raise
from .jobs import JobSpec, add_process_cpu, worker_env

log = logging.getLogger(__name__)

#: Seconds the running jobs get to end cleanly on Ctrl-C / SIGTERM (each run writes its report
#: saying interrupted) before they are killed ...
STOP_GRACE_S = 5.0
#: ... after this wait for jobs that got the signal themselves (Ctrl-C reaches the whole group).
OWN_SIGNAL_WAIT_S = 1.0


@contextmanager
def child_environment(extra: dict):
    """Set environment variables for the children spawned inside the block, then restore."""
    old = {k: os.environ.get(k) for k in extra}
    os.environ.update(extra)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _child_main(conn, run_fn, task: tuple, log_level: int, tag: str) -> None:
    """Entry point of a spawned job process: run the job, send the record, exit."""
    from ..logs import setup_logging

    setup_logging(log_level, tag=f"[{tag} {task[0]}] ")
    try:
        with interrupts_raise():  # counted, so an interrupt a library turns into an error stays one
            rec = run_fn(task)
    except BaseException as exc:  # (run_fn should catch Exception; this is e.g. SystemExit)
        rec = {"index": task[0], "error": f"{type(exc).__name__}: {exc}", "crashed": True}
    add_process_cpu(rec)
    conn.send(rec)
    conn.close()


class _Scheduler:
    """The running job processes and their bookkeeping: ``running`` maps each process's
    sentinel to ``(proc, conn, task, t0)``; finished records go to ``results``."""

    def __init__(self, ctx, spec: JobSpec, timeout_s: float, bar):
        self.ctx, self.spec, self.timeout_s, self.bar = ctx, spec, timeout_s, bar
        self.running: dict = {}
        self.results: list[dict] = []
        self.level = logging.getLogger().getEffectiveLevel()
        self.env = worker_env()

    def start(self, task: tuple) -> None:
        recv, send = self.ctx.Pipe(duplex=False)
        proc = self.ctx.Process(target=_child_main, args=(send, self.spec.run_fn, task, self.level, self.spec.tag),
                                name=f"{self.spec.desc}-{task[0]}", daemon=True)
        with child_environment(self.env):
            proc.start()
        send.close()  # the child holds the only writer: EOF when it dies
        self.running[proc.sentinel] = (proc, recv, task, time.perf_counter())

    def finish(self, sentinel, rec: dict) -> None:
        proc, conn, _task, _t0 = self.running.pop(sentinel)
        conn.close()
        proc.join(timeout=10)
        self.results.append(rec)
        self.bar.set_postfix_str(self.spec.postfix_fn(self.results))
        self.bar.update(1)

    def collect_ready(self) -> None:
        """Wait until a job sends its record or exits, or the next deadline passes."""
        from multiprocessing.connection import wait

        now = time.perf_counter()
        next_deadline = min(t0 + self.timeout_s for (_p, _c, _t, t0) in self.running.values())
        by_obj = {}
        for sentinel, (_p, conn, _t, _t0) in self.running.items():
            by_obj[sentinel] = sentinel
            by_obj[conn] = sentinel
        for obj in wait(list(by_obj), timeout=max(0.0, next_deadline - now) + 0.05):
            sentinel = by_obj[obj]
            if sentinel in self.running:  # (its conn and sentinel may both be ready)
                rec = self._result_of(sentinel)
                if rec is not None:
                    self.finish(sentinel, rec)

    def _result_of(self, sentinel) -> Optional[dict]:
        """What a ready job sent; a failed record when its process exited without one; None
        when it is still running."""
        proc, conn, task, t0 = self.running[sentinel]
        rec = None
        try:
            if conn.poll():
                rec = conn.recv()
        except (EOFError, OSError):
            rec = None
        if rec is not None and rec.get("crashed"):
            return self.spec.failed_fn(task, rec["error"], time.perf_counter() - t0)
        if rec is None:
            proc.join(timeout=30)  # no result: the child closed its end or exited
            if proc.exitcode is None:
                return None
            err = f"WorkerDied: the job process exited with code {proc.exitcode} without a result"
            log.error("job %d: %s", task[0], err)
            rec = self.spec.failed_fn(task, err, time.perf_counter() - t0)
        return rec

    def kill_overdue(self) -> None:
        now = time.perf_counter()
        for sentinel, (proc, _conn, task, t0) in list(self.running.items()):
            if now - t0 > self.timeout_s:
                proc.kill()
                err = f"Timeout: the job took longer than {self.timeout_s:.0f} s wall time"
                log.error("job %d: %s", task[0], err)
                self.finish(sentinel, self.spec.failed_fn(task, err, now - t0))

    def stop_all(self, grace_s: float = STOP_GRACE_S) -> None:
        """Stop the running jobs cleanly, then kill what still runs: jobs that got the user's
        Ctrl-C themselves (the whole process group does) get a moment to end on their own, the
        others SIGINT (a run holds the arm and writes its report saying interrupted) and
        ``grace_s`` to end."""
        waited = self._join_all(min(OWN_SIGNAL_WAIT_S, grace_s))
        for proc, _conn, _task, _t0 in self.running.values():
            if waited and proc.is_alive() and proc.pid is not None:
                try:
                    os.kill(proc.pid, signal.SIGINT)
                except OSError:
                    pass
        if waited:
            self._join_all(grace_s)
        for proc, conn, _task, _t0 in self.running.values():
            if proc.is_alive():
                proc.kill()
                proc.join(timeout=10)
            conn.close()

    def _join_all(self, timeout_s: float) -> bool:
        """Wait up to ``timeout_s`` for the jobs to exit; False when a second Ctrl-C / SIGTERM
        cut the wait short (then nothing more is waited for)."""
        deadline = time.perf_counter() + timeout_s
        try:
            for proc, _conn, _task, _t0 in self.running.values():
                proc.join(timeout=max(0.0, deadline - time.perf_counter()))
        except KeyboardInterrupt:
            return False
        return True


def run_jobs(tasks: list[tuple], spec: JobSpec, workers: int, timeout_s: float,
             progress: bool, backend: str = "local", address: Optional[str] = None
             ) -> tuple[list[dict], bool]:
    """Run ``tasks`` in spawned processes, ``workers`` at a time, in the given order — or on
    Ray with ``backend="ray"`` (:mod:`.ray_backend`; ``address`` joins a cluster).
    Returns (records sorted by ``index``, interrupted): on Ctrl-C / SIGTERM the running jobs
    are stopped and the records finished so far are returned."""
    if backend == "ray":
        from .ray_backend import run_jobs_ray

        return run_jobs_ray(tasks, spec, workers, timeout_s, progress, address)
    if backend != "local":
        from ..exceptions import InputError

        raise InputError(f"backend must be 'local' or 'ray', got {backend!r}")
    import multiprocessing as mp

    from tqdm import tqdm

    pending = list(tasks)
    bar = tqdm(total=len(tasks), unit="job", desc=spec.desc, disable=not progress,
               file=sys.stderr, dynamic_ncols=True)
    sched = _Scheduler(mp.get_context("spawn"), spec, timeout_s, bar)
    interrupted = False
    try:
        while pending or sched.running:
            while pending and len(sched.running) < workers:
                sched.start(pending.pop(0))
            sched.collect_ready()
            sched.kill_overdue()
    except KeyboardInterrupt:
        interrupted = True
        log.error("interrupted: stopping the running jobs; writing the %d finished ones",
                  len(sched.results))
    finally:
        sched.stop_all(STOP_GRACE_S if interrupted else 0.0)
        bar.close()
    results = sorted(sched.results, key=lambda r: r["index"])
    return results, interrupted
