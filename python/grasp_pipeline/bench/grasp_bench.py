"""Grasp benchmark: the whole product (rough view → scan → pick every object into the tray) on
N seeded random scenes, with ground-truth scoring.

``grasp-pipeline bench grasp --scenes N --seed K --workers W --json PATH --out DIR``

Each scene is exactly one ``run_pipeline(scene="random", seed=<scene seed>, video=False)``
call. The scene seed is derived from ``K`` and the scene index by :func:`scene_seed`, so a
single scene is reproduced with ``grasp-pipeline run --scene random --seed <scene seed>``.

Processes: every scene runs in its **own** freshly spawned process (``multiprocessing``
"spawn" start method — MuJoCo's EGL/OSMesa contexts must not be forked), at most ``W`` at a
time. A fresh process per scene matters for determinism: OMPL's random generator is seeded
once per process, so a worker that ran an earlier scene would plan the next one from a
different random state, and the results would depend on the scheduling. Children inherit
``MUJOCO_GL`` (the parent's choice, see :mod:`grasp_pipeline.sim.gl_backend`) and
``PYTHONPATH``, and are limited to one thread each (``OMP_NUM_THREADS=1`` and the BLAS
equivalents), so ``W`` workers use ``W`` cores. A scene that raises is recorded as a failed
scene with its error; a child that dies (signal, segfault) or exceeds ``scene_timeout_s`` is
recorded the same way, and the benchmark goes on.

The result is deterministic for a seed as far as the product is (scenes sorted by index; the
JSON is the same apart from the timing fields listed in :data:`TIMING_KEYS`). Aggregation
(:func:`aggregate`) works on the per-scene records only and is a pure function.

Scoring uses ground truth (the scene spec and ``report[...]["scores"]``): evaluation code only.
"""

from __future__ import annotations

import logging
import math
import os
import re
import time
import traceback
from pathlib import Path
from typing import Any, Iterable, Optional

from ..app.run_command import sigterm_as_interrupt
from ..report.output_lock import output_claim
from ..report.serialize import check_writable, check_writable_dir
from ..results import SceneRecord, SceneScanSummary
from .jobs import JobSpec, worker_env
from .scheduler import run_jobs

log = logging.getLogger(__name__)

#: Wall-clock limit of one scene [s] (a hung scene is killed and recorded as failed).
DEFAULT_SCENE_TIMEOUT_S = 1800.0
#: Object kinds whose footprint defines a yaw (cylinders are round).
YAW_KINDS = ("cube", "cuboid")
#: Width bins [mm] for "success by size" (true narrow horizontal side).
SIZE_BINS_MM = (30.0, 40.0, 50.0, 60.0, 70.0)
#: Accuracy metrics: JSON name → key in a score row.
ACCURACY_METRICS = {"center_mm": "center_err_mm", "width_mm": "width_err_mm",
                    "height_mm": "height_err_mm", "yaw_deg": "yaw_err_deg",
                    "pca_tilt_deg": "pca_tilt_deg"}
#: Top-level JSON keys (and per-scene keys) that hold timings — the only fields allowed to
#: differ between two runs with the same seed.
TIMING_KEYS = ("wall_time_s", "scenes_per_minute", "time_per_scene_s", "time_per_object_s",
               "time_per_stage_s", "timings", "wall_s", "real_time_factor", "cpu_time_per_scene_s",
               "cpu_real_time_factor", "scenes_per_minute_idle_cores")
#: The issue's targets: name → (JSON path, comparison, value).
TARGETS = {
    "pick success": (("success_rate",), ">=", 0.95),
    "NADIR centre median [mm]": (("accuracy", "center_mm", "median"), "<=", 2.0),
    "NADIR width median [mm]": (("accuracy", "width_mm", "median"), "<=", 1.5),
    "NADIR height median [mm]": (("accuracy", "height_mm", "median"), "<=", 1.5),
    "NADIR yaw median [deg]": (("accuracy", "yaw_deg", "median"), "<=", 1.5),
}
#: Pick stages in pipeline order (for tables and plots).
STAGE_ORDER = ("SCENE", "PLANE", "DETECT", "NOT_ATTEMPTED", "SELECT", "GRASP", "PRE_GRASP",
               "APPROACH", "CLOSE", "LIFT", "DONE", "PLACE", "VERIFY")


