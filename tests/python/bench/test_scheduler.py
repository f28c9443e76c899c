"""The job scheduler of the benchmarks, local and on Ray: results in index order, a fresh
process per job (or up to ``jobs_per_worker`` jobs per process, each planned from a fresh
process's random state; never after a failed job), and a worker that dies costs its own job
only (reported with the reason)."""

from __future__ import annotations

from pathlib import Path

import pytest

from grasp_pipeline.bench.jobs import JobSpec
from grasp_pipeline.bench.scheduler import run_jobs

import jobs_for_tests as jobs  # (this folder is on sys.path: no package)

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
