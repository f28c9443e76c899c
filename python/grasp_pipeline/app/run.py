"""``grasp-pipeline run``: rough view → active scan → pick (and place) the selected objects.

:func:`run_pipeline` builds the simulated system (:mod:`.sim_system`), subscribes the
recorders (video, snapshots) and the ground-truth evaluation to the event stream, runs the
stages and returns a :class:`~grasp_pipeline.results.RunReport`. The report is written (one
serializer, atomically) whatever happens: ``status`` is ``complete``, ``failed`` (with
``error``) or ``interrupted`` (Ctrl-C / SIGTERM: the arm holds, everything done so far is
kept; also when it comes while the objects load). Output paths are checked before the
simulation starts, and the output folder is marked while the run writes there: a second command
writing the same folder warns (:mod:`~grasp_pipeline.report.output_lock`). The report lists the
loaded objects' notes and warnings (``object_notes``; the warnings also in ``warnings``).
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np
from typing import Callable, Optional, Sequence

from ..evaluation import scoring
from ..evaluation.pick_evaluator import PickEvaluator
from ..exceptions import GraspPipelineError
from ..objects.catalog import model_notes
from ..orchestration import GraspSource, PickContext, StageEvent, default_targets, pick_object
from ..orchestration.declutter import clear_table
from ..orchestration.grasping.registry import make_grasp_source
from ..orchestration.scene.targets import rough_view_ids
from ..orchestration.scene.tracks import track_summary
from ..report.output_lock import output_claim
from ..report.serialize import check_writable, check_writable_dir, write_json
from ..report.rerun_recorder import RerunRecorder, check_recording_path, import_rerun
from ..report.snapshot_recorder import SnapshotRecorder
from ..report.video_recorder import VideoRecorder
from ..results import (STATUS_COMPLETE, STATUS_FAILED, STATUS_INTERRUPTED, RunReport, ScanReport,
                       ViewReport)
from ..settings import Settings, load_settings
from .sim_system import SECTIONS, System, build_system, make_scene

log = logging.getLogger("grasp_pipeline.run")

SNAPSHOTS = {"rough_view_done": ("rough.png", "rough view (start pose)"),
             "scan_done": ("scan.png", "after the active scan")}


def _view(system: System, settings: Settings, snapshots: SnapshotRecorder, stage: str) -> ViewReport:
    loop = system.loop
    system.events.publish(StageEvent(float(system.world.time_s), stage, perception=loop))
    return ViewReport(tracks=[track_summary(t) for t in loop.tracks()],
                      scores=scoring.score_estimates(system.world, loop.tracks(), settings.obb.width_tol_m),
                      snapshot=snapshots.written.get(stage))


def _rough_view(system: System, settings: Settings, report: RunReport, snapshots) -> bool:
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
    return True


def _scan(system: System, settings: Settings, report: RunReport, snapshots) -> None:
    t0 = time.perf_counter()
    trig = system.scanner.trigger()
    outcome, failure = None, ""
    try:
        outcome = system.rt.run(system.scanner.task, settings.scan.scan_timeout_s) if trig.accepted else None
    except TimeoutError as exc:  # the scan task was closed: the arm holds where it is
        system.world.hold()
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


def _resolve_picks(system: System, settings: Settings, report: RunReport, pick, observations) -> list:
    """The (x, y) of the objects the ``--pick`` descriptions name, resolved against the
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


def _targets(system: System, settings: Settings, report: RunReport, select, rough_tids) -> list:
    if select:
        return list(select)
    targets, report.targets_skipped = default_targets(
        system.loop.tracks(), system.cell, settings.grasp.target_fixture_margin_m, rough_tids,
        system.loop.judge)
    for s in report.targets_skipped:
        log.info("not picking track #%d at (%.3f, %.3f): %s", s["tid"], *s["center"], s["why"])
    return targets


def _stages(system: System, settings: Settings, report: RunReport, snapshots, select,
            scan: bool, place: bool, source: GraspSource, declutter: bool = False,
            pick: Sequence[str] = ()) -> None:
    system.loop.width_guard = bool(getattr(source, "top_down_only", True))
    observations = None
    if pick:
        from ..language import ObservationRecorder

        observations = ObservationRecorder(settings.language).attach(system.events)
    if not _rough_view(system, settings, report, snapshots):
        return
    rough = {int(t.tid): tuple(t.smoothed.center[:2]) for t in system.loop.tracks()}
    if scan:
        _scan(system, settings, report, snapshots)
    rough_tids = rough_view_ids(rough, system.loop.tracks(), settings.grasp.rough_takeover_m)
    if pick:
        select = _resolve_picks(system, settings, report, pick, observations)
    t0, sim0 = time.perf_counter(), float(system.world.time_s)
    ctx = PickContext(system.rt, system.loop, system.action, system.scanner if scan else None,
                      settings, source, place, side_view=system.side_view)
    if declutter and not select:
        out = clear_table(ctx, system.cell, rough_tids, settings.declutter,
                          on_attempt=report.picks.append)
        report.targets_skipped, report.end_reason = out.skipped, out.end_reason
    else:
        for xy in _targets(system, settings, report, select, rough_tids):
            report.picks.append(pick_object(ctx, xy))
    report.timings["picks_s"] = time.perf_counter() - t0
    _proposal_timings(report, source)
    _real_time(report, "picks", float(system.world.time_s) - sim0, report.timings["picks_s"])
    _volume_cost(system, report)


