"""``grasp-pipeline eval``: a policy's success in the environment, closed loop, on seeded scenes.

``eval --policy DIR|reference --protocol sparse|packed|pile [--objects builtin|DIR] --episodes N
--seed K [--workers W] [--backend local|ray --address H:P] [--max-steps M] [--device cpu|cuda]
--out DIR [--no-video] [--image-size PX] [--fps N] [--depth] [--config FILE] [--set ...]``

``--policy DIR``: a policy saved by LeRobot (``save_pretrained`` with its pre/post-processors,
e.g. by ``grasp-pipeline train``); ``reference``: the pipeline itself acting through the
environment's actions (:mod:`.reference_policy`), the ceiling to compare with. Episode ``i`` is
the environment's episode on the scene of seed ``scene_seed(K, i)`` (as ``record``: evaluate on
another ``--seed`` than the training data's for scenes the policy never saw), played until the
target rests in the tray or the time limit (``env.yaml`` ``time_limit_s``, or ``--max-steps``).
Jobs of ``env.yaml`` ``episodes_per_job`` episodes run in worker processes (or on Ray); each
loads the policy once.

Everything the run needs is checked before any simulation (a one-line error): the output
folder (new or empty; marked while eval writes there, so that a second eval started into it
is refused), the protocol and object set, the policy folder and its input features
against the environment's observations (key and shape). ``--out`` receives ``eval.json``
(:mod:`.eval_report`: success rate with a 95 % interval, per task word and per object, failure
reasons, steps and seconds per episode, every episode), ``summary.md`` and
``videos/episode_<i>_scene_<seed>.mp4`` (scene and wrist camera side by side). ``eval.json``
is written (atomically) when the run starts (``"status": "running"``) and when it ends
(``complete``; ``partial`` / ``failed`` when some / all episodes did not run to their end, a job
having timed out, died or raised, with a ``status_note`` saying why; or ``interrupted`` with the
``phase`` and the episodes finished until then);
the video of an episode that is not in the report (unfinished, or its result not saved) is
removed.
"""

from __future__ import annotations

import logging
import math
import os
import time
from collections import Counter
from pathlib import Path
from typing import Optional

from ..exceptions import InputError

log = logging.getLogger(__name__)

REPORT_FILE = "eval.json"
SUMMARY_FILE = "summary.md"
VIDEOS = "videos"
#: Where the workers put each finished episode's result until the report holds them.
RESULTS = ".episodes"


def _eval_task(task: tuple) -> dict:
    from .eval_job import run_eval_job

    return run_eval_job(task[1])


def _failed_job(task: tuple, error: str, wall_s: float) -> dict:
    return {"index": task[0], "episodes": [], "error": error, "timings": {"wall_s": wall_s}}


def _postfix(records: list[dict]) -> str:
    eps = [e for r in records for e in r["episodes"]]
    return f"success {sum(bool(e.get('success')) for e in eps)} / {len(eps)}"


def _jobs():
    from ..bench.jobs import JobSpec

    return JobSpec(run_fn=_eval_task, failed_fn=_failed_job, postfix_fn=_postfix, desc="eval", tag="job")


def check_policy(policy: str, env, device: str) -> str:
    """``reference`` or the policy folder (as a string), checked against ``env``'s spaces."""
    if policy == "reference":
        return policy
    from ..dataset.lerobot_writer import require_lerobot
    from .compatibility import check_policy_features, policy_config

    require_lerobot()
    cfg = policy_config(policy)
    check_policy_features(cfg, env.observation_space, env.action_space)
    if device == "cuda":
        import torch

        if not torch.cuda.is_available():
            raise InputError("--device cuda: torch finds no CUDA device here (use --device cpu)")
    return str(Path(policy).resolve())


def check_out(out: Path, claim=None) -> None:
    """``--out`` is a new or empty folder that can be written (with ``claim``: empty but for
    this process's own marker — a second ``eval`` started into the same folder is refused)."""
    from ..report.serialize import check_writable_dir

    mine = getattr(claim, "marker", None)
    if out.exists() and (not out.is_dir() or any(p != mine for p in out.iterdir())):
        raise InputError(f"--out {out} exists and is not an empty folder: choose a new folder")
    check_writable_dir(out, "output folder (--out)")


