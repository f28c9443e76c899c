"""Grasp benchmark: the whole product (rough view → scan → pick every object into the tray) on
N seeded random scenes, with ground-truth scoring.

``grasp-pipeline bench grasp --scenes N --seed K --workers W --json PATH --out DIR``

Each scene is exactly one ``run_pipeline(scene="random", seed=<scene seed>, video=False)``
call. The scene seed is derived from ``K`` and the scene index by :func:`scene_seed`, so a
single scene is reproduced with ``grasp-pipeline run --scene random --seed <scene seed>``.

Processes: scenes run in spawned worker processes (``multiprocessing`` "spawn" start method —
MuJoCo's EGL/OSMesa contexts must not be forked), at most ``W`` at a time, each worker running
up to ``jobs_per_worker`` scenes one after the other; every scene starts from the state a fresh
process would have for it (OMPL's random generator seeded again, see :mod:`.scheduler`), so
the results do not depend on the scheduling. Children inherit ``MUJOCO_GL`` (the parent's
choice, see :mod:`grasp_pipeline.sim.gl_backend`) and ``PYTHONPATH``, and are limited to one
thread each (``OMP_NUM_THREADS=1`` and the BLAS equivalents), so ``W`` workers use ``W``
cores. A scene that raises is recorded as a failed scene with its error; a child that dies
(signal, segfault) or exceeds ``scene_timeout_s`` is recorded the same way, and the benchmark
goes on.

The result (:class:`~.grasp_result.GraspBenchResult`) is deterministic for a seed as far as
the product is (scenes sorted by index; the JSON is the same apart from the timing fields
listed in :data:`~.grasp_result.TIMING_KEYS`). Aggregation (:func:`.grasp_aggregate.aggregate`)
works on the per-scene records only and is a pure function.

Scoring uses ground truth (the scene spec and ``report[...]["scores"]``): evaluation code only.
"""

from __future__ import annotations

import logging
import math
import os
import time
import traceback
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from ..app.run_command import sigterm_as_interrupt
from ..report.output_lock import output_claim
from ..report.serialize import check_writable, check_writable_dir
from ..results import SceneRecord, SceneScanSummary
from .accuracy import ACCURACY_METRICS
from .failure_reasons import exception_category, reason_category
from .grasp_aggregate import aggregate
from .grasp_result import GraspBenchResult
from .jobs import SIM_JOBS_PER_WORKER, JobSpec, worker_env
from .scheduler import run_jobs
from .seeds import scene_seed

if TYPE_CHECKING:
    from ..settings import Settings

log = logging.getLogger(__name__)

#: Wall-clock limit of one scene [s] (a hung scene is killed and recorded as failed).
DEFAULT_SCENE_TIMEOUT_S = 1800.0


# ------------------------------------------------------------------------------ one scene
def _score_rows(section: Optional[dict]) -> list[dict]:
    return [] if not section else list(section.get("scores") or [])


def _score_fields(row: Optional[dict]) -> Optional[dict]:
    """The error figures of one score row (None when the object had no track)."""
    if not row or row.get("tid") is None:
        return None
    out = {"quality": row.get("quality"), "tid": row.get("tid")}
    for key in ACCURACY_METRICS.values():
        v = row.get(key)
        out[key] = None if v is None else float(v)
    return out


def _nearest_object(objects: list[dict], xy) -> Optional[str]:
    if not objects or xy is None:
        return None
    d = [math.hypot(o["position_m"][0] - xy[0], o["position_m"][1] - xy[1]) for o in objects]
    return objects[min(range(len(d)), key=d.__getitem__)]["name"]


def _pick_failure(p: dict) -> tuple[str, str]:
    """(stage, message) of a pick row that did not put its object in the tray."""
    if p.get("failed_stage"):
        return str(p["failed_stage"]), str(p.get("message") or "")
    if p.get("success") and not p.get("placed"):
        return "VERIFY", "reported success but the object is not in the tray"
    return "UNKNOWN", str(p.get("message") or "no success and no failed stage reported")


def _record_timings(report: dict, wall_s: Optional[float]) -> dict:
    """The report's stage timings as floats, with ``wall_s`` added when the report has none."""
    timings = {k: float(v) for k, v in (report.get("timings") or {}).items()}
    if wall_s is not None and "wall_s" not in timings:
        timings["wall_s"] = float(wall_s)
    return timings