def _volume_cost(system: System, report: RunReport) -> None:
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
    """``<name>_sim_s`` and ``<name>_real_time_factor`` (simulated seconds per wall second)."""
    report.timings[f"{name}_sim_s"] = sim_s
    report.timings[f"{name}_real_time_factor"] = sim_s / wall_s if wall_s > 0 else 0.0


def _check_outputs(out_dir: Path, json_path, rerun) -> None:
    """Every output path, and the Rerun SDK when recording (before the simulation starts)."""
    check_writable_dir(out_dir, "output folder (--out)")
    if json_path is not None:
        check_writable(json_path, "report file (--json)")
    if rerun is not None:
        import_rerun()
        check_recording_path(rerun)


def _recorders(system: System, out_dir: Path, video: bool, report: RunReport, settings: Settings,
               rerun=None) -> tuple:
    """(snapshots, video recorder or None, Rerun recorder or None); subscribes them and the
    pick evaluation. The video renders its own view at ``settings.video``'s rate and size on
    the event stream's ticks — never through the eye-in-hand camera."""
    snapshots = SnapshotRecorder(out_dir, SNAPSHOTS).attach(system.events)
    PickEvaluator(system.world).attach(system.events)
    recording = None if rerun is None else \
        RerunRecorder(rerun, system.world, settings.rerun).attach(system.events)
    return snapshots, _video(system, out_dir, video, report, settings), recording


def _video(system: System, out_dir: Path, video: bool, report: RunReport, settings: Settings):
    if not video:
        return None
    from ..sim.exceptions import RenderUnavailable
    from ..sim.scene_view import SceneView

    try:
        view = SceneView(system.world, settings.video.video_width_px, settings.video.video_height_px)
    except RenderUnavailable as exc:
        log.warning("no video: %s", exc)
        report.warnings.append(f"video skipped: {exc}")
        return None
    recorder = VideoRecorder(view.render, out_dir / "run.mp4", fps=settings.video.video_fps,
                             on_close=view.close)
    return recorder.attach(system.events)


def run_pipeline(scene: str = "reference", seed: int = 0,
                 select: Optional[Sequence[tuple[float, float]]] = None,
                 out_dir: str | Path = "out", json_path: str | Path | None = None,
                 settings: Optional[Settings] = None, video: bool = True, place: bool = True,
                 scan: bool = True, grasp_source: Optional[GraspSource] = None,
                 prepare: Optional[Callable[[System], None]] = None,
                 objects: str = "builtin", declutter: bool = False,
                 pick: Sequence[str] = (), rerun: str | Path | None = None,
                 mark_output: bool = True) -> RunReport:
    """Run the whole pipeline headless; returns (and writes to ``json_path``) the report.

    ``scene``: ``"reference"``, ``"random"``/``"sparse"``, ``"packed"``, ``"pile"`` (with
    ``seed``; packed/pile of the object set ``objects``: ``"builtin"`` or a path) or a
    ``SceneSpec``;
    ``grasp_source``: where grasps come from (default: the one ``grasp.grasp_source`` names);
    ``prepare(system)``: called once the system is built, before anything runs (attach your
    own recorders to ``system.events``, or inject faults in tests);
    ``declutter``: instead of picking every target of the first look, clear the table one
    pick at a time, looking again after each (:mod:`~grasp_pipeline.orchestration.declutter`;
    ignored with ``select``);
    ``pick``: descriptions of the objects to pick, in order ("the red mug"), resolved against
    the perceived objects after the scan (:mod:`grasp_pipeline.language`; instead of
    ``select``); a refusal ends the run with status failed and the reason as its error;
    ``rerun``: also record the run into this ``.rrd`` file (:mod:`~grasp_pipeline.report.rerun_recorder`;
    the Rerun SDK is an optional extra, checked before the simulation starts);
    ``mark_output``: mark ``out_dir`` while writing there, so that a second writer warns (the
    benchmarks mark their --out and not their rounds' folders)."""
    wall0 = time.perf_counter()
    settings = settings or load_settings(SECTIONS)
    out_dir = Path(out_dir)
    _check_outputs(out_dir, json_path, rerun)
    with output_claim(out_dir, "run", enabled=mark_output) as claim:
        report = RunReport(scene={"name": getattr(scene, "name", str(scene)), "seed": seed, "objects": None},
                           settings=settings.as_dict(), warnings=[claim.warning] if claim.warning else [])
        system = _build(scene, seed, settings, objects, report, wall0, json_path)
        if system is None:
            return report
        recorders = None
        try:
            recorders = _recorders(system, out_dir, video, report, settings, rerun)
            if prepare is not None:  # after the built-in recorders: the pick evaluation comes first
                prepare(system)
            _stages(system, settings, report, recorders[0], select, scan, place,
                    grasp_source or default_grasp_source(settings), declutter, pick)
            report.status = STATUS_FAILED if report.error else STATUS_COMPLETE
        except KeyboardInterrupt:
            system.world.hold()
            report.status, report.error = STATUS_INTERRUPTED, "interrupted (SIGINT/SIGTERM); the arm holds"
            log.error("run interrupted: the arm holds; writing the report of what was done")
        except GraspPipelineError as exc:
            system.world.hold()
            report.status, report.error = STATUS_FAILED, f"{type(exc).__name__}: {exc}"
            log.error("run failed: %s", exc)
        except Exception as exc:  # a bug: the report says so, then the traceback is shown
            system.world.hold()
            report.status, report.error = STATUS_FAILED, f"internal error {type(exc).__name__}: {exc}"
            raise
        finally:
            _finish(system, report, recorders, wall0, json_path)
    return report


