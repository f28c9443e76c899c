"""``grasp-pipeline record``: the reference policy's episodes as one LeRobot dataset (format v3.0).

``record --protocol sparse|packed|pile --objects builtin|DIR --episodes N --seed K --workers W
[--backend local|ray --address H:P] --out DIR [--fps 15] [--image-size 256] [--depth]
[--keep-failed]``

Episode ``i`` is an episode of the environment ``grasp_pipeline/PickPlace-v0`` on the scene of
seed ``scene_seed(K, i)`` (as ``bench clutter``'s rounds), played by the reference policy (the
pipeline acting through the environment's actions) and recorded through the environment's own
observations and actions (:mod:`.record_job`). Jobs of ``env.yaml`` ``episodes_per_job``
consecutive episodes run in worker processes (:mod:`grasp_pipeline.bench.scheduler`, or Ray),
which write each kept episode (successful ones; every one with ``--keep-failed``) as a LeRobot
dataset of its own in a work folder next to ``--out`` (:mod:`.shards`; on a Ray cluster that
folder must be on a file system every node shares): video encoding happens in the workers. Jobs
are started in batches until N episodes are kept; the parent then merges the first N, in
episode order, with LeRobot's ``aggregate_datasets``. The dataset is therefore the same for a
seed whatever the backend and worker count.

On disk (:mod:`.dataset_folder`): ``--out`` is marked incomplete (``RECORD_INCOMPLETE.json``)
until the merged dataset is moved in with one rename; on Ctrl-C / SIGTERM the episodes finished
so far are written; interrupted while writing, ``--out`` stays marked incomplete and the
finished episodes stay in the work folder, each a LeRobot dataset.
"""

from __future__ import annotations

import logging
import math
import os
import resource
import time
from collections import Counter
from pathlib import Path
from typing import Optional

from ..exceptions import InputError
from .lerobot_writer import require_lerobot

log = logging.getLogger(__name__)

#: Give up when this many episodes per requested episode gave too few kept ones.
MAX_ATTEMPTS_PER_EPISODE = 5
#: The run's summary, inside the dataset's ``meta`` folder.
SUMMARY_FILE = "meta/grasp_pipeline_record.json"


def _record_task(task: tuple) -> dict:
    from .record_job import run_record_job

    return run_record_job(task[1])


def _failed_job(task: tuple, error: str, wall_s: float) -> dict:
    return {"index": task[0], "episodes": [], "error": error, "timings": {"wall_s": wall_s}}


def _postfix(records: list[dict]) -> str:
    eps = [e for r in records for e in r["episodes"]]
    return f"episodes {sum(bool(e.get('success')) for e in eps)} ok / {len(eps)}"


def _jobs():
    from ..bench.jobs import JobSpec

    return JobSpec(run_fn=_record_task, failed_fn=_failed_job, postfix_fn=_postfix,
                   desc="record", tag="job")


def check_inputs(protocol: str, objects: str, episodes: int, workers: int, out: Path,
                 overrides: tuple):
    """The loaded settings; :class:`InputError` / ``ConfigError`` before anything runs."""
    from ..learning.pick_env import check_protocol
    from .record_settings import record_settings

    check_protocol(protocol)
    if episodes < 1 or workers < 1:
        raise InputError("episodes and workers must be >= 1")
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise InputError(f"--out {out} exists and is not an empty folder: choose a new folder "
                         "(a LeRobot dataset is written into a folder of its own)")
    settings = record_settings(overrides)
    if protocol != "sparse":
        from ..objects.catalog import object_set

        object_set(objects)  # a bad object folder fails here (MeshError naming the file)
    return settings


def _check_rerun_dir(rerun_dir) -> Optional[Path]:
    """The Rerun recordings folder, checked (SDK present, folder writable) before any episode."""
    if rerun_dir is None:
        return None
    from ..report.rerun_recorder import import_rerun
    from ..report.serialize import check_writable_dir

    import_rerun()
    return check_writable_dir(Path(rerun_dir), "Rerun recordings folder (--rerun)")


def _kept(rows: list[dict]) -> int:
    return sum(1 for r in rows for e in r["episodes"] if e.get("shard"))


def job_size(per_job: int, episodes: int, workers: int) -> int:
    """Episodes per job: ``per_job``, fewer when the request would not fill every worker's
    first job (2 episodes on 1 worker: one job of 2, not of 4). Which scene an episode plays
    depends on its index only, so the dataset does not depend on it."""
    return max(1, min(per_job, math.ceil(episodes / max(1, workers))))