def _pick_rows(picks_in: list[dict], objects: list[dict]) -> list[dict]:
    """The compact pick rows, each attributed to a true object: its own ground-truth name when
    it reached the grasp action, else the object nearest to its anchor (a selection that
    failed)."""
    picks: list[dict[str, Any]] = []
    for p in picks_in:
        name = p.get("object") or _nearest_object(objects, p.get("anchor"))
        ok = bool(p.get("success") and p.get("placed") and not p.get("failed_stage"))
        prow: dict[str, Any] = {
            "object": name, "anchor": [round(float(x), 4) for x in p.get("anchor") or []],
            "success": ok, "reported_success": bool(p.get("success")),
            "placed": bool(p.get("placed")), "lift_mm": round(1e3 * float(p.get("lift_m") or 0.0), 2)}
        if not ok:
            stage, msg = _pick_failure(p)
            prow.update(stage=stage, reason=reason_category(msg), message=msg)
        picks.append(prow)
    return picks


def _unpicked_cause(name: str, mine: list[dict], rough: dict, nadir: dict, report: dict,
                    error: Optional[str]) -> tuple[str, str, str]:
    """(stage, reason, message) of an object that was not picked into the tray: its first
    failed pick, else the scene's exception, the run's error, or how far perception got."""
    failed = [p for p in mine if not p["success"]]
    if failed:
        return failed[0]["stage"], failed[0]["reason"], failed[0]["message"]
    if error is not None:
        return "SCENE", exception_category(error), error
    if report.get("error"):
        return "PLANE", reason_category(report["error"]), report["error"]
    if name not in nadir and name not in rough:
        return "NOT_ATTEMPTED", "no pick (run ended early)", "no pick"
    if (nadir.get(name) or rough.get(name) or {}).get("tid") is None:
        return "DETECT", "not detected", "no track matched the object"
    return ("NOT_ATTEMPTED", "tracked but no pick aimed at it",
            "a track matched the object but no pick was attributed to it")


def _object_row(o: dict, picks: list[dict], rough: dict, nadir: dict, report: dict,
                error: Optional[str]) -> dict:
    """The outcome and estimate errors of one true object ``o`` of the scene."""
    name = o["name"]
    mine = [p for p in picks if p["object"] == name]
    nadir_row = _score_fields(nadir.get(name))
    row: dict[str, Any] = {"name": name, "kind": o["kind"],
           "width_mm": round(1e3 * min(o["size_m"][0], o["size_m"][1]), 2),
           "height_mm": round(1e3 * o["size_m"][2], 2),
           "picked": any(p["success"] for p in mine), "attempts": len(mine),
           "nadir": bool(nadir_row and nadir_row["quality"] == "NADIR"),
           "rough_errors": _score_fields(rough.get(name)), "nadir_errors": nadir_row}
    if not row["picked"]:
        stage, reason, msg = _unpicked_cause(name, mine, rough, nadir, report, error)
        row.update(stage=stage, reason=reason, message=msg)
    return row


def scene_record(index: int, seed: int, objects: list[dict], report: Optional[dict],
                 error: Optional[str] = None, wall_s: Optional[float] = None) -> SceneRecord:
    """The compact per-scene record: scene facts, per-object outcome and errors, picks.

    ``objects``: the scene's true objects (name, kind, size_m, position_m) from the spec;
    ``report``: what :func:`run_pipeline` returned (None when it raised); ``error``: the
    exception text when it raised.
    """
    report = report or {}
    timings = _record_timings(report, wall_s)
    rough = {r.get("object"): r for r in _score_rows(report.get("rough"))}
    nadir = {r.get("object"): r for r in _score_rows(report.get("scan"))}
    picks = _pick_rows(list(report.get("picks") or []), objects)
    scan = report.get("scan") or {}
    obj_rows = [_object_row(o, picks, rough, nadir, report, error) for o in objects]
    scan_summary = SceneScanSummary(completed=bool(scan.get("completed")), failure=scan.get("failure") or "",
                                    nadir=sum(r["nadir"] for r in obj_rows)) if scan else None
    return SceneRecord(index=index, seed=seed, objects=len(objects),
                       picks=sum(r["picked"] for r in obj_rows), error=error,
                       run_error=report.get("error"), scan=scan_summary, object_rows=obj_rows,
                       pick_rows=picks, timings=timings)


def scene_settings(overrides: tuple = (None, ())) -> "Settings":
    """The run's parameter sets with ``(config_file, sets)`` overrides (``--config``/``--set``)."""
    from ..app.sim_system import SECTIONS
    from ..settings import load_settings

    config_file, sets = overrides
    return load_settings(SECTIONS, config_file, list(sets))


