"""``grasp-pipeline record``: scripted demonstrations as one LeRobot dataset (format v3.0).

``record --protocol sparse|packed --objects builtin|DIR --episodes N --seed K --workers W
[--backend local|ray --address H:P] --out DIR [--fps 15] [--image-size 256] [--depth]
[--keep-failed]``

Declutter rounds (as ``bench clutter``'s: round ``i`` of seed ``K`` uses the scene seed
``scene_seed(K, i)``) run in worker processes (:mod:`grasp_pipeline.bench.scheduler`, or
Ray); each records its picks as episodes (:mod:`.record_round`) into a work folder next to
``--out`` (on a Ray cluster that folder must be on a file system every node shares). Rounds
are started in batches until the rounds done hold N episodes to keep (successful ones;
every attempt with ``--keep-failed``); the parent then writes the first N of them in round
and attempt order through LeRobot's writer (:mod:`.lerobot_writer`) and deletes the work
folder. The dataset is therefore the same for a seed whatever the backend and worker count.
On Ctrl-C the episodes finished so far are written.
"""

from __future__ import annotations

import logging
import math
import resource
import shutil
import time
from collections import Counter
from pathlib import Path
from typing import Optional

from ..exceptions import InputError
from .lerobot_writer import LeRobotWriter, require_lerobot

log = logging.getLogger(__name__)

PROTOCOLS = ("sparse", "packed")
#: Give up when this many rounds per requested episode gave too few episodes.
MAX_ROUNDS_PER_EPISODE = 5


def _record_task(task: tuple) -> dict:
    from .record_round import run_record_round

    return run_record_round(task[1])


def _failed_round(task: tuple, error: str, wall_s: float) -> dict:
    public = {k: v for k, v in task[1].items() if k not in ("overrides", "work_dir")}
    return {**public, "episodes": [], "error": error, "end_reason": None, "timings": {"wall_s": wall_s}}


def _postfix(records: list[dict]) -> str:
    eps = [e for r in records for e in r["episodes"]]
    return f"episodes {sum(e['success'] for e in eps)} ok / {len(eps)}"


def _jobs():
    from ..bench.scheduler import JobSpec

    return JobSpec(run_fn=_record_task, failed_fn=_failed_round, postfix_fn=_postfix,
                   desc="record", tag="round")


def _overrides(overrides: tuple, fps: Optional[int], image_size: Optional[int]) -> tuple:
    config_file, sets = overrides
    sets = list(sets)
    if fps is not None:
        sets.append(f"record.record_fps_hz={int(fps)}")
    if image_size is not None:
        sets += [f"record.image_width_px={int(image_size)}", f"record.image_height_px={int(image_size)}"]
    return (config_file, tuple(sets))


def check_inputs(protocol: str, objects: str, episodes: int, workers: int, out: Path,
                 overrides: tuple):
    """The loaded settings; :class:`InputError` / ``ConfigError`` before anything runs."""
    from .record_settings import record_settings

    if protocol not in PROTOCOLS:
        raise InputError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
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
    """The Rerun recordings folder, checked (SDK present, folder writable) before any round."""
    if rerun_dir is None:
        return None
    from ..report.rerun_recorder import import_rerun
    from ..report.serialize import check_writable_dir

    import_rerun()
    return check_writable_dir(Path(rerun_dir), "Rerun recordings folder (--rerun)")


def _kept(rows: list[dict]) -> list[tuple[dict, dict]]:
    """(round record, episode outcome) of the saved episodes, in round and attempt order."""
    rows = sorted(rows, key=lambda r: r["index"])
    return [(r, e) for r in rows for e in r["episodes"] if e.get("file")]


def _batch(needed: int, rows: list[dict], workers: int) -> int:
    """Rounds to start next: one per worker first, then as many as the episodes kept per round
    so far say are still needed (a multiple of the worker count)."""
    kept = len(_kept(rows))
    if not rows or not kept:
        return workers
    n = max(workers, math.ceil(needed * len(rows) / kept))
    return workers * math.ceil(n / workers)


def _tasks(first: int, n: int, a: dict, work: Path) -> list[tuple]:
    from ..bench.grasp_bench import scene_seed

    out = []
    for i in range(first, first + n):
        seed = scene_seed(a["seed"], i)
        name = f"round_{i:05d}_scene_{seed}"
        rrd = None if a["rerun_dir"] is None else str(Path(a["rerun_dir"]) / f"{name}.rrd")
        out.append((i, {"index": i, "bench_seed": a["seed"], "round": i, "seed": seed,
                        "protocol": a["protocol"], "objects": str(a["objects"]),
                        "keep_failed": a["keep_failed"], "depth": a["depth"], "recording": rrd,
                        "overrides": a["overrides"], "work_dir": str(work / name)}))
    return out


def _simulate(a: dict, work: Path, progress: bool) -> tuple[list[dict], bool]:
    """Rounds in batches until N episodes are kept (or the round limit); (records, interrupted)."""
    from ..bench.scheduler import run_jobs

    rows, interrupted, limit = [], False, MAX_ROUNDS_PER_EPISODE * a["episodes"]
    while len(_kept(rows)) < a["episodes"] and len(rows) < limit and not interrupted:
        n = min(_batch(a["episodes"] - len(_kept(rows)), rows, a["workers"]), limit - len(rows))
        batch, interrupted = run_jobs(_tasks(len(rows), n, a, work), _jobs(), min(a["workers"], n),
                                      a["round_timeout_s"], progress, a["backend"], a["address"])
        rows += batch
        if len(batch) < n:  # interrupted: the rounds not started are not there
            break
        if all(r.get("error") for r in batch):  # (e.g. no GL, a broken install): no more rounds
            log.error("every round of the last batch failed (%s); stopping", batch[0]["error"])
            break
    return sorted(rows, key=lambda r: r["index"]), interrupted


