"""One round of the clutter benchmark, in the process that runs it (evaluation code).

A round is one ``run_pipeline(scene=<packed|pile|sparse scene>, declutter=True)``: rough view,
scan, then one pick at a time with a fresh look after each attempt
(:mod:`grasp_pipeline.orchestration.declutter`). Around it, subscribers score what the robot
cannot know: which true object each attempt was aimed at and whether it ended in the tray
(:class:`~grasp_pipeline.evaluation.pick_evaluator.PickEvaluator`), the segmentation of the
scan's probe frames (:class:`~grasp_pipeline.evaluation.segmentation.ScanSegmentationRecorder`),
each object's geometric bound and what happened to it
(:class:`~grasp_pipeline.evaluation.object_outcomes.ObjectOutcomeRecorder`) and PNGs of every
failed attempt (for a failure after the grasp, also a view of where the object went,
:mod:`~grasp_pipeline.evaluation.object_view`). Afterwards the ground truth says whether the
table is clear.

:func:`run_round` never raises: an exception becomes the record's ``error``.
"""

from __future__ import annotations

import logging
import time
import traceback
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from .clutter_result import RoundRecord
from .failure_reasons import exception_category, reason_category

if TYPE_CHECKING:
    from ..settings import Settings
    from ..sim.scene_spec import SceneSpec

log = logging.getLogger(__name__)

#: Why a round ended, when the ground truth finds the table clear.
END_CLEARED = "table cleared"
#: A round whose run raised or failed.
END_ERROR = "error"


def clutter_settings(overrides: tuple = (None, ())) -> "Settings":
    """The run's parameter sets plus the evaluation's (``grasp_bound``), with ``(config_file,
    sets)`` overrides (``--config``/``--set``)."""
    from ..app.sim_system import SECTIONS
    from ..settings import load_settings

    config_file, sets = overrides
    return load_settings((*SECTIONS, "grasp_bound"), config_file, list(sets))


def round_scene(protocol: str, seed: int, objects: str, settings: "Settings") -> "SceneSpec":
    """The round's scene: ``packed``/``pile`` of the object set ``objects``, or ``sparse``
    (the random primitive scenes)."""
    from ..app.sim_system import make_scene

    return make_scene("random" if protocol == "sparse" else protocol, seed, settings, objects)


def _model_name(obj) -> str:
    """What "success by object" groups by: the mesh model's name (``mug_2``), else the kind."""
    return getattr(obj.mesh, "name", None) or obj.kind


def names_on_table(world) -> list[str]:
    """The objects still resting over the table top (ground truth): not in the tray, not
    fallen to the floor."""
    from ..sim.ground_truth import object_truths

    cell = world.work_cell
    top_z = float(cell.table.center[2] + 0.5 * cell.table.extents[2])
    return [t.name for t in object_truths(world)
            if cell.pick_target_note(t.position_m[:2], 0.0) is None and t.position_m[2] > top_z - 0.01]


def objects_on_table(world) -> int:
    """How many objects still rest over the table top (:func:`names_on_table`)."""
    return len(names_on_table(world))


class _Observers:
    """The round's evaluation subscribers, attached through ``run_pipeline(prepare=...)``."""

    def __init__(self, out_dir: Path, band_m: float, bound_config) -> None:
        self.out_dir, self.band_m, self.bound_config = out_dir, band_m, bound_config
        self.system = None
        self.segmentation = None
        self.outcomes = None
        self.failures = None
        self.view = None

    def __call__(self, system) -> None:
        from ..evaluation.object_outcomes import ObjectOutcomeRecorder
        from ..evaluation.object_view import ObjectView
        from ..evaluation.segmentation import ScanSegmentationRecorder
        from ..report.failure_recorder import FailureSnapshotRecorder

        self.system = system
        self.segmentation = ScanSegmentationRecorder(system.world, self.band_m).attach(system.events)
        self.outcomes = ObjectOutcomeRecorder(system.world, system.loop, self.bound_config,
                                              names_on_table).attach(system.events)
        render = self._render()
        self.failures = FailureSnapshotRecorder(
            self.out_dir / "failures", render,
            None if render is None else ObjectView(system.world, self.view).render).attach(system.events)

    def _render(self):
        """The failure pictures' scene view, made at the first failure (most rounds have
        none); None where no GL context can exist."""
        from ..sim.gl_backend import gl_unavailable_reason
        from ..sim.scene_view import TABLE_VIEW, DeferredSceneView

        reason = gl_unavailable_reason()
        if reason is not None:
            log.warning("no failure scene PNGs: no GL rendering: %s", reason)
            return None
        self.view = DeferredSceneView(self.system.world, **TABLE_VIEW)
        return self.view.render

    def close(self) -> None:
        if self.view is not None:
            self.view.close()


