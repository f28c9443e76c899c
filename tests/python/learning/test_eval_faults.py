"""``eval`` interrupted in each phase leaves a valid report that says so (``eval.json`` with
``"status": "interrupted"`` and the phase, ``summary.md``), the finished episodes with their
videos, and no unfinished video:

* while loading the policy: a report with no episode;
* while simulating (Ctrl-C from a terminal, the installed command): the finished episodes;
* while writing the report: the report again, saying it was interrupted while writing.
"""

from __future__ import annotations

import json
import signal
import subprocess
import time
from pathlib import Path

import pytest

import grasp_pipeline.learning.eval_command as eval_command
from recorded import EXE, IMAGE_PX, clean_env


def _as_from_a_terminal() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


#: A finished episode's result, as a worker saves it.
EPISODE = {"index": 0, "scene_seed": 1, "task": "pick up the red cube and put it in the tray",
           "target": "cube_0", "target_model": "cube", "success": True, "terminated": True,
           "truncated": False, "failed_stage": "", "failure_reason": "", "target_state": "in the tray",
           "steps": 200, "sim_s": 13.3, "wall_s": 9.0, "video": None, "error": None, "extra": {}}


def _files(out):
    return sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())


def test_interrupted_while_loading_the_policy(tmp_path, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(eval_command, "check_policy", interrupted)
    report = eval_command.evaluate("reference", episodes=2, out=tmp_path / "ev", progress=False)
    assert report["status"] == "interrupted" and report["phase"] == "loading"
    assert json.loads((tmp_path / "ev/eval.json").read_text())["episodes_finished"] == 0
    assert _files(tmp_path / "ev") == ["eval.json", "summary.md"]


def test_interrupted_while_simulating_keeps_the_finished_episodes(trained_policy, tmp_path):
    args = [str(EXE), "eval", "--policy", str(trained_policy[0]), "--episodes", "3", "--seed", "5",
            "--max-steps", "30", "--no-progress", "--image-size", str(IMAGE_PX),
            "--set", "sim.object_count=[1,1]", "--set", "env.episodes_per_job=1", "--out", "ev"]
    proc = subprocess.Popen(args, cwd=tmp_path, env=clean_env(tmp_path), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL,
                            preexec_fn=_as_from_a_terminal)
    seen, t_end = "", time.monotonic() + 900
    while "episode 0 (scene" not in seen and time.monotonic() < t_end:
        line = proc.stderr.readline()
        if not line:
            break
        seen += line
    assert "episode 0 (scene" in seen, seen[-3000:]
    running = json.loads((tmp_path / "ev/eval.json").read_text())
    assert running["status"] == "running"                       # a report exists from the start
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    _, rest = proc.communicate(timeout=600)
    assert proc.returncode == 130 and "Traceback" not in rest, (seen + rest)[-3000:]
    report = json.loads((tmp_path / "ev/eval.json").read_text())
    assert report["status"] == "interrupted" and report["phase"] == "simulating"
    assert 1 <= report["episodes_finished"] < 3
    videos = [f for f in _files(tmp_path / "ev") if f.startswith("videos/")]
    assert videos == sorted(e["video"] for e in report["episodes"])   # no unfinished (.partial) video
    assert "interrupted" in (tmp_path / "ev/summary.md").read_text()


def test_interrupted_while_writing_the_report(tmp_path, monkeypatch):
    import grasp_pipeline.bench.scheduler as scheduler

    episode = dict(EPISODE)

    def run_jobs(tasks, *args, **kwargs):  # a worker's finished episode, saved as workers save it
        from grasp_pipeline.report.serialize import write_json

        write_json(Path(tasks[0][1]["results_dir"]) / "episode_00000.json", episode)
        return [{"index": 0, "episodes": [episode], "error": None}], False

    monkeypatch.setattr(scheduler, "run_jobs", run_jobs)
    calls = []
    original = eval_command._write_text

    def write_text(path, text):
        calls.append(path)
        if len(calls) == 1:
            raise KeyboardInterrupt
        original(path, text)

    monkeypatch.setattr(eval_command, "_write_text", write_text)
    with pytest.raises(KeyboardInterrupt):
        eval_command.evaluate("reference", episodes=1, out=tmp_path / "ev", progress=False, video=False)
    report = json.loads((tmp_path / "ev/eval.json").read_text())
    assert report["status"] == "interrupted" and report["phase"] == "writing"
    assert report["episodes_finished"] == 1 and report["successes"] == 1
    assert _files(tmp_path / "ev") == ["eval.json", "summary.md"]


def test_the_video_of_an_episode_whose_result_was_not_saved_is_removed(tmp_path, monkeypatch):
    """Ctrl-C reaching a worker after it closed an episode's video but before it saved the
    episode's result: the report cannot hold that episode, so its video goes like an
    unfinished one's — the videos left are exactly the reported episodes'."""
    import grasp_pipeline.bench.scheduler as scheduler
    from grasp_pipeline.report.serialize import write_json

    def run_jobs(tasks, *args, **kwargs):
        job = tasks[0][1]
        videos = Path(job["videos_dir"])
        videos.mkdir(parents=True, exist_ok=True)
        saved = videos / "episode_0000_scene_1.mp4"
        saved.write_bytes(b"mp4")
        write_json(Path(job["results_dir"]) / "episode_00000.json", {**EPISODE, "video": str(saved)})
        (videos / "episode_0001_scene_2.mp4").write_bytes(b"mp4")         # result never saved
        (videos / "episode_0002_scene_3.partial.mp4").write_bytes(b"mp")  # still being written
        return [], True                                                     # interrupted

    monkeypatch.setattr(scheduler, "run_jobs", run_jobs)
    report = eval_command.evaluate("reference", episodes=3, out=tmp_path / "ev", progress=False)
    assert report["status"] == "interrupted" and report["episodes_finished"] == 1
    assert [e["video"] for e in report["episodes"]] == ["videos/episode_0000_scene_1.mp4"]
    assert _files(tmp_path / "ev") == ["eval.json", "summary.md", "videos/episode_0000_scene_1.mp4"]


def test_eval_marks_its_folder_before_the_slow_checks_and_refuses_a_marked_one(tmp_path, monkeypatch):
    """``eval`` marks ``--out`` as soon as it is checked (a second ``eval`` started into it
    while the first loads finds it not empty) and checks it again once marked: a folder that
    holds anything but its own marker (another eval marked it meanwhile) is refused."""
    import json
    import subprocess

    from grasp_pipeline.exceptions import InputError
    from grasp_pipeline.report.output_lock import PREFIX, SUFFIX, _process_start, claim_output

    seen = []

    def check_inputs(a):
        seen.append(sorted(p.name for p in a["out"].iterdir()))
        raise InputError("stop here")

    monkeypatch.setattr(eval_command, "check_inputs", check_inputs)
    out = tmp_path / "ev"
    with pytest.raises(InputError, match="stop here"):
        eval_command.evaluate("reference", episodes=1, out=out, progress=False)
    assert len(seen[0]) == 1 and seen[0][0].startswith(PREFIX)   # marked while checking
    assert list(out.iterdir()) == []                               # and unmarked after

    mine = claim_output(out, "eval")
    eval_command.check_out(out, mine)                              # only its own marker: fine
    other = subprocess.Popen(["sleep", "30"])
    try:
        (out / f"{PREFIX}elsewhere-{other.pid}{SUFFIX}").write_text(json.dumps(
            {"pid": other.pid, "process_start": _process_start(other.pid), "command": "eval"}))
        with pytest.raises(InputError, match="exists and is not an empty folder"):
            eval_command.check_out(out, mine)
    finally:
        other.kill()
        other.wait()
        mine.release()


def test_an_eval_whose_jobs_did_not_run_to_their_end_fails(tmp_path, monkeypatch):
    """Every job timed out (no episode saved): status failed with a note saying why, exit
    code 1 — not "complete: 0 / 0 episodes" with exit code 0."""
    import grasp_pipeline.bench.scheduler as scheduler
    from grasp_pipeline.cli import build_parser

    def run_jobs(tasks, *args, **kwargs):
        return [{"index": t[0], "episodes": [], "error": "Timeout: the job took longer than 1 s wall time"}
                for t in tasks], False

    monkeypatch.setattr(scheduler, "run_jobs", run_jobs)
    args = build_parser().parse_args(["eval", "--policy", "reference", "--episodes", "2", "--no-video",
                                      "--no-progress", "--set", "env.episodes_per_job=1",
                                      "--out", str(tmp_path / "ev")])
    assert eval_command.eval_main(args) == 1
    report = json.loads((tmp_path / "ev/eval.json").read_text())
    assert report["status"] == "failed" and report["episodes_finished"] == 0
    assert report["status_note"] == "2 of 2 episodes did not run to their end (Timeout x2)"
    assert report["status_note"] in (tmp_path / "ev/summary.md").read_text()


def test_the_status_says_whether_every_episode_ran_to_its_end():
    ok, timeout, died = {"error": None}, {"error": "Timeout: 1 s"}, {"error": "WorkerDied: code -9"}
    assert eval_command.ended_status("complete", 2, 2, [ok]) == ("complete", "")
    assert eval_command.ended_status("complete", 3, 1, [ok, timeout, died]) == (
        "partial", "2 of 3 episodes did not run to their end (Timeout x1, WorkerDied x1)")
    assert eval_command.ended_status("interrupted", 3, 1, [timeout]) == ("interrupted", "")
