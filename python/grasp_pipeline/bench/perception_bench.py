"""``grasp-pipeline bench perception``: the per-frame path vs the original Python design.

A synthetic 640×480 tabletop frame (≈307 k points: table, floor, a wall, three
objects, 2 mm depth noise; see :mod:`grasp_pipeline.perception.synthetic`) goes
through the whole per-frame path — one call into C++: scene filter, two-pass
estimates, view quality, tracker — pinned to one CPU core. The baseline is the
original design's Python pipeline (:mod:`.baseline`: numpy RANSAC + Open3D DBSCAN +
Open3D OBB), measured in the same run on the same frames. Targets: median ≤ 10 ms
and ≥ 20× the baseline.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import platform
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
from tqdm import tqdm

from .. import _core
from ..perception.config import ObbConfig, SceneFilterConfig
from ..robot.depth_noise import DepthNoiseConfig
from ..report.serialize import write_json
from ..perception.synthetic import PinholeCamera, tabletop_frame

log = logging.getLogger(__name__)

TARGET_MEDIAN_MS = 10.0
TARGET_SPEEDUP = 20.0
DISTINCT_FRAMES = 4  # noise realisations cycled through (each frame is new to the filter)
FRAME_WIDTH_PX = PinholeCamera().width_px  # the synthetic frames' image width
BASELINE_IMPLEMENTATION = "numpy RANSAC (method.md §1.1-1.3) + Open3D cluster_dbscan + Open3D OBB"


@dataclass(frozen=True)
class FrameTimes:
    """Wall-clock times of the timed frames [ms]."""

    median_ms: float
    p90_ms: float
    mean_ms: float
    min_ms: float
    frames: int


@dataclass(frozen=True, kw_only=True)
class BaselineTimes:
    """The original Python design's times on the same frames [ms], and its object counts."""

    median_ms: float
    p90_ms: float
    mean_ms: float
    min_ms: float
    frames: int
    objects_per_frame: tuple[int, ...]
    implementation: str = BASELINE_IMPLEMENTATION


@dataclass(frozen=True)
class PerceptionTargets:
    median_ms_max: float = TARGET_MEDIAN_MS
    speedup_min: float = TARGET_SPEEDUP


@dataclass(frozen=True)
class PerceptionMachine:
    python: str
    processor: str
    cpus: Optional[int]


@dataclass(frozen=True, kw_only=True)
class PerceptionBenchResult:
    """The per-frame path's times (``median_ms`` ... ``frames``: the whole path, one call into
    C++ with the binding's conversions; ``breakdown_*``: its C++ parts), the baseline's and the
    speed-up (None without a baseline)."""

    points_per_frame: int
    median_ms: float
    p90_ms: float
    mean_ms: float
    min_ms: float
    frames: int
    breakdown_median_ms: dict[str, float]
    breakdown_p90_ms: dict[str, float]
    objects_per_frame: tuple[int, ...]
    pinned_cpu: Optional[int]
    baseline: Optional[BaselineTimes]
    baseline_note: Optional[str]
    speedup: Optional[float]
    targets: PerceptionTargets = PerceptionTargets()
    machine: PerceptionMachine
    meets_targets: bool


def open3d_available() -> bool:
    """True when the optional baseline's Open3D can be imported (the ``bench`` extra)."""
    return importlib.util.find_spec("open3d") is not None


@contextmanager
def one_core():
    """Pin this process to a single CPU while timing (restored afterwards)."""
    if not hasattr(os, "sched_getaffinity"):
        yield None
        return
    before = os.sched_getaffinity(0)
    cpu = min(before)
    os.sched_setaffinity(0, {cpu})
    try:
        yield cpu
    finally:
        os.sched_setaffinity(0, before)


def _times(ms: list[float]) -> FrameTimes:
    a = np.asarray(ms)
    return FrameTimes(median_ms=float(np.median(a)), p90_ms=float(np.percentile(a, 90)),
                      mean_ms=float(a.mean()), min_ms=float(a.min()), frames=int(len(a)))