def _attempt_row(p: dict, models: dict) -> dict:
    ok = bool(p.get("success") and p.get("placed") and not p.get("failed_stage"))
    row = {"object": p.get("object"), "model": models.get(p.get("object")),
           "anchor": [round(float(x), 4) for x in p.get("anchor") or []], "success": ok,
           "reported_success": bool(p.get("success")), "wall_s": p.get("wall_s"), "grasp": p.get("grasp"),
           "snapshots": list(p.get("snapshots") or [])}
    if not ok:
        stage = p.get("failed_stage") or ("VERIFY" if p.get("success") else "UNKNOWN")
        msg = str(p.get("message") or "")
        if stage == "VERIFY":
            msg = "reported success but the object is not in the tray"
        row.update(stage=stage, reason=reason_category(msg), message=msg)
    return row


def _object_rows(spec, report: dict, attempts: list, obs: Optional[_Observers], error: Optional[str],
                 models: dict, bound_config) -> list:
    """Each object's bound and outcome (:mod:`grasp_pipeline.evaluation.object_outcomes`);
    without a run (its process died, or it failed before building the world): the bounds where
    the scene placed the objects."""
    from ..evaluation.object_outcomes import rows_without_run

    try:
        if obs is not None and obs.outcomes is not None:
            return obs.outcomes.rows(attempts, report.get("targets_skipped") or [],
                                     report.get("end_reason") or "", error or report.get("error"), models)
        return [] if spec is None or bound_config is None else rows_without_run(spec, bound_config, models, error)
    except Exception:  # the scoring must not lose the round's record
        log.error("objects' bounds and outcomes not scored:\n%s", traceback.format_exc())
        return []


def round_record(task: dict, spec: Optional["SceneSpec"], report: Optional[dict], obs: Optional[_Observers],
                 error: Optional[str], wall_s: float, bound_config=None) -> RoundRecord:
    """The compact per-round record (see :mod:`.clutter_bench` for the fields);
    ``bound_config``: the ``grasp_bound`` parameters when ``obs`` is None."""
    report = report or {}
    models = {o.name: _model_name(o) for o in spec.objects} if spec is not None else {}
    attempts = [_attempt_row(p, models) for p in report.get("picks") or []]
    seg = [] if obs is None or obs.segmentation is None else \
        [s.to_dict() for s in obs.segmentation.best.values()]
    left = None if obs is None or obs.system is None else objects_on_table(obs.system.world)
    end = report.get("end_reason") or ""
    if error or report.get("error"):
        end = END_ERROR
    elif left == 0:
        end = END_CLEARED
    timings = {k: float(v) for k, v in (report.get("timings") or {}).items()}
    timings["wall_s"] = float(wall_s)
    objects = _object_rows(spec, report, attempts, obs, error, models, bound_config)
    return {**task, "objects_placed": len(models), "models": models,
            "attempts": attempts, "successes": sum(a["success"] for a in attempts),
            "end_reason": end, "objects_left": left, "segmentation": seg,
            "error": error or report.get("error"),
            "error_category": exception_category(error) if error else None,
            "timings": timings, "object_outcomes": objects}


def run_round(task: dict) -> RoundRecord:
    """Run one round in this process (``task``: index, bench_seed, seed, protocol, objects,
    out_dir, overrides, recording: a ``.rrd`` path or None); never raises."""
    from ..app.run import run_pipeline

    t0 = time.perf_counter()
    spec = obs = report = bound_config = None
    error = None
    try:
        settings = clutter_settings(task["overrides"])
        bound_config = settings.grasp_bound
        spec = round_scene(task["protocol"], task["seed"], task["objects"], settings)
        out = Path(task["out_dir"])
        obs = _Observers(out, settings.scene_filter.band, bound_config)
        report = run_pipeline(scene=spec, seed=task["seed"], out_dir=out, json_path=out / "report.json",
                              settings=settings, video=False, declutter=True, prepare=obs,
                              rerun=task.get("recording"), mark_output=False, snapshots=False).to_dict()
    except Exception as exc:  # any failure of the round is a result, not a crash
        error = f"{type(exc).__name__}: {exc}"
        log.error("round %d (seed %d) raised %s\n%s", task["index"], task["seed"], error,
                  traceback.format_exc())
    finally:
        if obs is not None:
            obs.close()
    public = {k: v for k, v in task.items() if k not in ("overrides", "out_dir")}
    return round_record(public, spec, report, obs, error, time.perf_counter() - t0, bound_config)