def _object_count(seed: int, overrides: tuple = (None, ())) -> int:
    try:
        return len(_spec_objects(seed, overrides))
    except Exception:  # (the scene process will record the error)
        return 0


def _spec_objects(seed: int, overrides: tuple = (None, ())) -> list[dict]:
    from ..sim.scenes import random_scene

    spec = random_scene(seed, config=scene_settings(overrides).sim)
    return [{"name": o.name, "kind": o.kind, "size_m": [float(x) for x in o.size_m],
             "position_m": [float(x) for x in o.position_m]} for o in spec.objects]


def run_scene(index: int, seed: int, out_dir: str | Path, overrides: tuple = (None, ())) -> SceneRecord:
    """One benchmark scene in this process: never raises (errors become the record)."""
    t0 = time.perf_counter()
    objects: list[dict] = []
    try:
        objects = _spec_objects(seed, overrides)
        from ..app.run import run_pipeline

        out = Path(out_dir)
        report = run_pipeline(scene="random", seed=seed, out_dir=out, json_path=out / "report.json",
                              video=False, settings=scene_settings(overrides), mark_output=False,
                              snapshots=False)
        return scene_record(index, seed, objects, report.to_dict())
    except Exception as exc:  # any failure of the scene is a result, not a crash
        text = f"{type(exc).__name__}: {exc}"
        log.error("scene %d (seed %d) raised %s\n%s", index, seed, text, traceback.format_exc())
        return scene_record(index, seed, objects, None, error=text, wall_s=time.perf_counter() - t0)


def _run_task(task: tuple) -> SceneRecord:
    """Job function of the scheduler (in the spawned process): ``(index, seed, out_dir,
    overrides)`` → the scene record."""
    index, seed, out_dir, overrides = task
    return run_scene(index, seed, out_dir, overrides)


def _failed_task(task: tuple, error: str, wall_s: float) -> SceneRecord:
    index, seed, _out_dir, overrides = task
    return _failed_record(index, seed, error, wall_s, overrides)


def _postfix(records: list[SceneRecord]) -> str:
    return f"picked {sum(r['picks'] for r in records)}/{sum(r['objects'] for r in records)}"


#: How the scheduler runs the scenes of this benchmark.
SCENE_JOBS = JobSpec(run_fn=_run_task, failed_fn=_failed_task, postfix_fn=_postfix, desc="bench grasp",
                     tag="scene", jobs_per_worker=SIM_JOBS_PER_WORKER)


def _failed_record(index: int, seed: int, error: str, wall_s: float,
                   overrides: tuple = (None, ())) -> SceneRecord:
    try:
        objects = _spec_objects(seed, overrides)
    except Exception:  # the scene itself cannot be generated
        objects = []
    return scene_record(index, seed, objects, None, error=error, wall_s=wall_s)


# ------------------------------------------------------------------------------ entry point
def run_grasp_benchmark(scenes: int, seed: int = 0, workers: int = 1, json_path: str | Path | None = None,
                        out_dir: str | Path = "out/bench_grasp", progress: bool = True,
                        scene_timeout_s: float = DEFAULT_SCENE_TIMEOUT_S,
                        overrides: tuple = (None, ()), backend: str = "local",
                        address: Optional[str] = None,
                        jobs_per_worker: int = SIM_JOBS_PER_WORKER) -> GraspBenchResult:
    """Run the benchmark; write the JSON (``json_path``), ``OUT/summary.md`` and plots.

    ``overrides``: ``(config_file, [name=value, ...])`` applied to every scene's settings;
    ``backend``: ``"local"`` (spawned processes) or ``"ray"`` (``address``: a cluster's, else a
    local Ray instance with ``workers`` CPUs). ``status``: complete, partial, failed (no scene
    ran to its end) or interrupted (Ctrl-C / SIGTERM at any phase — generating the scenes,
    simulating, writing: the JSON says so, then KeyboardInterrupt is raised)."""
    if scenes < 1:
        raise ValueError(f"scenes must be >= 1, got {scenes}")
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    out = check_writable_dir(Path(out_dir), "output folder (--out)")
    scene_settings(overrides)  # bad overrides fail here, before any scene starts
    if json_path is not None:
        check_writable(json_path, "benchmark JSON (--json)")
    workers_used = min(workers, scenes)
    if workers_used > (os.cpu_count() or 1):
        log.warning("%d workers on %s cores: scenes will compete for CPU", workers_used, os.cpu_count())
    t0 = time.perf_counter()
    records, interrupted, phase = [], False, "generating the scenes"
    with output_claim(out, "bench grasp") as claim, sigterm_as_interrupt():
        try:
            tasks = _scene_tasks(scenes, seed, out, overrides)
            phase = "simulating"
            jobs = replace(SCENE_JOBS, jobs_per_worker=int(jobs_per_worker))
            records, interrupted = run_jobs([(*t, overrides) for t in tasks], jobs, workers_used,
                                            scene_timeout_s, progress, backend, address)
        except KeyboardInterrupt:
            interrupted = True
        status, note = _status(records, interrupted)
        result = replace(aggregate(records, seed, workers_used, time.perf_counter() - t0),
                         workers_requested=int(workers), cpu_count=os.cpu_count(), backend=backend,
                         mujoco_gl=worker_env()["MUJOCO_GL"], status=status, status_note=note,
                         scenes_finished=len(records), warnings=(claim.warning,) if claim.warning else (),
                         interrupted_while=phase if interrupted else None)
        result = _write_results(result, out, json_path)
    if result.status == "interrupted":
        raise KeyboardInterrupt(f"bench grasp interrupted while {result.interrupted_while} after "
                                f"{len(records)} of {scenes} scenes (written to {json_path})")
    return result


