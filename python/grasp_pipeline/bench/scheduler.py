"""Benchmark jobs in spawned worker processes, W at a time, with a progress bar.

Used by ``bench grasp`` (one job = one scene), ``bench clutter`` (one job = one round),
``record`` and ``eval``.

Jobs run in worker processes started with ``multiprocessing``'s "spawn" method (MuJoCo's
EGL/OSMesa contexts must not be forked), at most ``W`` at a time. A worker runs up to
``JobSpec.jobs_per_worker`` jobs one after the other (1: a fresh process per job), so the
interpreter start-up and the imports are paid once per worker, not once per job. Each job
starts from the state a fresh process would have for it: :func:`.jobs.begin_job` re-seeds OMPL
(whose random generator is otherwise seeded once per process — a worker that ran an earlier
job would plan the next one from a different random state), and everything else a job uses is
built by the job itself (its object set: a copy of the set as the process loaded it, see
:func:`grasp_pipeline.objects.catalog.object_set`); the benchmark tests compare reused workers
with fresh processes.
A worker whose job failed, crashed or timed out is never reused. Children inherit
``MUJOCO_GL`` (the parent's choice, see :mod:`grasp_pipeline.sim.gl_backend`) and
``PYTHONPATH``, and are limited to one thread each (``OMP_NUM_THREADS=1`` and the BLAS
equivalents), so ``W`` workers use ``W`` cores. A job whose function raises is the function's
business (it should return a failed record); a child that dies (signal, segfault) or exceeds
``timeout_s`` is recorded through ``failed_fn`` and the benchmark goes on. Ctrl-C / SIGTERM
stops the running jobs — SIGINT first (unless Ctrl-C reached them already), so each run holds
its arm and writes its report saying interrupted, then SIGKILL for what still runs after
:data:`STOP_GRACE_S` — and returns the records finished so far. A worker is started with both
signals held (:func:`grasp_pipeline.signals.held`): the command's own interrupt waits until the new
process has its instructions and is known, and the worker's (Ctrl-C in a terminal reaches every
process of the command) until it is ready to stop quietly. What a job is
(:class:`~.jobs.JobSpec`) and the workers' environment: :mod:`.jobs`.
"""
from __future__ import annotations

import logging
import os
import signal
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Optional

from .. import signals
from ..signals import held, interrupts_raise, release_held
from .jobs import JobSpec, add_process_cpu, begin_job, worker_env

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


def _worker_main(conn, run_fn, log_level: int, tag: str) -> None:
    """Entry point of a spawned worker: run the jobs it is sent, one at a time, until it is sent
    ``None``; each job's record goes back with the CPU time the job cost this process. A Ctrl-C
    or SIGTERM outside a job (during the start-up, between jobs) ends it quietly; once it ends,
    Ctrl-C is ignored."""
    from ..logs import setup_logging
    from ..process_memory import keep_large_allocations

    setup_logging(log_level, tag=f"[{tag}] ")
    keep_large_allocations()
    mark = signals.received()
    try:
        with interrupts_raise():  # counted: an interrupt a library turns into an error stays one
            release_held()  # the start-up's Ctrl-C (held by the parent's mask) arrives here
            _serve(conn, run_fn, tag)
    except (EOFError, OSError, KeyboardInterrupt):  # the parent is gone, or Ctrl-C between jobs
        pass
    except Exception:
        if signals.received() == mark:  # not an import a Ctrl-C cut short: a real error
            raise
    finally:
        # Exiting: nothing is left to stop. A late Ctrl-C (the parent's, a second one) must not
        # break into the exit handlers (MuJoCo's EGL display is closed there).
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        conn.close()


def _serve(conn, run_fn, tag: str) -> None:
    """The worker's job loop (see :func:`_worker_main`)."""
    from ..logs import retag_logging

    cpu_before = 0.0  # the first job carries the start-up (interpreter, imports)
    while (task := conn.recv()) is not None:
        retag_logging(f"[{tag} {task[0]}] ")
        begin_job()
        try:
            rec = run_fn(task)
        except BaseException as exc:  # (run_fn should catch Exception; this is e.g. SystemExit)
            rec = {"index": task[0], "error": f"{type(exc).__name__}: {exc}", "crashed": True}
        add_process_cpu(rec, since_s=cpu_before)
        cpu_before = time.process_time()
        conn.send(rec)


@dataclass
class _Worker:
    """One worker process, its end of the pipe, the job it runs (``task``, started at ``t0``,
    perf_counter) and how many jobs it was given."""

    proc: object
    conn: object
    task: Optional[tuple] = None
    t0: float = 0.0
    jobs: int = 0

    def give(self, task: tuple) -> None:
        self.conn.send(task)
        self.task, self.t0 = task, time.perf_counter()
        self.jobs += 1

    def retire(self, timeout_s: float = 10.0) -> None:
        """Tell it to exit (after its current job, if any) and wait; kill it if it does not."""
        try:
            self.conn.send(None)
        except (OSError, ValueError):
            pass
        self.proc.join(timeout=timeout_s)
        if self.proc.is_alive():
            self.proc.kill()
            self.proc.join(timeout=10)
        self.conn.close()


