"""What ``bench grasp`` returns and writes: :class:`GraspBenchResult` (the JSON's top level, in
the file's key order) and its parts. Written by :mod:`grasp_pipeline.report.serialize`; the
per-scene records (:class:`~grasp_pipeline.results.SceneRecord`) stay mappings, as they come
from the worker processes."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

from ..report.serialize import OMIT_IF_NONE
from ..results import SceneScanSummary
from .accuracy import Accuracy, ScanImprovement
from .figures import StageFailures, Stats
from .seeds import SCENE_SEED_RULE

#: Top-level JSON keys (and per-scene keys) that hold timings — the only fields allowed to
#: differ between two runs with the same seed.
TIMING_KEYS = ("wall_time_s", "scenes_per_minute", "time_per_scene_s", "time_per_object_s",
               "time_per_stage_s", "timings", "wall_s", "real_time_factor", "cpu_time_per_scene_s",
               "cpu_real_time_factor", "scenes_per_minute_idle_cores")


@dataclass(frozen=True)
class GroupSuccess:
    """Pick success of one group of objects (a kind, a width bin, a scene size)."""

    objects: int
    picked: int
    success_rate: Optional[float]


@dataclass(frozen=True)
class TargetCheck:
    """One target of the benchmark: the measured value, the target ("<= 2.0") and whether it
    is met (None without a value)."""

    value: Optional[float]
    target: str
    met: Optional[bool]


@dataclass(frozen=True)
class RealTimeFactors:
    """Simulated seconds per wall second over all scenes: the whole run and the pick loop."""

    run: Optional[float]
    pick_loop: Optional[float]


@dataclass(frozen=True)
class SceneRow:
    """One scene in the JSON: its errors (scene, run, unpicked objects) listed, its objects'
    and picks' rows as the scene's process recorded them."""

    index: int
    seed: int
    objects: int
    picks: int
    errors: tuple[str, ...]
    scan: Optional[SceneScanSummary]
    timings: dict[str, float]
    object_rows: tuple[dict, ...]
    pick_rows: tuple[dict, ...]


@dataclass(frozen=True, kw_only=True)
class GraspBenchResult:
    """The benchmark's result; times in wall-clock seconds unless named ``sim``/``cpu``."""

    benchmark: str = "grasp"
    seed: int
    scene_seed_rule: str = SCENE_SEED_RULE
    # outcomes
    scenes: int
    scenes_failed: int
    objects: int
    picked: int
    success_rate: Optional[float]
    reported_success_rate: Optional[float]
    false_successes: int
    failures: int
    failures_by_stage: dict[str, StageFailures]
    # perception
    scan_success_rate: Optional[float]
    scan_failures: dict[str, int]
    accuracy: Accuracy
    accuracy_oblique: Accuracy
    scan_improvement: ScanImprovement
    # success by group
    success_by_kind: dict[str, GroupSuccess]
    success_by_width_mm: dict[str, GroupSuccess]
    success_by_scene_objects: dict[str, GroupSuccess]
    # time
    time_per_scene_s: Stats
    time_per_object_s: Stats
    time_per_stage_s: dict[str, Stats]
    wall_time_s: float
    scenes_per_minute: Optional[float]
    real_time_factor: RealTimeFactors
    cpu_time_per_scene_s: Stats
    cpu_real_time_factor: Optional[float]
    scenes_per_minute_idle_cores: Optional[float]
    workers: int
    targets: dict[str, TargetCheck]
    # the run
    workers_requested: Optional[int] = None
    cpu_count: Optional[int] = None
    backend: str = "local"
    mujoco_gl: Optional[str] = None
    status: str = "complete"
    status_note: str = ""
    scenes_finished: Optional[int] = None
    warnings: tuple[str, ...] = ()
    interrupted_while: Optional[str] = field(default=None, metadata=OMIT_IF_NONE)
    plots: Optional[dict[str, str]] = field(default=None, metadata=OMIT_IF_NONE)
    summary: Optional[str] = None
    scene_rows: tuple[SceneRow, ...] = ()


def strip_timings(result: Any) -> Any:
    """A result's JSON form (a dict from :func:`~grasp_pipeline.report.serialize.to_jsonable`)
    without the fields that legitimately differ between runs (timings)."""
    if isinstance(result, dict):
        return {k: strip_timings(v) for k, v in result.items() if k not in TIMING_KEYS}
    if isinstance(result, list):
        return [strip_timings(v) for v in result]
    return result


def differences(a: Any, b: Any, path: str = "", limit: int = 10) -> list[str]:
    """Up to ``limit`` paths where two JSON-like values (results' JSON forms) differ."""
    out: list[str] = []
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if len(out) >= limit:
                break
            out += differences(a.get(k), b.get(k), f"{path}.{k}", limit - len(out))
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            if len(out) >= limit:
                break
            out += differences(x, y, f"{path}[{i}]", limit - len(out))
    elif a != b:
        out.append(f"{path or '.'}: {a!r} != {b!r}")
    return out