# ------------------------------------------------------------------------------ seeds
def scene_seed(seed: int, index: int) -> int:
    """The random-scene seed of scene ``index`` of a benchmark with seed ``seed``.

    Derived with numpy's ``SeedSequence`` (a stable, documented hash), so benchmarks with
    different seeds draw independent scenes; a non-negative 31-bit integer.
    """
    import numpy as np

    state = np.random.SeedSequence(entropy=int(seed), spawn_key=(int(index),)).generate_state(1, np.uint32)
    return int(state[0] >> 1)


# ------------------------------------------------------------------------------ reasons
_STAGE_PREFIX = re.compile(r"^[A-Z_]+ failed:\s*")


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def reason_category(message: str, max_len: int = 80) -> str:
    """A short category of a failure message, the same for every instance of one cause: the
    ``STAGE failed:`` prefix removed; the text before the first ``:`` (the details follow it;
    when that head is only one or two words, like "execution stopped", the next part too);
    parenthesised/bracketed details dropped; every number replaced by ``N``.

    ``"CLOSE failed: fingers stalled at 1.2 mm but touch no object"`` →
    ``"fingers stalled at N mm but touch no object"``;
    ``"PLACE failed: execution stopped: unexpected robot contact [('a', 'b')]; the arm …"`` →
    ``"execution stopped: unexpected robot contact"``.
    """
    text = _STAGE_PREFIX.sub("", str(message or "").strip())
    text = text.split(" | ", 1)[0]
    text = re.sub(r"\([^()]*\)|\[[^\[\]]*\]", "", text)  # (details), [details]
    parts = [p.strip() for p in re.split(r":\s", text)]
    head = parts[0]
    if len(head.split()) <= 2 and len(parts) > 1:
        head = f"{head}: {parts[1]}"
    head = head.split(";", 1)[0]
    head = _NUMBER.sub("N", head)
    head = re.sub(r"\s+", " ", head).strip(" ,;.:")
    if len(head) > max_len:
        head = head[:max_len].rstrip() + "…"
    return head or "unspecified"


def exception_category(exc_text: str) -> str:
    """``"ValueError: bad thing 3"`` → ``"ValueError"``."""
    head = str(exc_text or "").split(":", 1)[0].strip()
    return head or "unspecified"


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


def scene_settings(overrides: tuple = (None, ())):
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


def run_scene(index: int, seed: int, out_dir: str | Path, overrides: tuple = (None, ())) -> dict:
    """One benchmark scene in this process: never raises (errors become the record)."""
    t0 = time.perf_counter()
    objects: list[dict] = []
    try:
        objects = _spec_objects(seed, overrides)
        from ..app.run import run_pipeline

        out = Path(out_dir)
        report = run_pipeline(scene="random", seed=seed, out_dir=out, json_path=out / "report.json",
                              video=False, settings=scene_settings(overrides), mark_output=False)
        return scene_record(index, seed, objects, report.to_dict())
    except Exception as exc:  # any failure of the scene is a result, not a crash
        text = f"{type(exc).__name__}: {exc}"
        log.error("scene %d (seed %d) raised %s\n%s", index, seed, text, traceback.format_exc())
        return scene_record(index, seed, objects, None, error=text, wall_s=time.perf_counter() - t0)


def _run_task(task: tuple) -> dict:
    """Job function of the scheduler (in the spawned process): ``(index, seed, out_dir,
    overrides)`` → the scene record."""
    index, seed, out_dir, overrides = task
    return run_scene(index, seed, out_dir, overrides)