def check_inputs(a: dict):
    """The settings and the environment (not reset); :class:`InputError` before simulating.
    (``--out`` is checked before, by :func:`check_out`.)"""
    from ..dataset.record_settings import record_overrides, record_settings
    from .pick_env import PickPlaceEnv, check_protocol

    check_protocol(a["protocol"])
    if a["episodes"] < 1 or a["workers"] < 1:
        raise InputError("--episodes and --workers must be >= 1")
    if a["device"] not in ("cpu", "cuda"):
        raise InputError(f"--device must be cpu or cuda, got {a['device']!r}")
    settings = record_settings(record_overrides(a["overrides"], a["fps"], a["image_size"]))
    env = PickPlaceEnv(a["protocol"], a["objects"], a["depth"], settings=settings,
                       max_episode_steps=a["max_steps"])
    env.object_models()  # a bad object folder fails here (MeshError naming the file)
    return settings, env


def _tasks(a: dict, per_job: int, overrides: tuple) -> list[tuple]:
    from ..bench.seeds import scene_seed

    videos = None if not a["video"] else str(a["out"] / VIDEOS)
    out = []
    for j in range(math.ceil(a["episodes"] / per_job)):
        eps = [(i, scene_seed(a["seed"], i)) for i in range(j * per_job, min((j + 1) * per_job, a["episodes"]))]
        out.append((j, {"index": j, "episodes": eps, "policy": a["policy"], "device": a["device"],
                        "protocol": a["protocol"], "objects": str(a["objects"]), "depth": a["depth"],
                        "max_steps": a["max_steps"], "overrides": overrides, "videos_dir": videos,
                        "results_dir": str(a["out"] / RESULTS)}))
    return out


def finished_episodes(out: Path) -> list[dict]:
    """The results the workers saved, by episode index (a job stopped midway keeps its
    finished episodes)."""
    import json

    return [json.loads(p.read_text()) for p in sorted((out / RESULTS).glob("episode_*.json"))]


def ended_status(status: str, requested: int, finished: int, jobs: list) -> tuple[str, str]:
    """(status, note) of a run: one that ran to its end is ``complete`` only when every
    requested episode finished — ``partial`` when some did not (their job timed out, its
    process died or it raised), ``failed`` when none did; the note says how many and why."""
    if status != "complete" or finished >= requested:
        return status, ""
    why = Counter(str(r["error"]).split(":")[0] for r in jobs if r.get("error"))
    causes = ", ".join(f"{k} x{n}" for k, n in sorted(why.items())) or "no result"
    note = f"{requested - finished} of {requested} episodes did not run to their end ({causes})"
    return ("partial" if finished else "failed"), note


def _report(a: dict, status: str, phase: Optional[str], jobs: list, t0: float, settings) -> dict:
    from .eval_report import figures

    episodes = finished_episodes(a["out"])
    for e in episodes:
        if e.get("video"):
            e["video"] = os.path.relpath(e["video"], a["out"])
    errors = [f"job {r['index']}: {r['error']}" for r in jobs if r.get("error")]
    fig = figures(episodes, settings.record.task_template) if episodes else {}
    status, note = ended_status(status, a["episodes"], len(episodes), jobs)
    return {"status": status, "status_note": note, "phase": phase, "policy": a["policy"], "protocol": a["protocol"],
            "objects": str(a["objects"]), "seed": a["seed"], "episodes_requested": a["episodes"],
            "episodes_finished": len(episodes), **fig, "max_steps": a["max_steps"],
            "fps": settings.record.record_fps_hz, "image_size": [settings.record.image_height_px,
                                                                settings.record.image_width_px],
            "device": a["device"], "workers": a["workers"], "backend": a["backend"],
            "wall_s": round(time.perf_counter() - t0, 3), "errors": errors, "episodes": episodes}