def _build(scene, seed: int, settings: Settings, objects, report: RunReport, wall0: float,
           json_path) -> Optional[System]:
    """The scene (its object set loaded; the objects' notes go to the report) and the system
    built on it. When Ctrl-C / SIGTERM comes meanwhile, None (the report, written, says
    interrupted); a bad scene or object set raises, the report written as failed."""
    try:
        spec = make_scene(scene, seed, settings, objects)
        _note_objects(spec, report)
        return build_system(spec, settings)
    except KeyboardInterrupt:
        report.status = STATUS_INTERRUPTED
        report.error = "interrupted (SIGINT/SIGTERM) while the scene was built (objects loading)"
        log.error("run interrupted while the scene was built; writing the report")
        _write_early(report, wall0, json_path)
        return None
    except GraspPipelineError as exc:
        report.status, report.error = STATUS_FAILED, f"{type(exc).__name__}: {exc}"
        _write_early(report, wall0, json_path)
        raise


def _note_objects(spec, report: RunReport) -> None:
    report.scene.update(name=spec.name, objects=len(spec.objects))
    report.object_notes = model_notes(o.mesh for o in spec.objects if o.mesh is not None)
    report.warnings += [f"object {name}: {w}" for name, n in report.object_notes.items()
                        for w in n["warnings"]]


def _write_early(report: RunReport, wall0: float, json_path) -> None:
    """The report of a run that ended before its world was built."""
    report.timings["wall_s"] = time.perf_counter() - wall0
    if json_path is not None:
        write_json(json_path, report)


def default_grasp_source(settings: Settings) -> GraspSource:
    """The grasp source ``grasp.grasp_source`` names
    (:mod:`~grasp_pipeline.orchestration.grasping.registry`): ``any_side`` — grasps from any
    side within the sampler's tilt limit; ``top_down`` — method.md §3's top-down grasp fitted to the
    perceived points."""
    return make_grasp_source(settings)


def _finish(system: System, report: RunReport, recorders, wall0: float, json_path) -> None:
    """Close the recorders and the world, add the run's timings, write the report."""
    sim_s = float(system.world.time_s)
    _close(system, report, recorders)
    report.timings["wall_s"] = time.perf_counter() - wall0
    _real_time(report, "run", sim_s, report.timings["wall_s"])
    if json_path is not None:
        write_json(json_path, report)


def _close(system: System, report: RunReport, recorders) -> None:
    report.motion_plans = list(system.motion.plans)
    snapshots, recorder, recording = recorders if recorders is not None else (None, None, None)
    for rec in (recorder, recording):
        if rec is None:
            continue
        path = rec.close()
        if rec is recorder:
            report.video = path
        else:
            report.recording = path
        if rec.problem:
            report.warnings.append(rec.problem)
    if snapshots is not None:
        report.warnings.extend(snapshots.problems)
    report.warnings.extend(system.events.failures)
    system.close()
