"""Clutter benchmark: the VGN/GIGA packed and pile protocols with the whole product.

``grasp-pipeline bench clutter --protocol packed|pile|sparse --objects builtin|DIR --rounds N
--seed K [K ...] --workers W --json PATH --out DIR``

Each round (:mod:`.clutter_round`) builds a scene, takes the rough view, scans, then picks one
object at a time into the tray, looking again after each attempt; it ends when the table is
clear (ground truth), when no graspable object is proposed, or after 2 consecutive failed
attempts (VGN's rule; ``declutter.max_consecutive_failures``). Rounds run in spawned worker
processes (:mod:`.scheduler`); round ``i`` of seed ``K`` uses the scene seed
``scene_seed(K, i)``, so one round is reproduced with ``grasp-pipeline run --scene <protocol>
--seed <round seed> --objects ... --declutter``.

Metrics as VGN/GIGA define them: **grasp success rate** GSR = successful picks / attempts and
**declutter rate** DR = successful picks / objects placed, per seed, pooled over all rounds,
and mean ± std over the seeds (population std). A pick is successful when the object ends in
the tray (ground truth). Every attempt counts, also one that never moved the arm (a SELECT or
PRE_GRASP failure: the product chose that object and could not pick it);
``gsr_executed`` counts only attempts whose arm reached APPROACH. Also: failures by stage and
reason, success by object model, time per attempt and per round, segmentation quality at the
scan (:mod:`grasp_pipeline.evaluation.segmentation`), how rounds ended.

The gap to geometry (``grasp_bound``): every object of every round is labelled from its true
shape and settled pose — graspable by the 80 mm hand from straight above, with an approach
tilted up to 60°, from some side, or not at all (:mod:`grasp_pipeline.evaluation.grasp_bound`,
``config/grasp_bound.yaml``) — and given what happened to it (picked, attempted and failed,
never proposed and why, ...: :mod:`grasp_pipeline.evaluation.object_outcomes`); the JSON holds
the label counts, the declutter rate against each bound (``dr_top_down``, ``dr_tilted``,
``dr_any_side``: objects picked among those graspable under it / those graspable) and the
outcomes per label. Each round record lists its objects in ``object_outcomes``.

The result is a :class:`~.clutter_result.ClutterBenchResult`; deterministic for a seed
(rounds sorted; only the fields in :data:`~.clutter_result.TIMING_KEYS` differ).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import os
import time
from pathlib import Path
from typing import Any, Optional

from ..app.run_command import sigterm_as_interrupt
from ..exceptions import InputError
from ..report.output_lock import output_claim
from ..report.serialize import check_writable, check_writable_dir
from .clutter_result import ClutterBenchResult, ObjectSuccess, RatePair, RoundRecord, SeedCounts
from .clutter_round import clutter_settings, run_round
from .figures import failures_by_stage, rate, stats
from .jobs import SIM_JOBS_PER_WORKER, JobSpec, worker_env
from .scheduler import run_jobs
from .seeds import scene_seed

log = logging.getLogger(__name__)

PROTOCOLS = ("packed", "pile", "sparse")
#: Stages at or after which the arm moved towards the object.
EXECUTED_STAGES = ("APPROACH", "CLOSE", "LIFT", "DONE", "PLACE", "VERIFY")


def _counts(rows: list[RoundRecord]) -> dict[str, Any]:
    """Rounds, objects placed, attempts, successes, GSR, DR of some round records (the count
    fields of :class:`~.clutter_result.SeedCounts` and of the result)."""
    placed = sum(r["objects_placed"] for r in rows)
    attempts = [a for r in rows for a in r["attempts"]]
    ok = sum(a["success"] for a in attempts)
    executed = [a for a in attempts if a["success"] or a.get("stage") in EXECUTED_STAGES]
    return {"rounds": len(rows), "objects_placed": placed, "attempts": len(attempts),
            "successes": ok, "gsr": rate(ok, len(attempts)), "dr": rate(ok, placed),
            "attempts_executed": len(executed), "gsr_executed": rate(ok, len(executed))}


def _mean_std(values: list) -> tuple[Optional[float], Optional[float]]:
    """Mean and population std of the values that are not None (None, None without any)."""
    v = [float(x) for x in values if x is not None]
    if not v:
        return None, None
    m = sum(v) / len(v)
    return round(m, 4), round(math.sqrt(sum((x - m) ** 2 for x in v) / len(v)), 4)


def _over_seeds(per_seed: list[SeedCounts]) -> tuple[RatePair, RatePair]:
    """(mean, std) of GSR and DR over the seeds."""
    gsr = _mean_std([s.gsr for s in per_seed])
    dr = _mean_std([s.dr for s in per_seed])
    return RatePair(gsr[0], dr[0]), RatePair(gsr[1], dr[1])


def _success_by_object(rows: list[RoundRecord]) -> dict[str, ObjectSuccess]:
    """Per object model: how many were placed, attempted, picked."""
    counts: dict[str, list[int]] = {}
    for r in rows:
        for model in r["models"].values():
            counts.setdefault(model, [0, 0, 0])[0] += 1
        for a in r["attempts"]:
            c = counts.setdefault(a["model"] or "unknown", [0, 0, 0])
            c[1] += 1
            c[2] += int(a["success"])
    return {m: ObjectSuccess(placed=p, attempts=n, picked=k, success_rate=rate(k, n))
            for m, (p, n, k) in sorted(counts.items())}


def _segmentation(rows: list[RoundRecord]) -> dict:
    from ..evaluation.segmentation import ObjectSegmentation, summarize

    scores = [ObjectSegmentation(**s) for r in rows for s in r["segmentation"]]
    return summarize(scores, sum(r["objects_placed"] for r in rows))


def _grasp_bound(rows: list[RoundRecord]) -> dict:
    from ..evaluation.object_outcomes import summarize

    return summarize([o for r in rows for o in r.get("object_outcomes") or []])


def _end_reasons(rows: list[RoundRecord]) -> dict[str, int]:
    out: dict = {}
    for r in rows:
        key = r["end_reason"].split(" (")[0] or "unspecified"
        out[key] = out.get(key, 0) + 1
    return dict(sorted(out.items(), key=lambda kv: (-kv[1], kv[0])))


def aggregate(rows: list[RoundRecord], protocol: str, objects: str, seeds: list[int], workers: int,
              wall_time_s: float, bound_config=None) -> ClutterBenchResult:
    """The benchmark's figures from the round records (a pure function); ``bound_config``: the
    ``grasp_bound`` parameters, written with the bound's figures. The run's own facts (status,
    backend, ...) keep their defaults: the caller replaces them."""
    rows = sorted(rows, key=lambda r: r["index"])
    per_seed = [SeedCounts(seed=s, **_counts([r for r in rows if r["bench_seed"] == s])) for s in seeds]
    attempts = [a for r in rows for a in r["attempts"]]
    mean, std = _over_seeds(per_seed)
    bound = _grasp_bound(rows)
    if bound_config is not None:
        bound["config"] = dataclasses.asdict(bound_config)
    return ClutterBenchResult(
        protocol=protocol, objects=objects, seed_list=tuple(seeds), **_counts(rows),
        seeds=tuple(per_seed), mean=mean, std=std,
        rounds_failed=sum(1 for r in rows if r.get("error")),
        end_reasons=_end_reasons(rows),
        failures_by_stage=failures_by_stage(attempts, ok_key="success"),
        success_by_object=_success_by_object(rows),
        segmentation=_segmentation(rows), grasp_bound=bound,
        time_per_attempt_s=stats(a["wall_s"] for a in attempts),
        time_per_round_s=stats(r["timings"].get("wall_s") for r in rows),
        wall_time_s=round(float(wall_time_s), 3),
        rounds_per_hour=None if wall_time_s <= 0 else round(3600.0 * len(rows) / wall_time_s, 3),
        workers=int(workers), round_rows=tuple(rows))


def _failed_round(task: tuple, error: str, wall_s: float) -> RoundRecord:
    """The record of a round whose process died or timed out (its objects still count)."""
    from .clutter_round import round_record, round_scene

    t = task[1]
    spec = bound_config = None
    try:
        settings = clutter_settings(t["overrides"])
        bound_config = settings.grasp_bound
        spec = round_scene(t["protocol"], t["seed"], t["objects"], settings)
    except Exception:  # the scene itself cannot be generated
        pass
    public = {k: v for k, v in t.items() if k not in ("overrides", "out_dir")}
    return round_record(public, spec, None, None, error, wall_s, bound_config)


def _run_task(task: tuple) -> RoundRecord:
    return run_round(task[1])


def _postfix(records: list[RoundRecord]) -> str:
    ok = sum(r["successes"] for r in records)
    return f"GSR {ok}/{sum(len(r['attempts']) for r in records)}, DR {ok}/{sum(r['objects_placed'] for r in records)}"


ROUND_JOBS = JobSpec(run_fn=_run_task, failed_fn=_failed_round, postfix_fn=_postfix,
                     desc="bench clutter", tag="round", jobs_per_worker=SIM_JOBS_PER_WORKER)


def _tasks(protocol: str, objects: str, rounds: int, seeds: list[int], out: Path,
           overrides: tuple, rerun_dir: Optional[Path] = None) -> list[tuple]:
    """One task per round; ``recording``: the round's ``.rrd`` in ``rerun_dir`` (named like
    its folder) or None."""
    tasks, index = [], 0
    for s in seeds:
        for i in range(rounds):
            seed = scene_seed(s, i)
            name = f"seed_{s}_round_{i:03d}_scene_{seed}"
            task = {"index": index, "bench_seed": int(s), "round": i, "seed": seed,
                    "protocol": protocol, "objects": str(objects), "overrides": overrides,
                    "out_dir": str(out / "rounds" / name),
                    "recording": None if rerun_dir is None else str(Path(rerun_dir) / f"{name}.rrd")}
            tasks.append((index, task))
            index += 1
    return tasks


def _check_inputs(protocol: str, rounds: int, seeds: list[int], workers: int, overrides: tuple):
    """The run's settings; bad arguments or overrides fail here, before any round starts (the
    settings are read once: a configuration edited during the run cannot break its summary)."""
    if protocol not in PROTOCOLS:
        raise InputError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if rounds < 1 or workers < 1 or not seeds:
        raise InputError("rounds and workers must be >= 1 and at least one seed given")
    return clutter_settings(overrides)


def _check_objects(protocol: str, objects: str) -> dict:
    """Load the object set once here (a bad folder fails before any round: MeshError naming the
    file); its models' notes and warnings (logged) for the JSON."""
    if protocol == "sparse":
        return {}
    from ..objects.catalog import model_notes, object_set

    return model_notes(object_set(objects))


