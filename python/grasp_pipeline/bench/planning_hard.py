"""Hard planning problems and checker throughput, in perceived packed scenes.

Per seeded ``packed`` scene the simulated system is built as for ``run``; the rough view and
the active scan run; the perceived scene (environment points, object boxes, work-cell
fixtures) is handed to the motion planner exactly as the grasp action does. Then:

* **checker throughput** (first scene): random joint states, one core; ``single`` = one
  ``StateChecker.check`` call per state from Python, ``batched`` = one ``check_batch`` call;
  both as CPU time of the calling thread (robust to other load on the machine);
* **hard set**: random collision-free start/goal pairs whose straight joint line is invalid
  (so the direct-line shortcut cannot answer), planned by the product's ``JointPlanner``;
  success rate and planning time (wall and thread CPU). Every returned path is re-checked
  densely with the numpy reference validator (``reference_violations`` must be 0).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np

from ..motion.exceptions import MotionError
from ..motion.validity import StateValidator

if TYPE_CHECKING:
    from ..settings import Settings

#: Random states of the throughput measurement.
THROUGHPUT_STATES = 200_000
#: Single-call states (a Python loop).
THROUGHPUT_SINGLE_STATES = 50_000
#: Samples drawn per wanted pair before giving up on a scene.
MAX_SAMPLES_PER_PAIR = 2000


@dataclass(frozen=True)
class CheckerThroughput:
    """States checked per CPU second of one thread: one call per state, and one batch."""

    batched_states_per_s: float
    single_states_per_s: float
    valid_fraction: float
    states: int


@dataclass(frozen=True, kw_only=True)
class HardSetSummary:
    """The hard set's outcome: success and planning time [ms] (wall and thread CPU) of the
    pairs planned; ``reference_violations``: returned paths the reference validator refuses."""

    scenes: int
    pairs_wanted: int
    pairs: int
    successes: int
    success_rate: Optional[float]
    median_ms: Optional[float]
    p90_ms: Optional[float]
    max_ms: Optional[float]
    cpu_median_ms: Optional[float]
    cpu_p90_ms: Optional[float]
    reference_violations: int
    failures: tuple[dict, ...]


@dataclass(frozen=True)
class HardPlanningResult:
    """``bench planning --hard``: the checker throughput (first scene; None without a scene)
    and the hard set."""

    checker_throughput: Optional[CheckerThroughput]
    hard_set: HardSetSummary


def perceived_planner(seed: int, settings: "Settings"):
    """(system, motion planner) with the perceived packed scene after the rough view and scan."""
    from ..app.sim_system import build_system, make_scene
    from ..orchestration.scene.scene_model import snapshot

    system = build_system(make_scene("packed", seed, settings), settings)
    try:
        system.rt.spin(settings.scan.rough_view_s)
        if system.scanner.trigger().accepted:
            system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
        system.motion.set_scene(snapshot(system.loop))
    except BaseException:
        system.close()
        raise
    return system, system.motion.planner


def checker_throughput(validator: StateValidator, rng: np.random.Generator) -> CheckerThroughput:
    """States per CPU second of one thread, single calls and one batch."""
    Q = rng.uniform(validator.q_min, validator.q_max, size=(THROUGHPUT_STATES, 7))
    core = validator.core()
    t0 = time.thread_time()
    valid = core.check_batch(Q)
    batched = len(Q) / max(time.thread_time() - t0, 1e-9)
    check = core.check
    t0 = time.thread_time()
    for q in Q[:THROUGHPUT_SINGLE_STATES]:
        check(q)
    single = THROUGHPUT_SINGLE_STATES / max(time.thread_time() - t0, 1e-9)
    return CheckerThroughput(batched_states_per_s=batched, single_states_per_s=single,
                             valid_fraction=float(valid.mean()), states=len(Q))


def hard_pairs(validator: StateValidator, n: int, step_rad: float, rng: np.random.Generator) -> list:
    """Up to ``n`` (start, goal) pairs: both valid, straight line between them invalid."""
    pairs, drawn = [], 0
    while len(pairs) < n and drawn < MAX_SAMPLES_PER_PAIR * n:
        Q = rng.uniform(validator.q_min, validator.q_max, size=(64, 7))
        drawn += len(Q)
        free = Q[validator.check_batch(Q)]
        for qs, qg in zip(free[0::2], free[1::2]):
            if len(pairs) < n and not validator.check_segment(qs, qg, step_rad):
                pairs.append((qs, qg))
    return pairs


def _reference_ok(validator: StateValidator, wp: np.ndarray, step_rad: float) -> bool:
    dense = [wp[:1]] + [validator.segment_states(a, b, step_rad) for a, b in zip(wp[:-1], wp[1:])]
    return bool(np.all(validator._python_check_batch(np.vstack(dense))))


def solve_hard_set(planner, pairs: list, scene: str) -> list[dict]:
    """Plan every pair with the product's joint planner; one record per pair."""
    v, step = planner.validator, planner.config.final_check_step_rad
    records = []
    for qs, qg in pairs:
        rec = {"scene": scene, "ok": False}
        t_cpu = time.thread_time()
        try:
            path = planner.plan_path_to_joints(qs, qg)
        except MotionError as exc:
            rec.update(cpu_ms=(time.thread_time() - t_cpu) * 1e3, planning_ms=None,
                       error=f"{type(exc).__name__}: {exc}")
        else:
            rec.update(cpu_ms=(time.thread_time() - t_cpu) * 1e3, ok=True, planning_ms=path.planning_ms,
                       method=path.method, waypoints=len(path.waypoints), checked_states=path.checked_states,
                       reference_ok=_reference_ok(v, path.waypoints, step))
        records.append(rec)
    return records


def summarize_hard(records: list[dict], wanted: int, scenes: int) -> HardSetSummary:
    """The hard set's figures from one record per pair (:func:`solve_hard_set`)."""
    ms = [r["planning_ms"] for r in records if r["ok"]]
    cpu = [r["cpu_ms"] for r in records if r["ok"]]
    pct = (lambda x, q: float(np.percentile(x, q)) if x else None)
    return HardSetSummary(
        scenes=scenes, pairs_wanted=wanted * scenes, pairs=len(records),
        successes=sum(r["ok"] for r in records),
        success_rate=(sum(r["ok"] for r in records) / len(records)) if records else None,
        median_ms=pct(ms, 50), p90_ms=pct(ms, 90), max_ms=max(ms) if ms else None,
        cpu_median_ms=pct(cpu, 50), cpu_p90_ms=pct(cpu, 90),
        reference_violations=sum(1 for r in records if r["ok"] and not r["reference_ok"]),
        failures=tuple(r for r in records if not r["ok"])[:20])


def run_hard_set(scenes: int, seed: int, pairs_per_scene: int, settings: "Settings") -> HardPlanningResult:
    """Throughput (first scene) and the hard set over packed scenes ``seed .. seed+scenes-1``."""
    rng = np.random.default_rng(seed)
    records, throughput = [], None
    for k in range(scenes):
        system, planner = perceived_planner(seed + k, settings)
        try:
            if throughput is None:
                throughput = checker_throughput(planner.validator, rng)
            pairs = hard_pairs(planner.validator, pairs_per_scene, planner.config.final_check_step_rad, rng)
            records += solve_hard_set(planner, pairs, f"packed-{seed + k}")
        finally:
            system.close()
    return HardPlanningResult(throughput, summarize_hard(records, pairs_per_scene, scenes))
