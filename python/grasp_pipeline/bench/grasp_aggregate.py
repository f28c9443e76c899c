"""``bench grasp``'s figures from its per-scene records: :func:`aggregate` (a pure function;
the records sorted by scene index) → :class:`~.grasp_result.GraspBenchResult`."""

from __future__ import annotations

from typing import Any, Callable, Mapping, Optional, Sequence

from ..results import SceneRecord
from .accuracy import accuracy, scan_improvement
from .failure_reasons import reason_category
from .figures import failures_by_stage, rate, stats
from .grasp_result import GraspBenchResult, GroupSuccess, RealTimeFactors, SceneRow, TargetCheck

#: Width bins [mm] for "success by size" (true narrow horizontal side).
SIZE_BINS_MM = (30.0, 40.0, 50.0, 60.0, 70.0)
#: The benchmark's targets: name → (path of the figure in the result, comparison, value).
TARGETS = {
    "pick success": (("success_rate",), ">=", 0.95),
    "NADIR centre median [mm]": (("accuracy", "center_mm", "median"), "<=", 2.0),
    "NADIR width median [mm]": (("accuracy", "width_mm", "median"), "<=", 1.5),
    "NADIR height median [mm]": (("accuracy", "height_mm", "median"), "<=", 1.5),
    "NADIR yaw median [deg]": (("accuracy", "yaw_deg", "median"), "<=", 1.5),
}


def _size_bin(width_mm: float) -> str:
    edges = SIZE_BINS_MM
    for lo, hi in zip(edges[:-1], edges[1:]):
        if width_mm < hi:
            return f"{lo:.0f}-{hi:.0f}"
    return f"{edges[-2]:.0f}-{edges[-1]:.0f}"


def _group_success(rows: Sequence[Mapping], key: Callable[[Mapping], str]) -> dict[str, GroupSuccess]:
    counts: dict[str, list[int]] = {}
    for r in rows:
        c = counts.setdefault(key(r), [0, 0])
        c[0] += 1
        c[1] += int(r["picked"])
    return {k: GroupSuccess(objects=n, picked=p, success_rate=rate(p, n)) for k, (n, p) in sorted(counts.items())}


def _scan_failures(records: Sequence[SceneRecord]) -> dict[str, int]:
    """Scenes by scan failure category (the scan's own message; the objects may still be
    picked)."""
    scan_fail: dict[str, int] = {}
    for r in records:
        msg = (r.get("scan") or {}).get("failure")
        if msg:
            cat = reason_category(msg)
            scan_fail[cat] = scan_fail.get(cat, 0) + 1
    return dict(sorted(scan_fail.items()))


def _outcome_figures(records: Sequence[SceneRecord], objs: list[dict]) -> dict[str, Any]:
    """Scene, object and pick counts and rates, and the failures by stage."""
    n_obj = len(objs)
    n_pick = sum(o["picked"] for o in objs)
    picks = [p for r in records for p in r["pick_rows"]]
    return {
        "scenes": len(records),
        "scenes_failed": sum(1 for r in records if r.get("error")),
        "objects": n_obj,
        "picked": n_pick,
        "success_rate": rate(n_pick, n_obj),
        "reported_success_rate": rate(sum(1 for p in picks if p["reported_success"]), len(picks)),
        "false_successes": sum(1 for p in picks if p["reported_success"] and not p["success"]),
        "failures": n_obj - n_pick,
        "failures_by_stage": failures_by_stage(objs),
    }


def _perception_figures(records: Sequence[SceneRecord], objs: list[dict]) -> dict[str, Any]:
    """Scan success, estimate accuracy (NADIR and oblique) and what the scan improves."""
    return {
        "scan_success_rate": rate(sum(o["nadir"] for o in objs), len(objs)),
        "scan_failures": _scan_failures(records),
        "accuracy": accuracy(objs, "nadir_errors", nadir_only=True),
        "accuracy_oblique": accuracy(objs, "rough_errors", nadir_only=False),
        "scan_improvement": scan_improvement(objs),
    }


