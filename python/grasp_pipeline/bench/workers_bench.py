"""Worker scaling of the grasp benchmark: the same scenes with 1 worker, then with W.

``grasp-pipeline bench workers --scenes N --seed K --workers W --json PATH --out DIR``

Both runs are :func:`~grasp_pipeline.bench.grasp_bench.run_grasp_benchmark` on the same
seeded scenes, one after the other in this one command, so the ratio of their wall times is
measured under the same machine conditions. The runs must also agree on every non-timing
field (the benchmark is deterministic per seed and independent of scheduling); the result
says whether they did, and lists the first differences when they did not.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from ..report.serialize import to_jsonable, write_json
from .grasp_bench import run_grasp_benchmark
from .grasp_result import GraspBenchResult, differences, strip_timings

#: The target: ``--workers 2`` at least this much faster than ``--workers 1``.
SPEEDUP_TARGET = 1.6
#: Fields of a grasp benchmark result that depend on the workers (left out of the comparison).
RUN_DEPENDENT = ("workers", "workers_requested", "plots", "summary")


@dataclass(frozen=True, kw_only=True)
class WorkersBenchResult:
    """Both runs' figures keyed by their number of workers ("1" and "W"); wall-clock seconds."""

    benchmark: str = "workers"
    scenes: int
    seed: int
    objects: int
    cpu_count: Optional[int]
    wall_time_s: dict[str, float]
    scenes_per_minute: dict[str, Optional[float]]
    time_per_scene_median_s: dict[str, Optional[float]]
    workers: int
    speedup: Optional[float]
    speedup_target: float = SPEEDUP_TARGET
    speedup_met: Optional[bool]
    results_identical: bool
    differences: tuple[str, ...]
    success_rate: dict[str, Optional[float]]


def run_workers_benchmark(scenes: int, seed: int = 0, workers: int = 2,
                          json_path: Optional[str | Path] = None,
                          out_dir: str | Path = "out/bench_workers", progress: bool = True,
                          overrides: tuple = (None, ())) -> WorkersBenchResult:
    """Run the grasp benchmark with 1 worker and with ``workers``; report the speed-up."""
    if workers < 2:
        raise ValueError(f"workers must be >= 2 to compare with 1 worker, got {workers}")
    out = Path(out_dir)
    runs: dict[int, GraspBenchResult] = {}
    for w in (1, workers):
        runs[w] = run_grasp_benchmark(scenes=scenes, seed=seed, workers=w, json_path=out / f"w{w}.json",
                                      out_dir=out / f"w{w}", progress=progress, overrides=overrides)
    one, many = runs[1], runs[workers]
    diffs = differences(_comparable(one), _comparable(many))
    speedup = one.wall_time_s / many.wall_time_s if many.wall_time_s > 0 else None
    both = lambda value: {"1": value(one), str(workers): value(many)}  # noqa: E731
    result = WorkersBenchResult(
        scenes=scenes, seed=seed, objects=one.objects, cpu_count=one.cpu_count,
        wall_time_s=both(lambda r: r.wall_time_s), scenes_per_minute=both(lambda r: r.scenes_per_minute),
        time_per_scene_median_s=both(lambda r: r.time_per_scene_s.median), workers=workers,
        speedup=None if speedup is None else round(speedup, 3),
        speedup_met=None if speedup is None else bool(speedup >= SPEEDUP_TARGET),
        results_identical=not diffs, differences=tuple(diffs), success_rate=both(lambda r: r.success_rate))
    if json_path is not None:
        write_json(json_path, result)
    return result


def _comparable(result: GraspBenchResult) -> dict:
    """The JSON form of a run without its timings and the fields that depend on the workers."""
    return strip_timings({k: v for k, v in to_jsonable(result).items() if k not in RUN_DEPENDENT})