def _failed_task(task: tuple, error: str, wall_s: float) -> dict:
    index, seed, _out_dir, overrides = task
    return _failed_record(index, seed, error, wall_s, overrides)


def _postfix(records: list[dict]) -> str:
    return f"picked {sum(r['picks'] for r in records)}/{sum(r['objects'] for r in records)}"


#: How the scheduler runs the scenes of this benchmark.
SCENE_JOBS = JobSpec(run_fn=_run_task, failed_fn=_failed_task, postfix_fn=_postfix, desc="bench grasp",
                     tag="scene")


def _failed_record(index: int, seed: int, error: str, wall_s: float,
                   overrides: tuple = (None, ())) -> dict:
    try:
        objects = _spec_objects(seed, overrides)
    except Exception:  # the scene itself cannot be generated
        objects = []
    return scene_record(index, seed, objects, None, error=error, wall_s=wall_s)


# ------------------------------------------------------------------------------ aggregation
def _finite(values: Iterable) -> list[float]:
    return [float(v) for v in values if v is not None and math.isfinite(float(v))]


def _percentile(values: list[float], q: float) -> Optional[float]:
    if not values:
        return None
    import numpy as np

    return float(np.percentile(np.asarray(values, float), q))


def stats(values: Iterable) -> dict:
    """``{"n", "median", "p90", "mean", "max"}`` of the finite values (None when empty — JSON
    null, never NaN)."""
    v = _finite(values)
    r = lambda x: None if x is None else round(x, 4)  # noqa: E731
    return {"n": len(v), "median": r(_percentile(v, 50)), "p90": r(_percentile(v, 90)),
            "mean": r(sum(v) / len(v)) if v else None, "max": r(max(v)) if v else None}


def _rate(num: int, den: int) -> Optional[float]:
    return None if den == 0 else round(num / den, 4)


def _accuracy(rows: list[dict], key: str, nadir_only: bool) -> dict:
    """Error statistics over the objects' ``key`` errors (``rough_errors``/``nadir_errors``);
    ``nadir_only``: only objects whose estimate is NADIR; yaw only for cubes and cuboids."""
    sel = [(r, r[key]) for r in rows if r.get(key)]
    if nadir_only:
        sel = [(r, e) for r, e in sel if e.get("quality") == "NADIR"]
    out: dict[str, Any] = {"objects": len(sel)}
    for name, field in ACCURACY_METRICS.items():
        out[name] = stats(e[field] for r, e in sel if name != "yaw_deg" or r["kind"] in YAW_KINDS)
    return out


def _size_bin(width_mm: float) -> str:
    edges = SIZE_BINS_MM
    for lo, hi in zip(edges[:-1], edges[1:]):
        if width_mm < hi:
            return f"{lo:.0f}-{hi:.0f}"
    return f"{edges[-2]:.0f}-{edges[-1]:.0f}"


def _group_success(rows: list[dict], key) -> dict:
    groups: dict = {}
    for r in rows:
        g = groups.setdefault(key(r), {"objects": 0, "picked": 0})
        g["objects"] += 1
        g["picked"] += int(r["picked"])
    for g in groups.values():
        g["success_rate"] = _rate(g["picked"], g["objects"])
    return dict(sorted(groups.items()))


def failures_by_stage(objs: list[dict], ok_key: str = "picked") -> dict:
    """The rows whose ``ok_key`` is false (objects not picked, failed attempts), by stage
    (pipeline order) and reason (most frequent first)."""
    failures: dict = {}
    for o in objs:
        if o[ok_key]:
            continue
        f = failures.setdefault(o["stage"], {"count": 0, "reasons": {}})
        f["count"] += 1
        f["reasons"][o["reason"]] = f["reasons"].get(o["reason"], 0) + 1
    order = {s: i for i, s in enumerate(STAGE_ORDER)}
    return {s: {"count": failures[s]["count"], "reasons": dict(sorted(
        failures[s]["reasons"].items(), key=lambda kv: (-kv[1], kv[0])))}
        for s in sorted(failures, key=lambda s: (order.get(s, len(order)), s))}