def _write(a: dict, settings, rows: list[dict]) -> list[dict]:
    from .episode import Episode

    written = []
    if not _kept(rows):  # no dataset without episodes (the summary says why)
        return written
    writer = LeRobotWriter(a["out"], settings.record, a["depth"])
    for r, e in _kept(rows)[: a["episodes"]]:
        extra = {"scene_seed": r["seed"], "round": r["round"], "attempt": e["attempt"]}
        writer.add(Episode.load(Path(e["file"]), e), extra)
        written.append({**e, **extra})
    writer.close()
    return written


def _cpu_now() -> float:
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def summarize(rows: list[dict], written: list[dict], a: dict, wall_s: float, write_cpu_s: float,
              interrupted: bool) -> dict:
    """The run's summary (printed, and written to ``OUT/meta/grasp_pipeline_record.json``)."""
    attempts = [e for r in rows for e in r["episodes"]]
    ok = [e for e in written if e["success"]]
    round_cpu = sum(float(r["timings"].get("process_cpu_s", r["timings"].get("round_cpu_s", 0.0)))
                    for r in rows)
    status = "interrupted" if interrupted else ("complete" if len(written) >= a["episodes"] else "incomplete")
    return {"status": status, "out": str(a["out"]), "episodes_requested": a["episodes"],
            "episodes_written": len(written), "successful_episodes_written": len(ok),
            "rounds": len(rows), "rounds_failed": sum(1 for r in rows if r.get("error")),
            "attempts_recorded": len(attempts), "attempt_successes": sum(e["success"] for e in attempts),
            "failures_by_stage": dict(Counter(e["failed_stage"] for e in attempts if not e["success"])),
            "tasks": sorted({e["task"] for e in written}),
            "workers": a["workers"], "backend": a["backend"], "wall_s": round(wall_s, 3),
            "cpu_s": {"rounds": round(round_cpu, 3), "writing": round(write_cpu_s, 3)},
            "cpu_s_per_successful_episode": round((round_cpu + write_cpu_s) / len(ok), 3) if ok else None,
            "successful_episodes_per_hour": round(3600.0 * len(ok) / wall_s, 2) if wall_s > 0 else None,
            "errors": [f"round {r['index']}: {r['error']}" for r in rows if r.get("error")]}


def record_dataset(protocol: str = "sparse", objects: str = "builtin", episodes: int = 10,
                   seed: int = 0, workers: int = 1, out: str | Path = "out/dataset",
                   keep_failed: bool = False, depth: bool = False, fps: Optional[int] = None,
                   image_size: Optional[int] = None, backend: str = "local",
                   address: Optional[str] = None, overrides: tuple = (None, ()),
                   progress: bool = True, round_timeout_s: float = 3600.0,
                   rerun_dir: str | Path | None = None) -> dict:
    """Record ``episodes`` episodes into a new LeRobot dataset at ``out``; returns the summary.
    ``rerun_dir``: also one Rerun recording per round there (``round_<i>_scene_<seed>.rrd``)."""
    from ..app.run_command import sigterm_as_interrupt
    from ..report.serialize import write_json

    require_lerobot()  # before anything is simulated
    out = Path(out)
    overrides = _overrides(overrides, fps, image_size)
    settings = check_inputs(protocol, objects, episodes, workers, out, overrides)
    rerun_dir = _check_rerun_dir(rerun_dir)
    a = {"protocol": protocol, "objects": objects, "episodes": int(episodes), "seed": int(seed),
         "workers": int(workers), "keep_failed": bool(keep_failed), "depth": bool(depth),
         "overrides": overrides, "backend": backend, "address": address, "out": out,
         "round_timeout_s": round_timeout_s, "rerun_dir": rerun_dir}
    if out.exists():
        out.rmdir()  # an empty folder: LeRobot creates it itself
    out.parent.mkdir(parents=True, exist_ok=True)
    work = out.parent / f".{out.name}.rounds"
    t0 = time.perf_counter()
    try:
        with sigterm_as_interrupt():
            rows, interrupted = _simulate(a, work, progress)
        cpu0 = _cpu_now()
        written = _write(a, settings, rows)
        summary = summarize(rows, written, a, time.perf_counter() - t0, _cpu_now() - cpu0, interrupted)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    write_json(out / "meta" / "grasp_pipeline_record.json", summary)
    return summary


def record_main(args) -> int:
    """The ``record`` sub-command: record, print the summary; exit code 0 when complete."""
    from ..report.serialize import dumps

    summary = record_dataset(
        protocol=args.protocol, objects=args.objects, episodes=args.episodes, seed=args.seed,
        workers=args.workers, out=args.out, keep_failed=args.keep_failed, depth=args.depth,
        fps=args.fps, image_size=args.image_size, backend=args.backend, address=args.address,
        overrides=(args.config, args.sets), progress=not args.no_progress,
        round_timeout_s=args.round_timeout, rerun_dir=args.rerun)
    print(dumps(summary, sort_keys=True))
    if summary["status"] != "complete":
        log.error("dataset %s: %s (%d of %d episodes written)", summary["out"], summary["status"],
                  summary["episodes_written"], summary["episodes_requested"])
        return 1
    return 0