def run_status(rows: list[RoundRecord], interrupted: bool) -> tuple[str, str]:
    """(status, note): ``interrupted``; ``failed`` when no round ran to its end (each raised,
    timed out or its process died); ``partial`` when some did not; else ``complete``."""
    broken = [r for r in rows if r.get("error_category")]
    counts: dict = {}
    for r in broken:
        counts[r["error_category"]] = counts.get(r["error_category"], 0) + 1
    why = ", ".join(f"{k} x{v}" for k, v in sorted(counts.items()))
    note = f"{len(broken)} of {len(rows)} rounds did not run to their end ({why})" if broken else ""
    if interrupted:
        return "interrupted", note
    if rows and len(broken) == len(rows):
        return "failed", note
    return ("partial" if broken else "complete"), note


def run_clutter_benchmark(protocol: str = "packed", objects: str = "builtin", rounds: int = 20,
                          seeds: tuple = (0,), workers: int = 1, json_path=None,
                          out_dir: str | Path = "out/bench_clutter", progress: bool = True,
                          round_timeout_s: float = 3600.0, overrides: tuple = (None, ()),
                          backend: str = "local", address: Optional[str] = None,
                          rerun_dir: str | Path | None = None,
                          jobs_per_worker: int = SIM_JOBS_PER_WORKER) -> ClutterBenchResult:
    """Run the benchmark; write the JSON (``json_path``), ``OUT/summary.md`` and plots.
    ``backend``: ``"local"`` (spawned processes) or ``"ray"`` (``address``: a cluster's);
    ``rerun_dir``: also one Rerun recording per round there (``<round folder name>.rrd``).
    ``jobs_per_worker``: rounds a local worker process runs one after the other (each as in a
    fresh process; 1: a new process per round).
    ``status``: complete, partial, failed (no round ran to its end) or interrupted (Ctrl-C /
    SIGTERM at any phase — loading the objects, simulating, writing: the JSON says so, then
    KeyboardInterrupt is raised)."""
    seeds = [int(s) for s in seeds]
    bound_config = _check_inputs(protocol, rounds, seeds, workers, overrides).grasp_bound
    out = check_writable_dir(Path(out_dir), "output folder (--out)")
    if json_path is not None:
        check_writable(json_path, "benchmark JSON (--json)")
    if rerun_dir is not None:
        from ..report.rerun_recorder import import_rerun

        import_rerun()
        rerun_dir = check_writable_dir(Path(rerun_dir), "Rerun recordings folder (--rerun)")
    tasks = _tasks(protocol, objects, rounds, seeds, out, overrides, rerun_dir)
    t0 = time.perf_counter()
    rows, interrupted, notes, phase = [], False, {}, "loading the objects"
    with output_claim(out, "bench clutter") as claim, sigterm_as_interrupt():
        try:
            notes = _check_objects(protocol, objects)
            phase = "simulating"
            jobs = dataclasses.replace(ROUND_JOBS, jobs_per_worker=int(jobs_per_worker))
            rows, interrupted = run_jobs(tasks, jobs, min(workers, len(tasks)), round_timeout_s,
                                         progress, backend, address)
        except KeyboardInterrupt:
            interrupted = True
        status, note = run_status(rows, interrupted)
        result = dataclasses.replace(
            aggregate(rows, protocol, str(objects), seeds, min(workers, len(tasks)), time.perf_counter() - t0,
                      bound_config),
            status=status, status_note=note, rounds_requested=len(tasks), cpu_count=os.cpu_count(),
            mujoco_gl=worker_env()["MUJOCO_GL"], out_dir=str(out), backend=backend, object_notes=notes,
            warnings=(claim.warning,) if claim.warning else (), interrupted_while=phase if interrupted else None)
        result = _write_results(result, out, json_path)
    if result.status == "interrupted":
        raise KeyboardInterrupt(f"bench clutter interrupted while {result.interrupted_while} after "
                                f"{len(rows)} of {len(tasks)} rounds (written to {json_path})")
    return result