def _scan_failures(records: list[dict]) -> dict:
    """Scenes by scan failure category (the scan's own message; the objects may still be
    picked)."""
    scan_fail: dict = {}
    for r in records:
        msg = (r.get("scan") or {}).get("failure")
        if msg:
            cat = reason_category(msg)
            scan_fail[cat] = scan_fail.get(cat, 0) + 1
    return dict(sorted(scan_fail.items()))


def _scan_improvement(objs: list[dict]) -> dict:
    """The improvement the scan buys: the same objects, oblique (rough view) vs NADIR."""
    paired = [o for o in objs if o.get("rough_errors") and o.get("nadir_errors")
              and o["nadir_errors"].get("quality") == "NADIR"]
    improvement: dict[str, Any] = {"objects": len(paired)}
    for name, field in ACCURACY_METRICS.items():
        sel = [o for o in paired if name != "yaw_deg" or o["kind"] in YAW_KINDS]
        improvement[name] = {"oblique_median": stats(o["rough_errors"][field] for o in sel)["median"],
                             "nadir_median": stats(o["nadir_errors"][field] for o in sel)["median"],
                             "n": len(sel)}
    return improvement


def _outcome_figures(records: list[dict], objs: list[dict]) -> dict:
    """Scene, object and pick counts and rates, and the failures by stage."""
    n_obj = len(objs)
    n_pick = sum(o["picked"] for o in objs)
    return {
        "scenes": len(records),
        "scenes_failed": sum(1 for r in records if r.get("error")),
        "objects": n_obj,
        "picked": n_pick,
        "success_rate": _rate(n_pick, n_obj),
        "reported_success_rate": _rate(sum(1 for r in records for p in r["pick_rows"]
                                           if p["reported_success"]), sum(len(r["pick_rows"]) for r in records)),
        "false_successes": sum(1 for r in records for p in r["pick_rows"]
                               if p["reported_success"] and not p["success"]),
        "failures": n_obj - n_pick,
        "failures_by_stage": failures_by_stage(objs),
    }


def _perception_figures(records: list[dict], objs: list[dict]) -> dict:
    """Scan success, estimate accuracy (NADIR and oblique) and what the scan improves."""
    return {
        "scan_success_rate": _rate(sum(o["nadir"] for o in objs), len(objs)),
        "scan_failures": _scan_failures(records),
        "accuracy": _accuracy(objs, "nadir_errors", nadir_only=True),
        "accuracy_oblique": _accuracy(objs, "rough_errors", nadir_only=False),
        "scan_improvement": _scan_improvement(objs),
    }


def _success_groups(records: list[dict], objs: list[dict]) -> dict:
    """Pick success by object kind, by width bin and by the number of objects in the scene."""
    return {
        "success_by_kind": _group_success(objs, lambda o: o["kind"]),
        "success_by_width_mm": _group_success(objs, lambda o: _size_bin(o["width_mm"])),
        "success_by_scene_objects": _group_success(
            [dict(o, n=r["objects"]) for r in records for o in r["object_rows"]], lambda o: str(o["n"])),
    }


def _real_time_factors(records: list[dict]) -> dict:
    """Simulated seconds per wall second over all scenes (sums, not a mean of ratios): of the
    whole run (``run``) and of the pick loop alone (``pick_loop``); None without data."""
    out: dict[str, Optional[float]] = {}
    for name, sim_key, wall_key in (("run", "run_sim_s", "wall_s"), ("pick_loop", "picks_sim_s", "picks_s")):
        rows = [r["timings"] for r in records if r["timings"].get(sim_key) is not None
                and r["timings"].get(wall_key)]
        wall = sum(t[wall_key] for t in rows)
        out[name] = round(sum(t[sim_key] for t in rows) / wall, 3) if wall > 0 else None
    return out


