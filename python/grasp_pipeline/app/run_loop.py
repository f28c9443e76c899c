"""The run loop on any robot: rough view → active scan → picks (and places), and the report.

The stages ``grasp-pipeline run`` runs in the simulator (:mod:`.run`) and
:func:`~.robot_run.run_robot` runs on a user's robot, on a built
:class:`~.robot_system.RobotSystem`. :func:`drive` keeps the report valid whatever happens:
``status`` is ``complete``, ``failed`` (with ``error``) or ``interrupted`` (Ctrl-C / SIGTERM:
the arm holds, everything done so far is kept), and the report is written at the end.

It never imports the simulator or its ground truth: a system that has them scores its views
(``score_tracks``), and the simulated root attaches the pick evaluation itself.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Callable, Optional, Sequence

import numpy as np

from .. import signals
from ..exceptions import GraspPipelineError
from ..orchestration import GraspSource, PickContext, StageEvent, default_targets, pick_object
from ..orchestration.declutter import clear_table
from ..orchestration.grasping.registry import make_grasp_source
from ..orchestration.scene.targets import rough_view_ids
from ..orchestration.scene.tracks import track_summary
from ..report.serialize import write_json
from ..results import STATUS_COMPLETE, STATUS_FAILED, STATUS_INTERRUPTED, RunReport, ScanReport, ViewReport
from ..settings import Settings
from .robot_system import RobotSystem

log = logging.getLogger("grasp_pipeline.run")

SNAPSHOTS = {"rough_view_done": ("rough.png", "rough view (start pose)"),
             "scan_done": ("scan.png", "after the active scan")}
#: How far the perceived table may lie from the work cell's table height before the run
#: warns (a wrong camera mount, depth scale or table entry) [m].
TABLE_HEIGHT_TOL_M = 0.03


@dataclass(frozen=True)
class RunOptions:
    """What a run does. ``select``: pick at these (x, y) [m] instead of every target; ``scan``:
    the active scan before picking; ``place``: place picked objects into the tray;
    ``declutter``: clear the table one pick at a time, looking again after each (ignored with
    ``select``); ``pick``: descriptions of the objects to pick ("the red mug"), resolved after
    the scan; ``grasp_source``: where grasps come from (default: ``grasp.grasp_source``)."""

    select: Optional[Sequence[tuple[float, float]]] = None
    scan: bool = True
    place: bool = True
    declutter: bool = False
    pick: Sequence[str] = ()
    grasp_source: Optional[GraspSource] = None


@dataclass
class Recorders:
    """The recorders of a run (each None when not recording): PNG snapshots at the stages of
    :data:`SNAPSHOTS`, a video, a Rerun recording."""

    snapshots: Optional[object] = None
    video: Optional[object] = None
    recording: Optional[object] = None


def default_grasp_source(settings: Settings) -> GraspSource:
    """The grasp source ``grasp.grasp_source`` names
    (:mod:`~grasp_pipeline.orchestration.grasping.registry`): ``any_side`` — grasps from any
    side within the sampler's tilt limit; ``top_down`` — method.md §3's top-down grasp fitted to the
    perceived points."""
    return make_grasp_source(settings)


def drive(system: RobotSystem, settings: Settings, report: RunReport, options: RunOptions,
          attach: Callable[[], Recorders], wall0: float, json_path) -> None:
    """``attach()`` the recorders, run the stages, set the report's status; on Ctrl-C / SIGTERM
    or an error the arm holds. The recorders and the system are closed and the report written
    (to ``json_path`` unless None) in every case, a further Ctrl-C / SIGTERM meanwhile raised only
    after that (as ``KeyboardInterrupt``); a bug's traceback is raised after that too."""
    recorders, mark = None, signals.received()
    try:
        recorders = attach()
        _stages(system, settings, report, recorders.snapshots, options,
                options.grasp_source or default_grasp_source(settings))
        report.status = STATUS_FAILED if report.error else STATUS_COMPLETE
    except KeyboardInterrupt:
        _interrupted(system, report)
    except Exception as exc:
        if signals.received() != mark:  # Ctrl-C a library turned into an error: still Ctrl-C
            _interrupted(system, report)
        elif _failed(system, report, exc):
            raise
    finally:
        with signals.held():  # a second Ctrl-C waits until the report is written
            _finish(system, report, recorders, wall0, json_path)


def _interrupted(system: RobotSystem, report: RunReport) -> None:
    system.robot.hold()
    report.status, report.error = STATUS_INTERRUPTED, "interrupted (SIGINT/SIGTERM); the arm holds"
    log.error("run interrupted: the arm holds; writing the report of what was done")