def _batch(needed: int, rows: list[dict], a: dict) -> int:
    """Jobs to start next (a multiple of the worker count): first enough for the episodes
    still needed were every one kept, then as many as the episodes kept per episode played so
    far say are still needed. (A batch ends when its last job does: one large first batch keeps
    every worker busy.)"""
    played = sum(len(r["episodes"]) for r in rows)
    kept, per_job, workers = _kept(rows), a["per_job"], a["workers"]
    if not played:
        n = math.ceil(needed / per_job)
    elif not kept:
        n = workers
    else:
        n = math.ceil(needed * played / kept / per_job)
    return workers * math.ceil(max(n, workers) / workers)


def _tasks(first_job: int, n: int, a: dict, work: Path) -> list[tuple]:
    from ..bench.seeds import scene_seed
    from .shards import shard_name

    out = []
    for j in range(first_job, first_job + n):
        eps = [(i, scene_seed(a["seed"], i)) for i in range(j * a["per_job"], (j + 1) * a["per_job"])]
        recs = {} if a["rerun_dir"] is None else \
            {str(i): str(Path(a["rerun_dir"]) / f"{shard_name(i, s)}.rrd") for i, s in eps}
        out.append((j, {"index": j, "episodes": eps, "protocol": a["protocol"], "objects": str(a["objects"]),
                        "keep_failed": a["keep_failed"], "depth": a["depth"], "recordings": recs,
                        "overrides": a["overrides"], "work_dir": str(work)}))
    return out


def _simulate(a: dict, work: Path, progress: bool) -> tuple[list[dict], bool]:
    """Jobs in batches until N episodes are kept (or the attempt limit); (records, interrupted)."""
    from ..bench.scheduler import run_jobs

    rows, interrupted = [], False
    limit = math.ceil(MAX_ATTEMPTS_PER_EPISODE * a["episodes"] / a["per_job"])
    while _kept(rows) < a["episodes"] and len(rows) < limit and not interrupted:
        n = min(_batch(a["episodes"] - _kept(rows), rows, a), limit - len(rows))
        batch, interrupted = run_jobs(_tasks(len(rows), n, a, work), _jobs(), min(a["workers"], n),
                                      a["job_timeout_s"], progress, a["backend"], a["address"])
        rows += batch
        if len(batch) < n:  # interrupted: the jobs not started are not there
            break
        if all(r.get("error") or all(e.get("error") for e in r["episodes"]) for r in batch):
            first = next((r.get("error") or r["episodes"][0]["error"] for r in batch), "")
            log.error("every job of the last batch failed (%s); stopping", first)
            break
    return sorted(rows, key=lambda r: r["index"]), interrupted


def _cpu_now() -> float:
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def summarize(rows: list[dict], written: list[dict], a: dict, wall_s: float, write_cpu_s: float,
              interrupted: bool) -> dict:
    """The run's summary (printed, and written to ``OUT/meta/grasp_pipeline_record.json``)."""
    played = [e for r in rows for e in r["episodes"]]
    ok = [e for e in written if e["success"]]
    job_cpu = sum(float(r["timings"].get("process_cpu_s", r["timings"].get("job_cpu_s", 0.0))) for r in rows)
    status = "interrupted" if interrupted else ("complete" if len(written) >= a["episodes"] else "incomplete")
    errors = [f"job {r['index']}: {r['error']}" for r in rows if r.get("error")]
    errors += [f"episode {e['index']}: {e['error']}" for e in played if e.get("error")]
    return {"status": status, "out": str(a["out"]), "episodes_requested": a["episodes"],
            "episodes_written": len(written), "successful_episodes_written": len(ok),
            "episodes_played": len(played), "episode_successes": sum(bool(e.get("success")) for e in played),
            "failures_by_stage": dict(Counter(e.get("failed_stage") or "ERROR" for e in played
                                              if not e.get("success"))),
            "jobs": len(rows), "jobs_failed": sum(1 for r in rows if r.get("error")),
            "episodes_per_job": a["per_job"], "tasks": sorted({e["task"] for e in written}),
            "workers": a["workers"], "backend": a["backend"], "wall_s": round(wall_s, 3),
            "cpu_s": {"jobs": round(job_cpu, 3), "writing": round(write_cpu_s, 3)},
            "cpu_s_per_successful_episode": round((job_cpu + write_cpu_s) / len(ok), 3) if ok else None,
            "successful_episodes_per_hour": round(3600.0 * len(ok) / wall_s, 2) if wall_s > 0 else None,
            "errors": errors}