def _is_wall_timing(key: str) -> bool:
    return not (key.endswith("_sim_s") or key.endswith("_real_time_factor") or key.endswith("cpu_s"))


def _cpu_figures(records: list[dict], workers: int) -> dict:
    """CPU-time figures of the scene processes (robust to other load on the machine):
    the median CPU seconds per scene, simulated seconds per CPU second, and the throughput
    ``workers`` otherwise idle cores would give (60 N W / sum of CPU seconds: perfect
    packing; the parent's scheduling is not counted)."""
    cpu = [r["timings"]["process_cpu_s"] for r in records if r["timings"].get("process_cpu_s")]
    sim = [r["timings"].get("run_sim_s") or 0.0 for r in records if r["timings"].get("process_cpu_s")]
    total = sum(cpu)
    return {"cpu_time_per_scene_s": stats(cpu),
            "cpu_real_time_factor": round(sum(sim) / total, 3) if total > 0 else None,
            "scenes_per_minute_idle_cores": round(60.0 * len(cpu) * workers / total, 4) if total > 0 else None}


def _timing_figures(records: list[dict], wall_time_s: float) -> dict:
    """Time per scene, per object and per stage, the wall time, the throughput and the
    real-time factors (simulated per wall seconds)."""
    stage_keys = sorted({k for r in records for k in r["timings"] if _is_wall_timing(k)})
    scene_wall = [r["timings"].get("wall_s") for r in records]
    per_object = [r["timings"]["wall_s"] / r["objects"] for r in records
                  if r["objects"] and r["timings"].get("wall_s") is not None]
    return {
        "time_per_scene_s": stats(scene_wall),
        "time_per_object_s": stats(per_object),
        "time_per_stage_s": {k: stats(r["timings"].get(k) for r in records) for k in stage_keys},
        "wall_time_s": round(float(wall_time_s), 3),
        "scenes_per_minute": None if wall_time_s <= 0 else round(60.0 * len(records) / wall_time_s, 4),
        "real_time_factor": _real_time_factors(records),
    }


def _scene_row(r: dict) -> dict:
    """The JSON row of one scene record: its errors (scene, run, unpicked objects) listed."""
    return {"index": r["index"], "seed": r["seed"], "objects": r["objects"], "picks": r["picks"],
            "errors": ([r["error"]] if r.get("error") else [])
            + ([r["run_error"]] if r.get("run_error") else [])
            + [f"{o['name']}: {o['stage']}: {o['message']}" for o in r["object_rows"] if not o["picked"]],
            "scan": r.get("scan"), "timings": r["timings"],
            "object_rows": r["object_rows"], "pick_rows": r["pick_rows"]}


def aggregate(records: list[dict], seed: int, workers: int, wall_time_s: float,
              extra: Optional[dict] = None) -> dict:
    """The benchmark JSON from the per-scene records (sorted by scene index)."""
    records = sorted(records, key=lambda r: r["index"])
    objs = [o for r in records for o in r["object_rows"]]
    out = {
        "benchmark": "grasp",
        "seed": int(seed),
        "scene_seed_rule": "numpy SeedSequence(entropy=seed, spawn_key=(index,)) -> uint32 >> 1",
        **_outcome_figures(records, objs),
        **_perception_figures(records, objs),
        **_success_groups(records, objs),
        **_timing_figures(records, wall_time_s),
        **_cpu_figures(records, workers),
        "workers": int(workers),
        "scene_rows": [_scene_row(r) for r in records],
    }
    out["targets"] = _targets(out)
    if extra:
        out.update(extra)
    out["scene_rows"] = out.pop("scene_rows")  # (the long part last)
    return out


def _targets(result: dict) -> dict:
    out = {}
    for name, (path, op, target) in TARGETS.items():
        v: Any = result
        for k in path:
            v = v.get(k) if isinstance(v, dict) else None
        met = None if v is None else (v >= target if op == ">=" else v <= target)
        out[name] = {"value": v, "target": f"{op} {target}", "met": met}
    return out