def _write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (a temporary file renamed)."""
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def _remove_unreported_videos(out: Path, report: dict) -> None:
    """Delete every video that is not a reported episode's: an unfinished one (still named
    ``.partial``), or one whose episode's result was never saved (its job stopped — Ctrl-C,
    a timeout — between closing the video and saving the result)."""
    reported = {os.path.normpath(e["video"]) for e in report.get("episodes", []) if e.get("video")}
    for p in sorted((out / VIDEOS).glob("*")):
        if p.is_file() and os.path.relpath(p, out) not in reported:
            log.info("removed %s: its episode did not finish", p)
            p.unlink(missing_ok=True)


def _write(a: dict, report: dict) -> None:
    """``summary.md`` then ``eval.json`` (both atomically); no video of an unreported episode
    and no worker results (the report holds them) left."""
    import shutil

    from ..report.serialize import write_json
    from .eval_report import summary_markdown

    _remove_unreported_videos(a["out"], report)
    _write_text(a["out"] / SUMMARY_FILE, summary_markdown(report))
    write_json(a["out"] / REPORT_FILE, report)
    shutil.rmtree(a["out"] / RESULTS, ignore_errors=True)


def _run(a: dict, t0: float) -> tuple[dict, object]:
    """Check, load, simulate; (report, settings). Interrupted: the report says in which phase."""
    from ..bench.scheduler import run_jobs
    from ..report.serialize import write_json

    phase, rows, settings = "loading", [], None
    try:
        settings, env = check_inputs(a)
        a["policy"] = check_policy(a["policy"], env, a["device"])
        a["max_steps"] = env._max_episode_steps
        env.close()
        write_json(a["out"] / REPORT_FILE, _report(a, "running", "simulating", [], t0, settings))
        phase = "simulating"
        jobs = _tasks(a, settings.env.episodes_per_job, a["overrides"])
        rows, interrupted = run_jobs(jobs, _jobs(), min(a["workers"], len(jobs)), a["job_timeout_s"],
                                     a["progress"], a["backend"], a["address"])
    except KeyboardInterrupt:
        if settings is None:
            raise  # nothing was written yet: there is nothing to report
        interrupted = True
    status = "interrupted" if interrupted else "complete"
    return _report(a, status, phase if interrupted else None, rows, t0, settings), settings


def evaluate(policy: str, protocol: str = "sparse", objects: str = "builtin", episodes: int = 10,
             seed: int = 0, workers: int = 1, out: str | Path = "out/eval", backend: str = "local",
             address: Optional[str] = None, max_steps: Optional[int] = None, device: str = "cpu",
             video: bool = True, image_size: Optional[int] = None, fps: Optional[int] = None,
             depth: bool = False, overrides: tuple = (None, ()), progress: bool = True,
             job_timeout_s: float = 3600.0) -> dict:
    """Evaluate ``policy`` (see the module doc); returns the report."""
    from ..app.run_command import sigterm_as_interrupt
    from ..report.output_lock import output_claim
    from . import require_gymnasium

    require_gymnasium()  # before anything else: the environment is Gymnasium's
    a = {"policy": str(policy), "protocol": protocol, "objects": objects, "episodes": int(episodes),
         "seed": int(seed), "workers": int(workers), "out": Path(out), "backend": backend,
         "address": address, "max_steps": max_steps, "device": device, "video": bool(video),
         "image_size": image_size, "fps": fps, "depth": bool(depth), "overrides": overrides,
         "progress": progress, "job_timeout_s": job_timeout_s}
    t0 = time.perf_counter()
    check_out(a["out"])
    # marked at once, then checked again: another eval into this folder is refused (not mixed)
    with output_claim(a["out"], "eval") as claim, sigterm_as_interrupt():
        check_out(a["out"], claim)
        report, _settings = _run(a, t0)
        try:
            _write(a, report)
        except KeyboardInterrupt:
            report = {**report, "status": "interrupted", "phase": "writing"}
            _write(a, report)
            raise
    return report


def eval_main(args) -> int:
    """The ``eval`` sub-command: prints the headline; exit code 0 when complete, 130 when
    interrupted, 1 when episodes did not run to their end (``partial`` / ``failed``)."""
    report = evaluate(args.policy, protocol=args.protocol, objects=args.objects, episodes=args.episodes,
                      seed=args.seed, workers=args.workers, out=args.out, backend=args.backend,
                      address=args.address, max_steps=args.max_steps, device=args.device,
                      video=not args.no_video, image_size=args.image_size, fps=args.fps, depth=args.depth,
                      overrides=(args.config, args.sets), progress=not args.no_progress,
                      job_timeout_s=args.job_timeout)
    ci = report.get("ci95", [0.0, 1.0])
    print(f"{report['status']}: {report.get('successes', 0)} / {report['episodes_finished']} episodes "
          f"successful (95 % interval {ci[0]:.2f}–{ci[1]:.2f}); report {Path(args.out) / REPORT_FILE}")
    if report.get("status_note"):
        log.error("eval %s: %s", report["status"], report["status_note"])
    return {"complete": 0, "interrupted": 130}.get(report["status"], 1)
