"""Frames on demand vs continuous frames: the same seeded scenes, per-object outcomes compared.

``grasp-pipeline bench frames --scenes N --seed K --workers W --json PATH --out DIR``

Runs :func:`~grasp_pipeline.bench.grasp_bench.run_grasp_benchmark` twice on the same seeded
scenes, one after the other in this one command (so both throughputs are measured under the
same machine conditions): first with ``camera.frames=continuous`` (the old path: the
eye-in-hand camera renders at its rate during every motion), then with
``camera.frames=on_demand`` (frames only while a consumer looks). Decisions must stay the
same: for every true object of every scene the result compares whether it was picked into
the tray and, if not, the stage and reason category of its failure, and lists each
difference. The full non-timing comparison of the two results (as ``bench workers`` does)
is reported as well, for information: estimates differ in their last digits because the
two paths see different numbers of frames. ``speedup`` is the ratio of wall-clock
throughputs; ``speedup_cpu`` that of the scene processes' CPU-time throughputs (robust to
other load on a shared machine).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from ..report.serialize import to_jsonable, write_json
from .figures import StageFailures, Stats
from .grasp_bench import run_grasp_benchmark
from .grasp_result import GraspBenchResult, RealTimeFactors, differences, strip_timings

#: The target: on-demand throughput at least this many times the old path's.
SPEEDUP_TARGET = 5.0
#: The two paths, in the order they run.
MODES = ("continuous", "on_demand")
#: Per-object fields that are the outcome (decisions), not measurements.
OUTCOME_FIELDS = ("picked", "attempts", "stage", "reason")


@dataclass(frozen=True)
class ModeFigures:
    """One path's throughput and outcome (from its grasp benchmark result)."""

    wall_time_s: float
    scenes_per_minute: Optional[float]
    real_time_factor: RealTimeFactors
    cpu_time_per_scene_s: Stats
    cpu_real_time_factor: Optional[float]
    scenes_per_minute_idle_cores: Optional[float]
    objects: int
    picked: int
    success_rate: Optional[float]
    failures_by_stage: dict[str, StageFailures]


@dataclass(frozen=True, kw_only=True)
class FramesBenchResult:
    """Both paths' figures, the speed-ups (new / old) and every object whose outcome differs."""

    benchmark: str = "frames"
    scenes: int
    seed: int
    workers: int
    objects: int
    cpu_count: Optional[int]
    continuous: ModeFigures
    on_demand: ModeFigures
    speedup: Optional[float]
    speedup_cpu: Optional[float]
    speedup_target: float = SPEEDUP_TARGET
    speedup_met: Optional[bool]
    outcomes_identical: bool
    outcome_differences: tuple[dict, ...]
    results_identical: bool
    first_result_differences: tuple[str, ...]


def object_outcomes(result: dict) -> dict[tuple[int, str], dict]:
    """``(scene index, object name)`` → the object's outcome fields in a grasp benchmark
    result's JSON form (``stage``/``reason`` only for objects that were not picked)."""
    out = {}
    for row in result.get("scene_rows", []):
        for o in row["object_rows"]:
            out[(int(row["index"]), o["name"])] = {k: o.get(k) for k in OUTCOME_FIELDS}
            out[(int(row["index"]), o["name"])]["seed"] = row["seed"]
    return out


def compare_outcomes(old: dict, new: dict) -> list[dict]:
    """The objects whose outcome differs between two grasp benchmark results (JSON forms)."""
    a, b = object_outcomes(old), object_outcomes(new)
    diffs = []
    for key in sorted(set(a) | set(b)):
        x, y = a.get(key), b.get(key)
        if x != y:
            seed = (x or y or {}).get("seed")
            diffs.append({"scene": key[0], "seed": seed, "object": key[1],
                          MODES[0]: x, MODES[1]: y})
    return diffs


def _mode_figures(r: GraspBenchResult) -> ModeFigures:
    return ModeFigures(wall_time_s=r.wall_time_s, scenes_per_minute=r.scenes_per_minute,
                       real_time_factor=r.real_time_factor, cpu_time_per_scene_s=r.cpu_time_per_scene_s,
                       cpu_real_time_factor=r.cpu_real_time_factor,
                       scenes_per_minute_idle_cores=r.scenes_per_minute_idle_cores, objects=r.objects,
                       picked=r.picked, success_rate=r.success_rate, failures_by_stage=r.failures_by_stage)


def _comparable(result: dict) -> dict:
    return strip_timings({k: v for k, v in result.items()
                          if k not in ("workers_requested", "plots", "summary")})


def _ratio(a: Optional[float], b: Optional[float]) -> Optional[float]:
    return a / b if a and b else None


def _rounded(x: Optional[float]) -> Optional[float]:
    return None if x is None else round(x, 3)


def run_frames_benchmark(scenes: int, seed: int = 0, workers: int = 2,
                         json_path: Optional[str | Path] = None,
                         out_dir: str | Path = "out/bench_frames", progress: bool = True,
                         overrides: tuple = (None, ())) -> FramesBenchResult:
    """Run the grasp benchmark with continuous frames, then on demand; compare outcomes."""
    out = Path(out_dir)
    config_file, sets = overrides
    runs: dict[str, GraspBenchResult] = {}
    for mode in MODES:
        runs[mode] = run_grasp_benchmark(
            scenes=scenes, seed=seed, workers=workers, json_path=out / f"{mode}.json",
            out_dir=out / mode, progress=progress,
            overrides=(config_file, [*sets, f"camera.frames={mode}"]))
    old, new = runs[MODES[0]], runs[MODES[1]]
    old_json, new_json = to_jsonable(old), to_jsonable(new)
    diffs = compare_outcomes(old_json, new_json)
    speedup = _ratio(new.scenes_per_minute, old.scenes_per_minute)
    result = FramesBenchResult(
        scenes=scenes, seed=seed, workers=workers, objects=new.objects, cpu_count=new.cpu_count,
        continuous=_mode_figures(old), on_demand=_mode_figures(new), speedup=_rounded(speedup),
        speedup_cpu=_rounded(_ratio(new.scenes_per_minute_idle_cores, old.scenes_per_minute_idle_cores)),
        speedup_met=None if speedup is None else bool(speedup >= SPEEDUP_TARGET),
        outcomes_identical=not diffs, outcome_differences=tuple(diffs),
        results_identical=not differences(_comparable(old_json), _comparable(new_json), limit=1),
        first_result_differences=tuple(differences(_comparable(old_json), _comparable(new_json))))
    if json_path is not None:
        write_json(json_path, result)
    return result