def _scene_tasks(scenes: int, seed: int, out: Path, overrides: tuple) -> list[tuple]:
    """(index, scene seed, folder) per scene, longest first: the time of a scene grows with its
    objects, so the last scenes to finish are short ones and W workers stay busy to the end
    (results are sorted by index afterwards)."""
    tasks = [(i, scene_seed(seed, i), str(out / "scenes" / f"scene_{i:03d}_seed_{scene_seed(seed, i)}"))
             for i in range(scenes)]
    tasks.sort(key=lambda t: (-_object_count(t[1], overrides), t[0]))
    return tasks


def _status(records: list[SceneRecord], interrupted: bool) -> tuple[str, str]:
    """(status, note): ``interrupted``; ``failed`` when every scene raised, timed out or lost its
    process; ``partial`` when some did; else ``complete``."""
    broken = [r for r in records if r.get("error")]
    counts: dict = {}
    for r in broken:
        cat = exception_category(r["error"])
        counts[cat] = counts.get(cat, 0) + 1
    why = ", ".join(f"{k} x{v}" for k, v in sorted(counts.items()))
    note = f"{len(broken)} of {len(records)} scenes did not run to their end ({why})" if broken else ""
    if interrupted:
        return "interrupted", note
    if records and len(broken) == len(records):
        return "failed", note
    return ("partial" if broken else "complete"), note


def _write_results(result: GraspBenchResult, out: Path, json_path) -> GraspBenchResult:
    """The JSON, the plots and ``summary.md``, safe against a signal (:mod:`.results_files`)."""
    from .grasp_plots import write_plots, write_summary
    from .results_files import write_results

    return write_results(result, out, json_path, write_plots, write_summary)


def _median_text(s) -> str:
    return "n/a" if s.median is None else f"{s.median:.2f}"


def headline(result: GraspBenchResult) -> str:
    """A few lines for the terminal."""
    acc, f = result.accuracy, _median_text
    lines = [f"STATUS {result.status.upper()}: {result.status_note or 'interrupted'}"
             ] if result.status != "complete" else []
    lines += [
        f"scenes {result.scenes} ({result.scenes_failed} raised), objects {result.objects}, "
        f"picked {result.picked} -> success {100 * (result.success_rate or 0):.1f} %",
        f"scan: {100 * (result.scan_success_rate or 0):.1f} % of objects NADIR",
        f"NADIR median errors: centre {f(acc.center_mm)} mm, width {f(acc.width_mm)} mm, "
        f"height {f(acc.height_mm)} mm, yaw {f(acc.yaw_deg)} deg",
        f"time per scene: median {result.time_per_scene_s.median} s; wall {result.wall_time_s:.1f} s "
        f"with {result.workers} worker(s) -> {result.scenes_per_minute} scenes/min",
        f"real-time factor (simulated s per wall s): run {result.real_time_factor.run}, "
        f"pick loop {result.real_time_factor.pick_loop}; per CPU s {result.cpu_real_time_factor}",
        f"CPU per scene: median {result.cpu_time_per_scene_s.median} s -> "
        f"{result.scenes_per_minute_idle_cores} scenes/min on {result.workers} idle core(s)",
    ]
    for stage, f_ in result.failures_by_stage.items():
        lines.append(f"  failed at {stage}: {f_.count} ({', '.join(f'{k} x{v}' for k, v in f_.reasons.items())})")
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines)
