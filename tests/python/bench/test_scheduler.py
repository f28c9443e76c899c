"""The job scheduler of the benchmarks, local and on Ray: results in index order, a fresh
process per job (or up to ``jobs_per_worker`` jobs per process, each planned from a fresh
process's random state; never after a failed job), and a worker that dies costs its own job
only (reported with the reason). Ctrl-C while a worker starts stops it quietly: the command's
own Ctrl-C waits until the new process has its instructions, and the worker's (a terminal's
Ctrl-C reaches every process of the command) until it can stop without a traceback."""

from __future__ import annotations

import multiprocessing.util as mp_util
import os
import signal
import threading
from pathlib import Path

import pytest

from grasp_pipeline import signals
from grasp_pipeline.bench.jobs import JobSpec
from grasp_pipeline.bench.scheduler import run_jobs

import jobs_for_tests as jobs  # (this folder is on sys.path: no package)
import jobs_interrupted_start

JOB = JobSpec(run_fn=jobs.echo_or_die, failed_fn=jobs.failed, desc="test")
TASKS = [(0, "a"), (1, "die"), (2, "b"), (3, "c")]


@pytest.fixture
def importable(monkeypatch):
    """Ray workers find the test's job module through PYTHONPATH (as a checkout run would)."""
    monkeypatch.setenv("PYTHONPATH", str(Path(__file__).resolve().parent))


@pytest.mark.parametrize("backend", ["local", "ray"])
def test_a_dying_worker_costs_only_its_job(backend, importable):
    records, interrupted = run_jobs(TASKS, JOB, workers=2, timeout_s=120, progress=False,
                                    backend=backend)
    assert not interrupted
    assert [r["index"] for r in records] == [0, 1, 2, 3]
    assert "WorkerDied" in records[1]["error"]
    assert [records[i]["value"] for i in (0, 2, 3)] == ["a", "b", "c"]
    assert len({records[i]["pid"] for i in (0, 2, 3)}) == 3   # a fresh process per job


def test_unknown_backend_is_refused():
    from grasp_pipeline.exceptions import InputError

    with pytest.raises(InputError, match="backend"):
        run_jobs(TASKS, JOB, workers=1, timeout_s=10, progress=False, backend="dask")


def test_a_worker_runs_several_jobs_and_never_reuses_a_failed_ones_process():
    tasks = [(0, "a"), (1, "fail"), (2, "b"), (3, "c"), (4, "d")]
    spec = JobSpec(run_fn=jobs.echo_pid, failed_fn=jobs.failed, desc="test", jobs_per_worker=2)
    records, interrupted = run_jobs(tasks, spec, workers=1, timeout_s=120, progress=False)
    assert not interrupted and [r["value"] for r in records] == ["a", "fail", "b", "c", "d"]
    pids = [r["pid"] for r in records]
    assert pids[0] == pids[1]                  # two jobs in the first worker ...
    assert pids[2] not in pids[:2]             # ... which is not reused after its failed job
    assert pids[2] == pids[3] != pids[4]       # at most jobs_per_worker jobs per process
    for r in records:
        assert r["index"] == ["a", "fail", "b", "c", "d"].index(r["value"])


def test_a_reused_worker_plans_each_job_from_a_fresh_processs_random_state():
    spec = JobSpec(run_fn=jobs.ompl_draws, failed_fn=jobs.failed, desc="test", jobs_per_worker=3)
    reused, _ = run_jobs([(0,), (1,), (2,)], spec, workers=1, timeout_s=120, progress=False)
    fresh, _ = run_jobs([(0,)], JobSpec(run_fn=jobs.ompl_draws, failed_fn=jobs.failed, desc="test"),
                        workers=1, timeout_s=120, progress=False)
    assert len({r["pid"] for r in reused}) == 1
    assert all(r["draws"] == fresh[0]["draws"] for r in reused)


@pytest.fixture
def ctrl_c_interrupts():
    """SIGINT as a terminal's foreground command has it, here and in the workers (a test runner
    started in the background passes it on ignored)."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def _wait_for_exit(pid: int) -> None:
    try:
        os.waitpid(pid, 0)
    except ChildProcessError:  # already reaped by the scheduler
        pass


def test_ctrl_c_right_after_a_worker_was_forked_reaches_the_command_once_it_started(
        monkeypatch, capfd, ctrl_c_interrupts):
    """The signal lands between the fork and the hand-over of the worker's instructions."""
    forked = []
    original = mp_util.spawnv_passfds

    def spawn_then_ctrl_c(path, args, passfds):
        pid = original(path, args, passfds)
        if any("spawn_main" in str(a) for a in args):  # a worker, not multiprocessing's tracker
            forked.append(pid)
            os.kill(os.getpid(), signal.SIGINT)
        return pid

    monkeypatch.setattr(mp_util, "spawnv_passfds", spawn_then_ctrl_c)
    with signals.interrupts_raise():
        records, interrupted = run_jobs([(0, "a"), (1, "b")], JOB, workers=1, timeout_s=60,
                                        progress=False)
    assert interrupted and records == [] and len(forked) == 1
    _wait_for_exit(forked[0])  # (a worker left behind would write its traceback later)
    err = capfd.readouterr().err
    assert "Traceback" not in err and "Error" not in err, err


def test_ctrl_c_while_a_worker_imports_stops_it_without_a_traceback(monkeypatch, capfd,
                                                                   ctrl_c_interrupts):
    monkeypatch.setenv("INTERRUPT_START_FROM", str(os.getpid()))
    spec = JobSpec(run_fn=jobs_interrupted_start.echo, failed_fn=jobs.failed, desc="test")
    with signals.interrupts_raise():
        records, interrupted = run_jobs([(0,), (1,)], spec, workers=1, timeout_s=60, progress=False)
    assert interrupted and records == []
    err = capfd.readouterr().err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err


def test_a_late_ctrl_c_does_not_break_into_a_finished_workers_exit(capfd, ctrl_c_interrupts):
    """The command is stopped while a job runs; the job ends, and the worker is still in its exit
    handlers when the scheduler sends it SIGINT (it cannot tell whether Ctrl-C reached it)."""
    spec = JobSpec(run_fn=jobs.slow_exit, failed_fn=jobs.failed, desc="test")
    stop = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGTERM))
    with signals.interrupts_raise():
        stop.start()
        records, interrupted = run_jobs([(0, 1.0)], spec, workers=1, timeout_s=60, progress=False)
    assert interrupted
    err = capfd.readouterr().err
    assert "Traceback" not in err and "exit handlers done" in err, err