class _Scheduler:
    """The worker processes and their bookkeeping: ``running`` maps each busy worker's
    sentinel to its :class:`_Worker`; ``idle`` holds workers that may take another job
    (``spec.jobs_per_worker``); finished records go to ``results``."""

    def __init__(self, ctx, spec: JobSpec, timeout_s: float, bar):
        self.ctx, self.spec, self.timeout_s, self.bar = ctx, spec, timeout_s, bar
        self.running: dict = {}
        self.idle: list[_Worker] = []
        self.results: list[dict] = []
        self.level = logging.getLogger().getEffectiveLevel()
        self.env = worker_env()

    def _spawn(self) -> _Worker:
        here, there = self.ctx.Pipe(duplex=True)
        proc = self.ctx.Process(target=_worker_main, args=(there, self.spec.run_fn, self.level, self.spec.tag),
                                name=f"{self.spec.desc}-worker", daemon=True)
        with child_environment(self.env):
            proc.start()
        there.close()  # the child holds the only other end: EOF when it dies
        return _Worker(proc, here)

    def start(self, task: tuple) -> None:
        """Give ``task`` to an idle worker or a new one. Ctrl-C / SIGTERM are held meanwhile: a
        new process gets its instructions whole and is known to :meth:`stop_all` before the
        interrupt is raised (it also starts with them blocked, so a Ctrl-C of the whole group
        during its start-up is seen once it can stop quietly, not as a traceback mid-import)."""
        with held():
            worker = self.idle.pop() if self.idle else self._spawn()
            worker.give(task)
            self.running[worker.proc.sentinel] = worker

    def finish(self, sentinel, rec: dict, reusable: bool = False) -> None:
        """Record ``rec``; the worker waits for another job when ``reusable`` and it has jobs
        left, else it is retired (a failed or crashed job's process is never reused)."""
        worker = self.running.pop(sentinel)
        if reusable and worker.jobs < self.spec.jobs_per_worker and not rec.get("error"):
            worker.task = None
            self.idle.append(worker)
        else:
            worker.retire()
        self.results.append(rec)
        self.bar.set_postfix_str(self.spec.postfix_fn(self.results))
        self.bar.update(1)

    def collect_ready(self) -> None:
        """Wait until a job sends its record or its process exits, or the next deadline passes."""
        from multiprocessing.connection import wait

        now = time.perf_counter()
        next_deadline = min(w.t0 + self.timeout_s for w in self.running.values())
        by_obj = {}
        for sentinel, worker in self.running.items():
            by_obj[sentinel] = sentinel
            by_obj[worker.conn] = sentinel
        for obj in wait(list(by_obj), timeout=max(0.0, next_deadline - now) + 0.05):
            sentinel = by_obj[obj]
            if sentinel in self.running:  # (its conn and sentinel may both be ready)
                rec, alive = self._result_of(sentinel)
                if rec is not None:
                    self.finish(sentinel, rec, reusable=alive)

    def _result_of(self, sentinel) -> tuple[Optional[dict], bool]:
        """What a ready job sent (and whether its worker lives on); a failed record when its
        process exited without one; ``(None, True)`` when it is still running."""
        worker = self.running[sentinel]
        task, t0 = worker.task, worker.t0
        rec = None
        try:
            if worker.conn.poll():
                rec = worker.conn.recv()
        except (EOFError, OSError):
            rec = None
        if rec is not None and rec.get("crashed"):
            return self.spec.failed_fn(task, rec["error"], time.perf_counter() - t0), False
        if rec is None:
            worker.proc.join(timeout=30)  # no result: the child closed its end or exited
            if worker.proc.exitcode is None:
                return None, True
            err = f"WorkerDied: the job process exited with code {worker.proc.exitcode} without a result"
            log.error("job %d: %s", task[0], err)
            return self.spec.failed_fn(task, err, time.perf_counter() - t0), False
        return rec, True

    def kill_overdue(self) -> None:
        now = time.perf_counter()
        for sentinel, worker in list(self.running.items()):
            if now - worker.t0 > self.timeout_s:
                worker.proc.kill()
                err = f"Timeout: the job took longer than {self.timeout_s:.0f} s wall time"
                log.error("job %d: %s", worker.task[0], err)
                self.finish(sentinel, self.spec.failed_fn(worker.task, err, now - worker.t0))

    def stop_all(self, grace_s: float = STOP_GRACE_S) -> None:
        """Retire the idle workers and stop the running jobs cleanly, then kill what still
        runs: jobs that got the user's Ctrl-C themselves (the whole process group does) get a
        moment to end on their own, the others SIGINT (a run holds the arm and writes its
        report saying interrupted) and ``grace_s`` to end."""
        for worker in self.idle:
            worker.retire()
        self.idle.clear()
        for worker in self.running.values():
            try:
                worker.conn.send(None)  # exit after the current job
            except (OSError, ValueError):
                pass
        waited = self._join_all(min(OWN_SIGNAL_WAIT_S, grace_s))
        for worker in self.running.values():
            proc = worker.proc
            if waited and proc.is_alive() and proc.pid is not None:
                try:
                    os.kill(proc.pid, signal.SIGINT)
                except OSError:
                    pass
        if waited:
            self._join_all(grace_s)
        for worker in self.running.values():
            if worker.proc.is_alive():
                worker.proc.kill()
                worker.proc.join(timeout=10)
            worker.conn.close()

    def _join_all(self, timeout_s: float) -> bool:
        """Wait up to ``timeout_s`` for the jobs to exit; False when a second Ctrl-C / SIGTERM
        cut the wait short (then nothing more is waited for)."""
        deadline = time.perf_counter() + timeout_s
        try:
            for worker in self.running.values():
                worker.proc.join(timeout=max(0.0, deadline - time.perf_counter()))
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

    from multiprocessing import resource_tracker

    # Started now, not by the first worker's start: it unblocks the signals that start holds.
    resource_tracker.ensure_running()
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