def _write(a: dict, rows: list[dict], interrupted: bool, t0: float) -> dict:
    """Merge the finished episodes into ``out`` (see the module doc); the summary."""
    from ..report.serialize import write_json
    from . import dataset_folder as df
    from .shards import finished_shards, merge_shards

    out, work, staging = a["out"], df.work_dir(a["out"]), df.staging_dir(a["out"])
    shards = finished_shards(work)[: a["episodes"]]
    cpu0 = _cpu_now()
    if not shards:  # no dataset without episodes: the marker says why
        summary = summarize(rows, [], a, time.perf_counter() - t0, 0.0, interrupted)
        df.mark_incomplete(out, "recording", "interrupted before any episode was finished" if interrupted
                           else "no episode to keep (see failures_by_stage)", summary=summary)
        df.discard(work)
        return summary
    df.mark_incomplete(out, "writing", "the dataset is being written", episodes_finished=len(shards),
                       episodes_folder=str(work))
    try:
        df.discard(staging)
        written = merge_shards(shards, staging, a["repo_id"], a["video_file_size_mb"])
        summary = summarize(rows, written, a, time.perf_counter() - t0, _cpu_now() - cpu0, interrupted)
        write_json(staging / SUMMARY_FILE, summary)
        df.publish(staging, out)
    except BaseException as exc:
        df.discard(staging)
        df.mark_incomplete(out, "writing", f"stopped while writing the dataset ({type(exc).__name__}: {exc})",
                           episodes_finished=len(shards), episodes_folder=str(work),
                           note="each finished episode is kept there as a LeRobot dataset of its own")
        raise
    df.discard(work)
    return summary


def record_dataset(protocol: str = "sparse", objects: str = "builtin", episodes: int = 10,
                   seed: int = 0, workers: int = 1, out: str | Path = "out/dataset",
                   keep_failed: bool = False, depth: bool = False, fps: Optional[int] = None,
                   image_size: Optional[int] = None, backend: str = "local",
                   address: Optional[str] = None, overrides: tuple = (None, ()),
                   progress: bool = True, job_timeout_s: float = 3600.0,
                   rerun_dir: str | Path | None = None) -> dict:
    """Record ``episodes`` episodes into a new LeRobot dataset at ``out``; returns the summary.
    ``rerun_dir``: also one Rerun recording per episode there (``episode_<i>_scene_<seed>.rrd``)."""
    from ..app.run_command import sigterm_as_interrupt
    from . import dataset_folder as df
    from .record_settings import record_overrides

    from ..learning import require_gymnasium

    if not progress:  # LeRobot's own bars too (tqdm reads this when it is first imported)
        os.environ.setdefault("TQDM_DISABLE", "1")
    require_lerobot()  # before anything is simulated
    require_gymnasium()
    out = Path(out)
    overrides = record_overrides(overrides, fps, image_size)
    settings = check_inputs(protocol, objects, episodes, workers, out, overrides)
    rerun_dir = _check_rerun_dir(rerun_dir)
    a = {"protocol": protocol, "objects": objects, "episodes": int(episodes), "seed": int(seed),
         "workers": int(workers), "keep_failed": bool(keep_failed), "depth": bool(depth),
         "overrides": overrides, "backend": backend, "address": address, "out": out,
         "job_timeout_s": job_timeout_s, "rerun_dir": rerun_dir,
         "per_job": job_size(settings.env.episodes_per_job, int(episodes), int(workers)),
         "repo_id": settings.record.repo_id,
         "video_file_size_mb": settings.record.video_file_size_mb}
    work = df.work_dir(out)
    for stale in (work, df.staging_dir(out)):  # left by a run that was killed
        df.discard(stale)
    df.mark_incomplete(out, "recording", "record is running", pid=os.getpid(), episodes_folder=str(work))
    t0 = time.perf_counter()
    with sigterm_as_interrupt():
        rows, interrupted = _simulate(a, work, progress)
        return _write(a, rows, interrupted, t0)


def record_main(args) -> int:
    """The ``record`` sub-command: record, print the summary; exit code 0 when complete,
    130 when interrupted, 1 otherwise."""
    from ..report.serialize import dumps

    summary = record_dataset(
        protocol=args.protocol, objects=args.objects, episodes=args.episodes, seed=args.seed,
        workers=args.workers, out=args.out, keep_failed=args.keep_failed, depth=args.depth,
        fps=args.fps, image_size=args.image_size, backend=args.backend, address=args.address,
        overrides=(args.config, args.sets), progress=not args.no_progress,
        job_timeout_s=args.job_timeout, rerun_dir=args.rerun)
    print(dumps(summary, sort_keys=True))
    if summary["status"] != "complete":
        log.error("dataset %s: %s (%d of %d episodes written)", summary["out"], summary["status"],
                  summary["episodes_written"], summary["episodes_requested"])
        return 130 if summary["status"] == "interrupted" else 1
    return 0
