"""Planning benchmark: success and speed of the motion layer on random scenes, executed in the sim.

It drives the product's own code: per seeded random scene the simulated system is built as
for ``run`` (:func:`grasp_pipeline.app.sim_system.build_system`), the rough view is taken,
the real :class:`~grasp_pipeline.orchestration.ActiveScan` probes every object (its motions
are recorded), and then for every object the run would pick (its default targets) the grasp
action's own planning
(:func:`~grasp_pipeline.orchestration.execution.grasp_planning.plan_grasp` on the candidates of the
:class:`~grasp_pipeline.orchestration.GeometricGraspSource`) plans pre-grasp and approach;
they are executed, followed by the lift line and the way back to the start joints. The
gripper stays open (this measures motions, not grasps). Obstacles are perceived only.

Figures: ``plans``, ``success_rate`` (planned *and* executed without a stop), ``median_ms`` /
``p90_ms`` of the planning time (IK + collision checks + OMPL, without timing; wall), and
``cpu_median_ms`` / ``cpu_p90_ms`` of the planning thread's CPU time (robust to machine load),
``toppra_median_ms``, per-kind breakdowns, ``robot_contacts_during_motion``. With
``--hard N``: ``hard.checker_throughput`` and ``hard.hard_set`` (see :mod:`.planning_hard`).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Optional

import numpy as np

from .. import _core
from ..motion.exceptions import ExecutionError, MotionError
from ..orchestration import GeometricGraspSource, GraspRequest, default_targets
from ..orchestration.execution.grasp_planning import plan_grasp
from ..orchestration.grasping.opening import max_grasp_width_m
from ..orchestration.scene.scene_model import snapshot
from ..orchestration.scene.tracks import nearest_track
from ..report.serialize import OMIT_IF_NONE
from ..results import MotionRecord
from ..robot.description import GRIPPER_MAX_WIDTH_M
from ..robot.protocols import ContactAllowance
from .planning_hard import HardPlanningResult, run_hard_set

log = logging.getLogger(__name__)

MOTION_TIMEOUT_S = 60.0  # simulated limit of one executed motion
PERCEPTION = "the run's perception loop (C++ core + tracker)"


@dataclass(frozen=True)
class KindFigures:
    """The motions of one kind (pregrasp, approach, lift, ...): how many, how many succeeded,
    median planning time [ms] (wall and thread CPU)."""

    plans: int
    success_rate: float
    median_ms: Optional[float]
    cpu_median_ms: Optional[float]


@dataclass(frozen=True, kw_only=True)
class PlanningBenchResult:
    """Every planned motion's success (planned and executed without a stop) and planning time
    [ms] (wall; ``cpu_*``: the planning thread's CPU time; ``toppra_*``: the time-parametrization),
    by kind; ``failures``: the first 50 failed motions. ``hard``: with ``--hard``."""

    scenes: int
    seed: int
    plans: int
    successes: int
    success_rate: Optional[float]
    median_ms: Optional[float]
    p90_ms: Optional[float]
    max_ms: Optional[float]
    cpu_median_ms: Optional[float]
    cpu_p90_ms: Optional[float]
    toppra_median_ms: Optional[float]
    toppra_p90_ms: Optional[float]
    robot_contacts_during_motion: int
    contact_examples: tuple[str, ...]
    methods: dict[str, int]
    by_kind: dict[str, KindFigures]
    failures: tuple[MotionRecord, ...]
    wall_time_s: float
    planner: str
    perception: str = PERCEPTION
    hard: Optional[HardPlanningResult] = field(default=None, metadata=OMIT_IF_NONE)


def _median(x: list[float]):
    return float(np.median(x)) if x else None


def _p90(x: list[float]):
    return float(np.percentile(x, 90)) if x else None


class _Recorder:
    """Runs motions through the motion client and records every attempt."""

    def __init__(self, system, scene_name: str) -> None:
        self.system, self.scene = system, scene_name
        self.records: list[MotionRecord] = []
        self.contacts: list[str] = []

    def execute(self, kind: str, traj, allowance=ContactAllowance.NONE) -> bool:
        rec = MotionRecord(scene=self.scene, kind=kind, ok=False, planning_ms=traj.path.planning_ms,
                           planning_cpu_ms=traj.path.cpu_ms, method=traj.path.method, toppra_ms=traj.timing_ms, duration_s=traj.duration_s)
        self.records.append(rec)
        rt, motion = self.system.rt, self.system.motion
        try:
            rt.run(rt.start(kind, motion.execute(kind, traj, allowance)), MOTION_TIMEOUT_S)
        except ExecutionError as exc:
            rec["error"] = f"ExecutionError({exc.reason}): {exc}"
            if exc.reason == "contact":
                self.contacts.append(f"{self.scene} {kind}: {exc}")
            motion.sync()
            return False
        rec["ok"] = True
        return True

    def plan(self, kind: str, plan_fn, allowance=ContactAllowance.NONE) -> bool:
        t0, c0 = time.perf_counter(), time.thread_time()
        try:
            traj = plan_fn()
        except MotionError as exc:
            self.records.append(MotionRecord(scene=self.scene, kind=kind, ok=False,
                                             planning_ms=(time.perf_counter() - t0) * 1e3,
                                             planning_cpu_ms=(time.thread_time() - c0) * 1e3,
                                             method="none", error=f"{type(exc).__name__}: {exc}"))
            log.warning("%s %s: %s", self.scene, kind, self.records[-1]["error"])
            return False
        return self.execute(kind, traj, allowance)


def _scan_motions(system, rec: _Recorder, settings) -> None:
    trig = system.scanner.trigger()
    if not trig.accepted:
        return
    system.rt.run(system.scanner.task, settings.scan.scan_timeout_s)
    for p in system.motion.plans:  # the scan's executed motions
        rec.records.append(MotionRecord(scene=rec.scene, kind=p["kind"], ok=True, method=p["method"],
                                        planning_ms=p["planning_ms"], toppra_ms=p["timing_ms"],
                                        planning_cpu_ms=p["planning_cpu_ms"],
                                        duration_s=p["duration_s"]))
    system.motion.plans.clear()


def _grasp_motions(system, rec: _Recorder, track, settings) -> None:
    loop, motion, cfg = system.loop, system.motion, settings.grasp
    published = _core.best_grasp_from_estimate(track.smoothed, loop.plane)
    scene = snapshot(loop)
    req = GraspRequest((float(track.smoothed.center[0]), float(track.smoothed.center[1])), track,
                       published, scene, max_grasp_width_m(settings.grasp_fit))
    motion.set_scene(scene.without_fragments(track.tid, cfg.fragment_margin_m), track.tid)
    t0, c0 = time.perf_counter(), time.thread_time()
    try:
        planned = plan_grasp(motion, GeometricGraspSource(cfg).propose(req), cfg,
                             system.world.tcp_pose(), GRIPPER_MAX_WIDTH_M)
    except MotionError as exc:
        rec.records.append(MotionRecord(scene=rec.scene, kind="pregrasp+approach", ok=False,
                                        planning_ms=(time.perf_counter() - t0) * 1e3, method="none",
                                        planning_cpu_ms=(time.thread_time() - c0) * 1e3, error=f"{type(exc).__name__}: {exc}"))
        return
    fingers = ContactAllowance.FINGERS
    if rec.execute("pregrasp", planned.pre_grasp) and rec.execute("approach", planned.approach, fingers):
        T_lift = planned.T_grasp.copy()
        T_lift[:3, 3] -= cfg.lift_height_m * planned.approach_axis
        rec.plan("lift", lambda: motion.plan_line(T_lift, allow_target_contact=True), fingers)
    motion.set_touchable(None)
    rec.plan("grasp_return", lambda: motion.planner.plan_to_joints(motion.q_cmd, system.start_q))


def benchmark_scene(seed: int, settings) -> tuple[list[MotionRecord], list[str]]:
    """All motions of one scene: (records, contact descriptions)."""
    from ..app.sim_system import build_system
    from ..sim.scenes import random_scene

    spec = random_scene(seed, config=settings.sim)
    system = build_system(spec, settings)
    rec = _Recorder(system, spec.name)
    try:
        system.rt.spin(settings.scan.rough_view_s)
        if system.loop.plane is None:
            raise RuntimeError("perception found no table plane from the start pose")
        rough_tids = {int(t.tid) for t in system.loop.tracks()}
        _scan_motions(system, rec, settings)
        # the objects the run would pick (over the table, not the tray's rim or far glimpses)
        targets, _ = default_targets(system.loop.tracks(), system.cell,
                                     settings.grasp.target_fixture_margin_m, rough_tids)
        for xy in targets:
            track, _ = nearest_track(system.loop.tracks(), xy)
            _grasp_motions(system, rec, track, settings)
    finally:
        system.close()
    return rec.records, rec.contacts


def _by_kind(records: list[MotionRecord]) -> dict[str, KindFigures]:
    out = {}
    for kind in sorted({r["kind"] for r in records}):
        rs = [r for r in records if r["kind"] == kind]
        out[kind] = KindFigures(plans=len(rs), success_rate=sum(r["ok"] for r in rs) / len(rs),
                                median_ms=_median([r["planning_ms"] for r in rs if "planning_ms" in r]),
                                cpu_median_ms=_median([r["planning_cpu_ms"] for r in rs if "planning_cpu_ms" in r]))
    return out


def _summary(records: list[MotionRecord], contacts: list[str], scenes: int, seed: int, wall_s: float,
             planner: str) -> PlanningBenchResult:
    ms = [r["planning_ms"] for r in records if "planning_ms" in r]
    cpu = [r["planning_cpu_ms"] for r in records if "planning_cpu_ms" in r]
    tms = [r["toppra_ms"] for r in records if "toppra_ms" in r]
    methods: dict[str, int] = {}
    for r in records:
        methods[r.get("method", "")] = methods.get(r.get("method", ""), 0) + 1
    return PlanningBenchResult(
        scenes=scenes, seed=seed, plans=len(records), successes=int(sum(r["ok"] for r in records)),
        success_rate=(sum(r["ok"] for r in records) / len(records)) if records else None,
        median_ms=_median(ms), p90_ms=_p90(ms), max_ms=max(ms) if ms else None,
        cpu_median_ms=_median(cpu), cpu_p90_ms=_p90(cpu), toppra_median_ms=_median(tms), toppra_p90_ms=_p90(tms),
        robot_contacts_during_motion=len(contacts), contact_examples=tuple(contacts[:20]),
        methods=methods, by_kind=_by_kind(records), failures=tuple(r for r in records if not r["ok"])[:50],
        wall_time_s=wall_s, planner=planner)


def run_planning_benchmark(scenes: int, seed: int, json_path: str | Path | None,
                           overrides: tuple = (None, ()), hard_pairs: int = 0,
                           hard_only: bool = False) -> PlanningBenchResult:
    """Run the benchmark on ``scenes`` random scenes (seeds ``seed`` … ``seed+scenes-1``);
    ``overrides``: ``(config_file, [name=value, ...])`` for the settings. ``hard_pairs`` > 0
    adds the checker throughput and the hard set (that many blocked-line start/goal pairs per
    perceived packed scene, :mod:`.planning_hard`) under ``hard``; ``hard_only`` skips the
    executed random-scene motions."""
    from ..app.sim_system import SECTIONS
    from ..report.serialize import check_writable, write_json
    from ..settings import load_settings

    if scenes < 1:
        raise ValueError(f"scenes must be >= 1, got {scenes}")
    if json_path is not None:
        check_writable(json_path, "benchmark JSON (--json)")
    settings = load_settings(SECTIONS, overrides[0], list(overrides[1]))
    if hard_pairs < 0:
        raise ValueError(f"hard_pairs must be >= 0, got {hard_pairs}")
    records, contacts, t0 = [], [], time.perf_counter()
    for k in range(0 if hard_only else scenes):
        recs, cons = benchmark_scene(seed + k, settings)
        records += recs
        contacts += cons
        log.info("scene %d/%d: %d motions", k + 1, scenes, len(recs))
    result = _summary(records, contacts, 0 if hard_only else scenes, seed, time.perf_counter() - t0,
                      settings.motion.planner)
    if hard_pairs > 0:
        result = replace(result, hard=run_hard_set(scenes, seed, hard_pairs, settings))
    if json_path is not None:
        write_json(json_path, result, sort_keys=True)
    return result