def _time_frames(per, clouds: list, frames: int, warmup_frames: int) -> tuple[list, dict, list]:
    """Run the per-frame path on ``warmup_frames + frames`` frames (cycling ``clouds``); return
    the total times [ms], the per-part times [ms] and the object counts of the timed frames.

    Parts (C++ timers): pack = validity check, packing and labels of every row; plane = plane
    extraction, table choice, persistence; cluster = band split and clustering; estimate =
    cluster gathering, two-pass estimates and view quality; track = tracker update and
    retirement; core_total = the whole C++ call (the total adds the binding's conversions)."""
    totals = []
    parts = {"pack": [], "plane": [], "cluster": [], "estimate": [], "track": [], "core_total": []}
    n_objects = []
    t_sim = 0.0
    for i in tqdm(range(warmup_frames + frames), desc="perception", unit="frame"):
        pts, T = clouds[i % DISTINCT_FRAMES]
        t0 = time.perf_counter()
        # The frame is organized (640 x 480, row v*W + u): the organized segmentation runs.
        out = per.process(pts, T[:3, 3], t_sim, FRAME_WIDTH_PX)
        dt = (time.perf_counter() - t0) * 1e3
        t_sim += 1.0 / 30.0
        if i < warmup_frames:
            continue
        totals.append(dt)
        parts["pack"].append(out.filter.ms_pack)
        parts["plane"].append(out.filter.ms_plane)
        parts["cluster"].append(out.filter.ms_cluster)
        parts["estimate"].append(out.ms_estimate)
        parts["track"].append(out.ms_track)
        parts["core_total"].append(out.ms_total)
        n_objects.append(len(out.estimates))
    return totals, parts, n_objects


def _time_baseline(clouds: list, sf_cfg, baseline_frames: int) -> tuple[Optional[BaselineTimes], Optional[str]]:
    """(stats, note) of the original Python design on ``baseline_frames`` frames; (None, None)
    when not asked for, (None, why) when Open3D is missing."""
    baseline, baseline_note = None, None
    if baseline_frames > 0 and not open3d_available():
        baseline_note = ("baseline skipped: Open3D is not installed; add it with "
                         "pip install '.[bench]' (or pip install open3d)")
        log.warning("%s", baseline_note)
    elif baseline_frames > 0:
        from .baseline import baseline_frame

        b_ms, b_objects = [], []
        for i in tqdm(range(baseline_frames), desc="baseline", unit="frame"):
            pts, _ = clouds[i % DISTINCT_FRAMES]
            t0 = time.perf_counter()
            res = baseline_frame(pts, sf_cfg, seed=i)
            b_ms.append((time.perf_counter() - t0) * 1e3)
            b_objects.append(len(res["boxes"]))
        t = _times(b_ms)
        baseline = BaselineTimes(median_ms=t.median_ms, p90_ms=t.p90_ms, mean_ms=t.mean_ms, min_ms=t.min_ms,
                                 frames=t.frames, objects_per_frame=tuple(b_objects))
    return baseline, baseline_note


def run_perception_benchmark(frames: int = 50, json_path: str | Path | None = None,
                             baseline_frames: int = 5, warmup_frames: int = 5) -> PerceptionBenchResult:
    """Time the per-frame path (and the baseline); write (``json_path``) and return the result."""
    if frames < 1:
        raise ValueError("frames: expected at least 1")
    sf_cfg, obb_cfg = SceneFilterConfig(), ObbConfig()
    clouds = [tabletop_frame(seed=s) for s in range(DISTINCT_FRAMES)]
    noise = DepthNoiseConfig()
    per = _core.Perception(sf_cfg.to_core(noise), obb_cfg.to_core(noise))
    with one_core() as cpu:
        totals, parts, n_objects = _time_frames(per, clouds, frames, warmup_frames)
        baseline, baseline_note = _time_baseline(clouds, sf_cfg, baseline_frames)
    t = _times(totals)
    speedup = (baseline.median_ms / float(np.median(totals))) if baseline else None
    result = PerceptionBenchResult(
        points_per_frame=int(len(clouds[0][0])), median_ms=t.median_ms, p90_ms=t.p90_ms, mean_ms=t.mean_ms,
        min_ms=t.min_ms, frames=t.frames,
        breakdown_median_ms={k: float(np.median(v)) for k, v in parts.items()},
        breakdown_p90_ms={k: float(np.percentile(v, 90)) for k, v in parts.items()},
        objects_per_frame=tuple(sorted(set(n_objects))), pinned_cpu=cpu, baseline=baseline,
        baseline_note=baseline_note, speedup=speedup,
        machine=PerceptionMachine(python=platform.python_version(), processor=platform.processor(),
                                  cpus=os.cpu_count()),
        meets_targets=bool(t.median_ms <= TARGET_MEDIAN_MS and speedup is not None and speedup >= TARGET_SPEEDUP))
    if json_path is not None:
        write_json(json_path, result)
    return result