def strip_timings(result: dict) -> dict:
    """``result`` without the fields that legitimately differ between runs (timings)."""
    if isinstance(result, dict):
        return {k: strip_timings(v) for k, v in result.items() if k not in TIMING_KEYS}
    if isinstance(result, list):
        return [strip_timings(v) for v in result]
    return result


# ------------------------------------------------------------------------------ entry point
def run_grasp_benchmark(scenes: int, seed: int = 0, workers: int = 1, json_path: str | Path | None = None,
                        out_dir: str | Path = "out/bench_grasp", progress: bool = True,
                        scene_timeout_s: float = DEFAULT_SCENE_TIMEOUT_S,
                        overrides: tuple = (None, ()), backend: str = "local",
                        address: Optional[str] = None) -> dict:
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
            records, interrupted = run_jobs([(*t, overrides) for t in tasks], SCENE_JOBS, workers_used,
                                            scene_timeout_s, progress, backend, address)
        except KeyboardInterrupt:
            interrupted = True
        status, note = _status(records, interrupted)
        result = aggregate(records, seed, workers_used, time.perf_counter() - t0,
                           extra={"workers_requested": int(workers), "cpu_count": os.cpu_count(),
                                  "backend": backend, "mujoco_gl": worker_env()["MUJOCO_GL"],
                                  "status": status, "status_note": note, "scenes_finished": len(records),
                                  "warnings": [claim.warning] if claim.warning else []})
        if interrupted:
            result["interrupted_while"] = phase
        _write_results(result, out, json_path)
    if result["status"] == "interrupted":
        raise KeyboardInterrupt(f"bench grasp interrupted while {result['interrupted_while']} after "
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


def _status(records: list[dict], interrupted: bool) -> tuple[str, str]:
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


def _write_results(result: dict, out: Path, json_path) -> None:
    """The JSON, the plots and ``summary.md``, safe against a signal (:mod:`.results_files`)."""
    from .grasp_plots import write_plots, write_summary
    from .results_files import write_results

    write_results(result, out, json_path, write_plots, write_summary, "scene_rows")


def headline(result: dict) -> str:
    """A few lines for the terminal."""
    acc = result["accuracy"]
    f = lambda s: "n/a" if s["median"] is None else f"{s['median']:.2f}"  # noqa: E731
    lines = [f"STATUS {result['status'].upper()}: {result.get('status_note') or 'interrupted'}"
             ] if result.get("status", "complete") != "complete" else []
    lines += [
        f"scenes {result['scenes']} ({result['scenes_failed']} raised), objects {result['objects']}, "
        f"picked {result['picked']} -> success {100 * (result['success_rate'] or 0):.1f} %",
        f"scan: {100 * (result['scan_success_rate'] or 0):.1f} % of objects NADIR",
        f"NADIR median errors: centre {f(acc['center_mm'])} mm, width {f(acc['width_mm'])} mm, "
        f"height {f(acc['height_mm'])} mm, yaw {f(acc['yaw_deg'])} deg",
        f"time per scene: median {result['time_per_scene_s']['median']} s; wall {result['wall_time_s']:.1f} s "
        f"with {result['workers']} worker(s) -> {result['scenes_per_minute']} scenes/min",
        f"real-time factor (simulated s per wall s): run {result['real_time_factor']['run']}, "
        f"pick loop {result['real_time_factor']['pick_loop']}; per CPU s {result.get('cpu_real_time_factor')}",
        f"CPU per scene: median {result['cpu_time_per_scene_s']['median']} s -> "
        f"{result.get('scenes_per_minute_idle_cores')} scenes/min on {result['workers']} idle core(s)",
    ]
    for stage, f_ in result["failures_by_stage"].items():
        lines.append(f"  failed at {stage}: {f_['count']} ({', '.join(f'{k} x{v}' for k, v in f_['reasons'].items())})")
    lines += [f"warning: {w}" for w in result.get("warnings") or []]
    return "\n".join(lines)