def _failed(system: RobotSystem, report: RunReport, exc: Exception) -> bool:
    """The arm holds and the report says why; True when ``exc`` is a bug (to be raised again
    after the report is written), False for a known failure."""
    system.robot.hold()
    report.status = STATUS_FAILED
    if isinstance(exc, GraspPipelineError):
        report.error = f"{type(exc).__name__}: {exc}"
        log.error("run failed: %s", exc)
        return False
    report.error = f"internal error {type(exc).__name__}: {exc}"
    return True


def _view(system: RobotSystem, settings: Settings, snapshots, stage: str) -> ViewReport:
    loop = system.loop
    system.events.publish(StageEvent(float(system.robot.time_s), stage, perception=loop))
    tracks = loop.tracks()
    return ViewReport(tracks=[track_summary(t) for t in tracks],
                      scores=system.score_tracks(tracks) if system.score_tracks is not None else [],
                      snapshot=None if snapshots is None else snapshots.written.get(stage))


def _rough_view(system: RobotSystem, settings: Settings, report: RunReport, snapshots) -> bool:
    t0 = time.perf_counter()
    system.rt.spin(settings.scan.rough_view_s)
    report.timings["rough_view_s"] = time.perf_counter() - t0
    loop = system.loop
    if loop.plane is None:
        report.error = "no table plane found from the start pose"
        return False
    report.rough = _view(system, settings, snapshots, "rough_view_done")
    report.plane = {"normal": [float(x) for x in loop.plane.n], "c": float(loop.plane.c),
                    "height_m": float(loop.plane.height_m)}
    _check_table_height(system, report)
    return True


def _check_table_height(system: RobotSystem, report: RunReport) -> None:
    """Warn when the perceived table is not where the work cell puts it."""
    if system.setup is None:
        return
    seen, told = float(system.loop.plane.height_m), system.setup.table_top_z_m
    if abs(seen - told) > TABLE_HEIGHT_TOL_M:
        msg = (f"the table plane is seen at z = {seen:.3f} m but the work cell ({system.setup.source}) puts "
               f"the table top at {told:.3f} m: check the camera mount (hand-eye calibration), the depth "
               "scale and table.center_m")
        log.warning("%s", msg)
        report.warnings.append(msg)


def _scan(system: RobotSystem, settings: Settings, report: RunReport, snapshots) -> None:
    t0 = time.perf_counter()
    trig = system.scanner.trigger()
    outcome, failure = None, ""
    try:
        outcome = system.rt.run(system.scanner.task, settings.scan.scan_timeout_s) if trig.accepted else None
    except TimeoutError as exc:  # the scan task was closed: the arm holds where it is
        system.robot.hold()
        failure = str(exc)
    report.timings["scan_s"] = time.perf_counter() - t0
    system.rt.spin(settings.scan.settle_view_s)
    view = _view(system, settings, snapshots, "scan_done")
    report.scan = ScanReport(
        tracks=view.tracks, scores=view.scores, snapshot=view.snapshot, trigger=trig.message,
        completed=bool(outcome and outcome.completed),
        returned_to_start=bool(outcome and outcome.returned_to_start),
        joint_error_rad=None if outcome is None else outcome.joint_error_rad,
        failure=failure if outcome is None else outcome.failure,
        probes=[] if outcome is None else list(outcome.probes))


def _resolve_picks(system: RobotSystem, settings: Settings, report: RunReport, pick, observations) -> list:
    """The (x, y) of the objects the ``pick`` descriptions name, resolved against the
    perceived tracks over the table top (not the tray's); a refusal raises a LanguageError."""
    from ..language import perceive_objects, resolve_picks

    margin = settings.grasp.target_fixture_margin_m
    tracks = [t for t in system.loop.tracks()
              if system.cell.pick_target_note(t.smoothed.center[:2], margin) is None]
    objects = perceive_objects(tracks, observations, settings.language)
    targets = resolve_picks(pick, objects, report.resolved, settings.language)
    for r in report.resolved:
        log.info("%r: #%d, %s at (%.3f, %.3f)", r.description, r.tid, r.described, *r.center[:2])
    return targets


def _targets(system: RobotSystem, settings: Settings, report: RunReport, select, rough_tids) -> list:
    if select:
        return list(select)
    targets, report.targets_skipped = default_targets(
        system.loop.tracks(), system.cell, settings.grasp.target_fixture_margin_m, rough_tids,
        system.loop.judge)
    for s in report.targets_skipped:
        log.info("not picking track #%d at (%.3f, %.3f): %s", s["tid"], *s["center"], s["why"])
    return targets


