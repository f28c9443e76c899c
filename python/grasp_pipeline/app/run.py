"""``grasp-pipeline run``: rough view → active scan → pick (and place) the selected objects.

:func:`run_pipeline` builds the simulated system (:mod:`.sim_system`), subscribes the
recorders (video, snapshots) and the ground-truth evaluation to the event stream, runs the
stages of the run loop every robot shares (:mod:`.run_loop`) and returns a
:class:`~grasp_pipeline.results.RunReport`. The report is written (one
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
from typing import Callable, Optional, Sequence

from ..exceptions import GraspPipelineError
from ..objects.catalog import model_notes
from ..orchestration import GraspSource
from ..report.output_lock import output_claim
from ..report.serialize import check_writable, check_writable_dir, write_json
from ..report.rerun_recorder import RerunRecorder, check_recording_path, import_rerun
from ..report.snapshot_recorder import SnapshotRecorder
from ..report.video_recorder import VideoRecorder
from ..results import STATUS_FAILED, STATUS_INTERRUPTED, RunReport
from ..settings import Settings, load_settings
from .run_loop import SNAPSHOTS, Recorders, RunOptions, default_grasp_source, drive
from .sim_system import SECTIONS, System, build_system, make_scene

__all__ = ["SNAPSHOTS", "default_grasp_source", "run_pipeline"]

log = logging.getLogger("grasp_pipeline.run")


def _check_outputs(out_dir: Path, json_path, rerun) -> None:
    """Every output path, and the Rerun SDK when recording (before the simulation starts)."""
    check_writable_dir(out_dir, "output folder (--out)")
    if json_path is not None:
        check_writable(json_path, "report file (--json)")
    if rerun is not None:
        import_rerun()
        check_recording_path(rerun)


def _recorders(system: System, out_dir: Path, video: bool, report: RunReport, settings: Settings,
               rerun=None, snapshots: bool = True) -> Recorders:
    """The snapshots (or None), the video (or None), the Rerun recording (or None); subscribes
    them and the pick evaluation. The video renders its own view at ``settings.video``'s rate
    and size on the event stream's ticks — never through the eye-in-hand camera."""
    pictures = SnapshotRecorder(out_dir, SNAPSHOTS).attach(system.events) if snapshots else None
    system.attach_evaluation()
    recording = None if rerun is None else \
        RerunRecorder(rerun, system.world, settings.rerun).attach(system.events)
    return Recorders(pictures, _video(system, out_dir, video, report, settings), recording)


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
                 mark_output: bool = True, snapshots: bool = True) -> RunReport:
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
    benchmarks mark their --out and not their rounds' folders);
    ``snapshots``: draw the PNG snapshots of the rough view and the scan (the benchmarks'
    rounds do not: they write pictures of their failures instead)."""
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
        options = RunOptions(select, scan, place, declutter, tuple(pick), grasp_source)

        def attach() -> Recorders:
            recorders = _recorders(system, out_dir, video, report, settings, rerun, snapshots)
            if prepare is not None:  # after the built-in recorders: the pick evaluation comes first
                prepare(system)
            return recorders

        drive(system, settings, report, options, attach, wall0, json_path)
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