def _write_results(result: ClutterBenchResult, out: Path, json_path) -> ClutterBenchResult:
    """The JSON, the plots and ``summary.md``, safe against a signal (:mod:`.results_files`)."""
    from .clutter_plots import write_plots, write_summary
    from .results_files import write_results

    return write_results(result, out, json_path, write_plots, write_summary)


def _pct(v: Optional[float]) -> str:
    return "n/a" if v is None else f"{100 * v:.1f} %"


def headline(result: ClutterBenchResult) -> str:
    """A few lines for the terminal."""
    pct, seg = _pct, result.segmentation
    lines = [f"STATUS {result.status.upper()}: {result.status_note or 'interrupted'}"
             ] if result.status != "complete" else []
    lines += [
        f"{result.protocol} / {result.objects}: {result.rounds} rounds, "
        f"{result.objects_placed} objects, {result.attempts} attempts, {result.successes} picked",
        f"GSR {pct(result.gsr)} (mean {pct(result.mean.gsr)} +- {pct(result.std.gsr)} over "
        f"{len(result.seeds)} seed(s)), DR {pct(result.dr)}",
        f"segmentation at the scan: {pct(seg['correct_rate'])} correct, {seg['merged']} merged, "
        f"{seg['split']} split, {seg['missed']} missed",
        f"time per attempt: median {result.time_per_attempt_s.median} s; per round: median "
        f"{result.time_per_round_s.median} s; wall {result.wall_time_s:.0f} s",
        f"rounds ended: {', '.join(f'{k} x{v}' for k, v in result.end_reasons.items())}",
    ]
    b = result.grasp_bound or {}
    if b.get("objects"):
        lines.append(f"geometric bound: graspable from above {pct(b['graspable_fraction']['top_down'])}, "
                     f"tilted {pct(b['graspable_fraction']['tilted'])}, any side "
                     f"{pct(b['graspable_fraction']['any_side'])}; DR against them "
                     f"{pct(b['dr_top_down'])} / {pct(b['dr_tilted'])} / {pct(b['dr_any_side'])}")
    for stage, f in result.failures_by_stage.items():
        lines.append(f"  failed at {stage}: {f.count} ({', '.join(f'{k} x{v}' for k, v in f.reasons.items())})")
    warned = [name for name, n in result.object_notes.items() if n["warnings"]]
    if warned:
        lines.append(f"object warnings ({len(warned)} models): {', '.join(warned[:8])}"
                     + (" ..." if len(warned) > 8 else "") + " (see object_notes in the JSON)")
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines)