def _success_groups(records: Sequence[SceneRecord], objs: list[dict]) -> dict[str, Any]:
    """Pick success by object kind, by width bin and by the number of objects in the scene."""
    return {
        "success_by_kind": _group_success(objs, lambda o: o["kind"]),
        "success_by_width_mm": _group_success(objs, lambda o: _size_bin(o["width_mm"])),
        "success_by_scene_objects": _group_success(
            [dict(o, n=r["objects"]) for r in records for o in r["object_rows"]], lambda o: str(o["n"])),
    }


def real_time_factors(records: Sequence[Mapping]) -> RealTimeFactors:
    """Simulated seconds per wall second over all scenes (sums, not a mean of ratios): of the
    whole run (``run``) and of the pick loop alone (``pick_loop``); None without data."""
    out: dict[str, Optional[float]] = {}
    for name, sim_key, wall_key in (("run", "run_sim_s", "wall_s"), ("pick_loop", "picks_sim_s", "picks_s")):
        rows = [r["timings"] for r in records if r["timings"].get(sim_key) is not None
                and r["timings"].get(wall_key)]
        wall = sum(t[wall_key] for t in rows)
        out[name] = round(sum(t[sim_key] for t in rows) / wall, 3) if wall > 0 else None
    return RealTimeFactors(**out)


def _is_wall_timing(key: str) -> bool:
    return not (key.endswith("_sim_s") or key.endswith("_real_time_factor") or key.endswith("cpu_s"))


def _cpu_figures(records: Sequence[SceneRecord], workers: int) -> dict[str, Any]:
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


def _timing_figures(records: Sequence[SceneRecord], wall_time_s: float) -> dict[str, Any]:
    """Time per scene, per object and per stage, the wall time, the throughput and the
    real-time factors (simulated per wall seconds)."""
    stage_keys = sorted({k for r in records for k in r["timings"] if _is_wall_timing(k)})
    per_object = [r["timings"]["wall_s"] / r["objects"] for r in records
                  if r["objects"] and r["timings"].get("wall_s") is not None]
    return {
        "time_per_scene_s": stats(r["timings"].get("wall_s") for r in records),
        "time_per_object_s": stats(per_object),
        "time_per_stage_s": {k: stats(r["timings"].get(k) for r in records) for k in stage_keys},
        "wall_time_s": round(float(wall_time_s), 3),
        "scenes_per_minute": None if wall_time_s <= 0 else round(60.0 * len(records) / wall_time_s, 4),
        "real_time_factor": real_time_factors(records),
    }


def scene_row(r: SceneRecord) -> SceneRow:
    """The JSON row of one scene record: its errors (scene, run, unpicked objects) listed."""
    errors = ([r["error"]] if r.get("error") else []) + ([r["run_error"]] if r.get("run_error") else []) \
        + [f"{o['name']}: {o['stage']}: {o['message']}" for o in r["object_rows"] if not o["picked"]]
    return SceneRow(index=r["index"], seed=r["seed"], objects=r["objects"], picks=r["picks"],
                    errors=tuple(errors), scan=r.get("scan"), timings=r["timings"],
                    object_rows=tuple(r["object_rows"]), pick_rows=tuple(r["pick_rows"]))


def _targets(figures: Mapping[str, Any]) -> dict[str, TargetCheck]:
    out = {}
    for name, (path, op, target) in TARGETS.items():
        v: Any = figures.get(path[0])
        for k in path[1:]:
            v = getattr(v, k, None)
        met = None if v is None else (v >= target if op == ">=" else v <= target)
        out[name] = TargetCheck(value=v, target=f"{op} {target}", met=met)
    return out


def aggregate(records: Sequence[SceneRecord], seed: int, workers: int, wall_time_s: float) -> GraspBenchResult:
    """The benchmark's figures from the per-scene records (sorted by scene index); the run's
    own facts (status, backend, ...) keep their defaults: the caller replaces them."""
    records = sorted(records, key=lambda r: r["index"])
    objs = [o for r in records for o in r["object_rows"]]
    figures = {**_outcome_figures(records, objs), **_perception_figures(records, objs),
               **_success_groups(records, objs), **_timing_figures(records, wall_time_s),
               **_cpu_figures(records, workers)}
    return GraspBenchResult(seed=int(seed), **figures, workers=int(workers), targets=_targets(figures),
                            scene_rows=tuple(scene_row(r) for r in records))
