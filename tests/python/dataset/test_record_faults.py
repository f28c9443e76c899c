"""``record`` interrupted in each phase leaves the finished episodes as a loadable LeRobot
dataset, or ``--out`` marked incomplete (``RECORD_INCOMPLETE.json``) with the finished episodes
kept — never part of a dataset:

* while loading the objects: nothing is written;
* while simulating (Ctrl-C from a terminal, the installed command): the episodes finished so
  far are written as a complete dataset that says ``interrupted``;
* while writing (inside LeRobot's merge): ``--out`` holds only the marker, the staging folder
  is gone, the finished episodes stay in the work folder, each a loadable dataset.
"""

from __future__ import annotations

import json
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from grasp_pipeline.config import build_config
from grasp_pipeline.dataset import dataset_folder as df
from grasp_pipeline.dataset.config import RecordConfig
from grasp_pipeline.dataset.episode import Episode
from recorded import EXE, clean_env


def _load(root: Path):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    return LeRobotDataset("grasp_pipeline/picks", root=root)


def _as_from_a_terminal() -> None:
    """Ctrl-C as a terminal delivers it (a backgrounded test runner passes SIGINT on ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_interrupted_while_loading_objects_leaves_nothing(tmp_path, monkeypatch):
    import grasp_pipeline.objects.catalog as catalog
    from grasp_pipeline.dataset.record_command import record_dataset

    def interrupted(_source):
        raise KeyboardInterrupt

    monkeypatch.setattr(catalog, "object_set", interrupted)
    with pytest.raises(KeyboardInterrupt):
        record_dataset(protocol="packed", objects="builtin", episodes=1, out=tmp_path / "ds", progress=False)
    assert not list(tmp_path.glob("*")) and not list(tmp_path.glob(".ds*"))


def test_interrupted_while_simulating_writes_the_finished_episodes(tmp_path):
    args = [str(EXE), "record", "--protocol", "sparse", "--episodes", "3", "--seed", "4", "--workers", "1",
            "--keep-failed", "--no-progress", "--image-size", "32", "--set", "sim.object_count=[1,1]",
            "--set", "env.episodes_per_job=1", "--out", "ds"]
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
    time.sleep(1.0)  # the parent receives the job's record
    marker = json.loads((tmp_path / "ds" / df.MARKER).read_text())
    assert marker["phase"] == "recording" and sorted(p.name for p in (tmp_path / "ds").iterdir()) == [df.MARKER]
    proc.send_signal(signal.SIGINT)
    out, rest = proc.communicate(timeout=600)
    assert proc.returncode == 130 and "Traceback" not in rest, (seen + rest)[-3000:]
    summary = json.loads(out)
    assert summary["status"] == "interrupted" and 1 <= summary["episodes_written"] < 3
    ds = _load(tmp_path / "ds")
    assert ds.num_episodes == summary["episodes_written"]
    meta = json.loads((tmp_path / "ds/meta/grasp_pipeline_record.json").read_text())
    assert meta["status"] == "interrupted" and not (tmp_path / "ds" / df.MARKER).exists()
    assert not list(tmp_path.glob(".ds.*"))      # no work or staging folder left


def _episode(n: int, seed: int) -> Episode:
    rng = np.random.default_rng(seed)
    f = lambda k: rng.random((n, k), dtype=np.float32)  # noqa: E731
    return Episode(task=f"pick up the red cube and put it in the tray", success=True, failed_stage="",
                   message="", object="cube_0", time_s=np.arange(n) / 15.0, state=f(8), ee_pose=f(7),
                   action=f(8), action_ee_delta=f(7),
                   images={c: rng.integers(0, 255, (n, 32, 32, 3), dtype=np.uint8) for c in ("wrist", "scene")})


def _finished_episodes(out: Path) -> tuple[dict, list]:
    """Two finished episodes (shards) in ``out``'s work folder, and the job rows."""
    from grasp_pipeline.dataset.shards import write_shard

    cfg = build_config(RecordConfig, {"image_width_px": 32, "image_height_px": 32})
    work = df.work_dir(out)
    rows = []
    for i, seed in ((0, 11), (1, 12)):
        ep = _episode(5 + i, seed)
        path = write_shard(work, i, seed, ep, {"scene_seed": seed, "attempt": i}, cfg, False)
        rows.append({"index": i, "episodes": [{"index": i, "shard": str(path), **ep.outcome()}],
                     "error": None, "timings": {"wall_s": 1.0}})
    df.mark_incomplete(out, "recording", "record is running")
    a = {"out": out, "episodes": 2, "repo_id": cfg.repo_id, "workers": 1, "backend": "local", "per_job": 1,
         "video_file_size_mb": cfg.video_file_size_mb}
    return a, rows


def test_interrupted_while_writing_keeps_the_episodes_and_marks_the_folder(tmp_path, monkeypatch):
    import lerobot.datasets.aggregate as aggregate

    from grasp_pipeline.dataset.record_command import _write

    out = tmp_path / "ds"
    a, rows = _finished_episodes(out)

    def interrupted(*args, **kwargs):  # after the videos were copied into the staging folder
        assert any(df.staging_dir(out).rglob("*.mp4"))
        raise KeyboardInterrupt

    monkeypatch.setattr(aggregate, "aggregate_data", interrupted)
    with pytest.raises(KeyboardInterrupt):
        _write(a, rows, False, time.perf_counter())
    assert sorted(p.name for p in out.iterdir()) == [df.MARKER]
    marker = json.loads((out / df.MARKER).read_text())
    assert marker["phase"] == "writing" and marker["episodes_finished"] == 2
    assert "KeyboardInterrupt" in marker["reason"] and Path(marker["episodes_folder"]) == df.work_dir(out)
    assert not df.staging_dir(out).exists()
    kept = sorted(df.work_dir(out).iterdir())
    assert [p.name for p in kept] == ["episode_00000_scene_11", "episode_00001_scene_12"]
    assert [_load(p).num_frames for p in kept] == [5, 6]


def test_written_in_episode_order_then_the_work_folder_is_removed(tmp_path):
    """(with video files so small that each episode starts a new one: the merged dataset reads
    its frames from both)"""
    from grasp_pipeline.dataset.record_command import _write

    out = tmp_path / "ds"
    a, rows = _finished_episodes(out)
    a["video_file_size_mb"] = 1e-6
    summary = _write(a, rows, False, time.perf_counter())
    assert summary["status"] == "complete" and summary["episodes_written"] == 2
    ds = _load(out)
    assert ds.num_episodes == 2 and [ep["length"] for ep in ds.meta.episodes] == [5, 6]
    assert len(list((out / "videos/observation.images.scene").rglob("*.mp4"))) == 2
    assert tuple(ds[0]["observation.images.scene"].shape) == tuple(ds[10]["observation.images.scene"].shape) == (3, 32, 32)
    outcomes = [json.loads(x) for x in (out / "meta/grasp_pipeline_episodes.jsonl").read_text().splitlines()]
    assert [(o["episode_index"], o["scene_seed"]) for o in outcomes] == [(0, 11), (1, 12)]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ds"] and not (out / df.MARKER).exists()
