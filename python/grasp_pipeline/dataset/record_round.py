"""One declutter round recorded as episodes, in the worker process that runs it.

A round is ``run_pipeline(scene=<protocol scene>, declutter=True)`` (as a ``bench clutter``
round) with an :class:`.episode_recorder.EpisodeRecorder` and its own camera views attached
through ``prepare``. Each finished episode is saved as ``<work_dir>/episode_<k>.npz`` (failed
ones only with ``keep_failed``); the record lists every episode's outcome (saved or not) for
the parent, which writes the dataset (:mod:`.record_command`).

:func:`run_record_round` never raises: an exception becomes the record's ``error``.
"""

from __future__ import annotations

import logging
import time
import traceback
from pathlib import Path

log = logging.getLogger(__name__)


class _RoundRecording:
    """The ``prepare`` of one round: attaches the recorder; keeps the episode outcomes."""

    def __init__(self, task: dict, settings, spec) -> None:
        self.task, self.settings, self.spec = task, settings, spec
        self.work = Path(task["work_dir"])
        self.outcomes: list[dict] = []
        self.views = None
        self.system = None

    def __call__(self, system) -> None:
        from .camera_views import RecordingViews
        from .episode_recorder import EpisodeRecorder
        from .tasks import TargetDescriber

        cfg = self.settings.record
        self.system = system
        self.views = RecordingViews(system.world, cfg, bool(self.task["depth"]))
        describe = TargetDescriber(system.world, self.spec.objects, cfg.task_template)
        EpisodeRecorder(system.world, cfg.record_fps_hz, self.on_episode, describe,
                        self.views).attach(system.events)

    def on_episode(self, episode) -> None:
        k = len(self.outcomes)
        row = {**episode.outcome(), "attempt": k, "file": None}
        if episode.success or self.task["keep_failed"]:
            path = self.work / f"episode_{k:03d}.npz"
            episode.save(path)
            row["file"] = str(path)
        self.outcomes.append(row)

    def close(self) -> None:
        if self.views is not None:
            self.views.close()


def run_record_round(task: dict) -> dict:
    """Run and record one round in this process (``task``: index, bench_seed, round, seed,
    protocol, objects, work_dir, keep_failed, depth, recording (a Rerun file or None),
    overrides); never raises."""
    from ..app.run import run_pipeline
    from ..bench.clutter_round import round_scene
    from .record_settings import record_settings

    t0, cpu0 = time.perf_counter(), time.process_time()
    rec, report, error = None, None, None
    try:
        settings = record_settings(task["overrides"])
        spec = round_scene(task["protocol"], task["seed"], task["objects"], settings)
        rec = _RoundRecording(task, settings, spec)
        Path(task["work_dir"]).mkdir(parents=True, exist_ok=True)
        report = run_pipeline(scene=spec, seed=task["seed"], out_dir=task["work_dir"], settings=settings,
                              video=False, declutter=True, prepare=rec, rerun=task.get("recording"))
        error = report.error
    except Exception as exc:  # any failure of the round is a result, not a crash
        error = f"{type(exc).__name__}: {exc}"
        log.error("round %d (seed %d) raised %s\n%s", task["index"], task["seed"], error,
                  traceback.format_exc())
    finally:
        if rec is not None:
            rec.close()
    public = {k: v for k, v in task.items() if k not in ("overrides", "work_dir")}
    timings = {"wall_s": time.perf_counter() - t0, "round_cpu_s": time.process_time() - cpu0}
    if report is not None:
        timings["sim_s"] = float(report.timings.get("run_sim_s", 0.0))
    return {**public, "episodes": [] if rec is None else rec.outcomes, "error": error,
            "end_reason": None if report is None else report.end_reason, "timings": timings}