def _stages(system: RobotSystem, settings: Settings, report: RunReport, snapshots, options: RunOptions,
            source: GraspSource) -> None:
    system.loop.width_guard = bool(getattr(source, "top_down_only", True))
    observations = None
    if options.pick:
        from ..language import ObservationRecorder

        observations = ObservationRecorder(settings.language).attach(system.events)
    if not _rough_view(system, settings, report, snapshots):
        return
    rough = {int(t.tid): tuple(t.smoothed.center[:2]) for t in system.loop.tracks()}
    if options.scan:
        _scan(system, settings, report, snapshots)
    rough_tids = rough_view_ids(rough, system.loop.tracks(), settings.grasp.rough_takeover_m)
    select = options.select
    if options.pick:
        select = _resolve_picks(system, settings, report, options.pick, observations)
    t0, sim0 = time.perf_counter(), float(system.robot.time_s)
    ctx = PickContext(system.rt, system.loop, system.action, system.scanner if options.scan else None,
                      settings, source, options.place, side_view=system.side_view)
    if options.declutter and not select:
        out = clear_table(ctx, system.cell, rough_tids, settings.declutter,
                          on_attempt=report.picks.append)
        report.targets_skipped, report.end_reason = out.skipped, out.end_reason
    else:
        for xy in _targets(system, settings, report, select, rough_tids):
            report.picks.append(pick_object(ctx, xy))
    report.timings["picks_s"] = time.perf_counter() - t0
    _proposal_timings(report, source)
    _real_time(report, "picks", float(system.robot.time_s) - sim0, report.timings["picks_s"])
    _volume_cost(system, report)


def _volume_cost(system: RobotSystem, report: RunReport) -> None:
    """The scene volume's integration cost (CPU seconds of the frames it integrated)."""
    volume = system.loop.volume
    if volume is None:
        return
    st = volume.stats
    report.timings["volume_integrate_cpu_s"] = st.integrate_cpu_s
    log.info("scene volume: %d of %d frames integrated, %.2f s CPU (%.1f ms a frame)", st.frames_integrated,
             st.frames_offered, st.integrate_cpu_s, 1e3 * st.integrate_cpu_s / max(1, st.frames_integrated))


def _proposal_timings(report: RunReport, source) -> None:
    """How many grasp proposals the source made and their CPU time (a source that measures it)."""
    cpu = list(getattr(source, "cpu_ms", []) or [])
    if cpu:
        report.timings["grasp_proposals"] = float(len(cpu))
        report.timings["grasp_proposal_cpu_ms_median"] = float(np.median(cpu))
        report.timings["grasp_proposal_cpu_ms_p90"] = float(np.percentile(cpu, 90))
        report.timings["grasp_proposal_cpu_s"] = float(np.sum(cpu)) / 1e3


def _real_time(report: RunReport, name: str, sim_s: float, wall_s: float) -> None:
    """``<name>_sim_s`` (seconds of the robot's clock: simulated time in the simulator) and
    ``<name>_real_time_factor`` (clock seconds per wall second)."""
    report.timings[f"{name}_sim_s"] = sim_s
    report.timings[f"{name}_real_time_factor"] = sim_s / wall_s if wall_s > 0 else 0.0


def _finish(system: RobotSystem, report: RunReport, recorders: Optional[Recorders], wall0: float,
            json_path) -> None:
    """Close the recorders and the system, add the run's timings, write the report."""
    sim_s = float(system.robot.time_s)
    _close(system, report, recorders)
    report.timings["wall_s"] = time.perf_counter() - wall0
    _real_time(report, "run", sim_s, report.timings["wall_s"])
    if json_path is not None:
        write_json(json_path, report)


def _close(system: RobotSystem, report: RunReport, recorders: Optional[Recorders]) -> None:
    report.motion_plans = list(system.motion.plans)
    recorders = recorders if recorders is not None else Recorders()
    for rec in (recorders.video, recorders.recording):
        if rec is None:
            continue
        path = rec.close()
        if rec is recorders.video:
            report.video = path
        else:
            report.recording = path
        if rec.problem:
            report.warnings.append(rec.problem)
    if recorders.snapshots is not None:
        report.warnings.extend(recorders.snapshots.problems)
    report.warnings.extend(system.events.failures)
    system.close()
