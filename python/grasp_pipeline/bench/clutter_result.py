"""What ``bench clutter`` returns and writes: :class:`ClutterBenchResult` (the JSON's top level,
in the file's key order) and its parts. Written by :mod:`grasp_pipeline.report.serialize`; the
round records stay mappings, as they come from the worker processes, and so do the summaries
of :mod:`grasp_pipeline.evaluation` (segmentation, geometric bound)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional, TypedDict

from ..report.serialize import OMIT_IF_NONE
from .figures import StageFailures, Stats

#: Fields that hold timings — the only ones allowed to differ between runs of one seed.
TIMING_KEYS = ("wall_s", "wall_time_s", "time_per_attempt_s", "time_per_round_s",
               "rounds_per_hour", "timings", "snapshots")


class RoundRecord(TypedDict):
    """One round as its process records it (:func:`.clutter_round.round_record`): the task's
    public fields, then what happened. ``attempts``: one row per pick attempt (object, model,
    success; stage, reason and message when it failed); ``object_outcomes``: each object's
    geometric bound and what happened to it (:mod:`grasp_pipeline.evaluation.object_outcomes`)."""

    index: int
    bench_seed: int
    round: int
    seed: int
    protocol: str
    objects: str
    recording: Optional[str]
    objects_placed: int
    models: dict[str, str]
    attempts: list[dict]
    successes: int
    end_reason: str
    objects_left: Optional[int]
    segmentation: list[dict]
    error: Optional[str]
    error_category: Optional[str]
    timings: dict[str, float]
    object_outcomes: list[dict]


@dataclass(frozen=True, kw_only=True)
class SeedCounts:
    """One benchmark seed's rounds: grasp success rate ``gsr`` = successes / attempts, declutter
    rate ``dr`` = successes / objects placed (None without attempts / objects)."""

    seed: int
    rounds: int
    objects_placed: int
    attempts: int
    successes: int
    gsr: Optional[float]
    dr: Optional[float]
    attempts_executed: int
    gsr_executed: Optional[float]


@dataclass(frozen=True)
class RatePair:
    """A statistic (mean or std over the seeds) of the two rates."""

    gsr: Optional[float]
    dr: Optional[float]


@dataclass(frozen=True)
class ObjectSuccess:
    """One object model: how many were placed, attempted, picked."""

    placed: int
    attempts: int
    picked: int
    success_rate: Optional[float]


@dataclass(frozen=True, kw_only=True)
class ClutterBenchResult:
    """The benchmark's result, all rounds pooled (the counts) and per seed (``seeds``); times
    in wall-clock seconds."""

    benchmark: str = "clutter"
    protocol: str
    objects: str
    seed_list: tuple[int, ...]
    rounds: int
    objects_placed: int
    attempts: int
    successes: int
    gsr: Optional[float]
    dr: Optional[float]
    attempts_executed: int
    gsr_executed: Optional[float]
    seeds: tuple[SeedCounts, ...]
    mean: RatePair
    std: RatePair
    rounds_failed: int
    end_reasons: dict[str, int]
    failures_by_stage: dict[str, StageFailures]
    success_by_object: dict[str, ObjectSuccess]
    segmentation: dict[str, Any]
    grasp_bound: dict[str, Any]
    time_per_attempt_s: Stats
    time_per_round_s: Stats
    wall_time_s: float
    rounds_per_hour: Optional[float]
    workers: int
    round_seed_rule: str = "scene_seed(seed, round) as bench grasp"
    # the run
    status: str = "complete"
    status_note: str = ""
    rounds_requested: Optional[int] = None
    cpu_count: Optional[int] = None
    mujoco_gl: Optional[str] = None
    out_dir: Optional[str] = None
    backend: str = "local"
    object_notes: dict[str, Any] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    interrupted_while: Optional[str] = field(default=None, metadata=OMIT_IF_NONE)
    plots: Optional[dict[str, str]] = field(default=None, metadata=OMIT_IF_NONE)
    summary: Optional[str] = None
    round_rows: tuple[RoundRecord, ...] = ()
