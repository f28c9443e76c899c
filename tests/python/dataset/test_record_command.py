"""``grasp-pipeline record``: a 2-episode dataset through the installed console script in a
clean environment (the session's shared run, :mod:`recorded`), read back with LeRobot's own
``LeRobotDataset``; the same seed on the Ray backend gives the same dataset; without LeRobot
the command refuses before simulating.

The two episodes are the environment's episodes on two one-object sparse scenes (2 workers,
one episode each) with ``--keep-failed``, so the dataset holds both whatever their outcome.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from grasp_pipeline.bench.seeds import scene_seed
from recorded import EPISODES, IMAGE_PX, ONE_OBJECT, SEED, record


@pytest.fixture(scope="module")
def datasets(recorded_dataset, tmp_path_factory):
    d = tmp_path_factory.mktemp("ray")
    res = record(d, "ray")
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr[-3000:]
    return {"local": recorded_dataset, "ray": (d / "ds", json.loads(res.stdout))}


def _load(root: Path):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    return LeRobotDataset("grasp_pipeline/picks", root=root)


def _columns(ds, key: str) -> np.ndarray:
    return np.stack([np.asarray(v) for v in ds.hf_dataset[key]])


def _outcomes(root: Path) -> list[dict]:
    return [json.loads(line) for line in (root / "meta/grasp_pipeline_episodes.jsonl").read_text().splitlines()]


def test_dataset_loads_with_lerobot_with_its_features_and_episodes(recorded_dataset):
    root, summary = recorded_dataset
    assert summary["status"] == "complete" and summary["episodes_written"] == EPISODES
    assert sorted(p.name for p in root.iterdir()) == ["data", "meta", "videos"]  # no marker, no temp files
    assert not list(root.parent.glob(".ds.*")), "work or staging folders left behind"
    info = json.loads((root / "meta/info.json").read_text())
    assert info["codebase_version"] == "v3.0" and info["fps"] == 15
    ds = _load(root)
    assert ds.fps == 15 and ds.num_episodes == EPISODES
    item = ds[0]
    for cam in ("wrist", "scene"):
        img = item[f"observation.images.{cam}"]
        assert tuple(img.shape) == (3, IMAGE_PX, IMAGE_PX)
        assert float(img.std()) > 0.01, f"{cam} image is blank"
    assert tuple(item["observation.state"].shape) == (8,) and tuple(item["action"].shape) == (8,)
    assert tuple(item["observation.ee_pose"].shape) == (7,) and tuple(item["action.ee_delta"].shape) == (7,)
    # episode boundaries: contiguous index ranges, frame_index restarting at 0, lengths as listed
    ep_index, frame_index = _columns(ds, "episode_index"), _columns(ds, "frame_index")
    start = 0
    for k, o in enumerate(_outcomes(root)):
        ep = ds.meta.episodes[k]
        assert (ep["dataset_from_index"], ep["dataset_to_index"]) == (start, start + o["length"])
        assert np.all(ep_index[start:start + o["length"]] == k)
        assert np.array_equal(frame_index[start:start + o["length"]], np.arange(o["length"]))
        start += o["length"]
    assert start == ds.num_frames


def test_tasks_and_outcomes_name_each_target(recorded_dataset):
    from grasp_pipeline.app.sim_system import make_scene
    from grasp_pipeline.dataset.record_settings import record_settings
    from grasp_pipeline.language.colours import colour_name

    root, _ = recorded_dataset
    ds, outcomes = _load(root), _outcomes(root)
    success, done = _columns(ds, "episode.success"), _columns(ds, "next.done")
    stages = [str(x) for x in ds.hf_dataset["episode.failed_stage"]]
    settings = record_settings((None, ONE_OBJECT))
    for k, o in enumerate(outcomes):
        assert o["scene_seed"] == scene_seed(SEED, o["attempt"]) and o["attempt"] == k
        (obj,) = make_scene("sparse", o["scene_seed"], settings).objects
        colour = colour_name(tuple(obj.rgba)[:3])  # sparse primitives: colour from their RGBA
        assert o["task"] == f"pick up the {colour} {obj.category or obj.kind} and put it in the tray"
        assert o["object"] == obj.name
        ep = ds.meta.episodes[k]
        assert list(ep["tasks"]) == [o["task"]]
        rows = slice(ep["dataset_from_index"], ep["dataset_to_index"])
        assert set(success[rows].reshape(-1).tolist()) == {o["success"]}
        assert set(stages[rows]) == {o["failed_stage"]}
        assert done[rows].reshape(-1).tolist() == [False] * (o["length"] - 1) + [True]
    assert set(ds.meta.tasks.index) == {o["task"] for o in outcomes}


def test_each_action_leads_to_the_next_state(recorded_dataset):
    """Frame i's joint targets are reached at frame i+1's time: the measured joints at i+1 lie
    within the executor's own "reached" tolerance of them (``motion.settle_position_tol_rad``,
    5 mrad; the servos with velocity feed-forward track the ramps far closer), while the arm
    moves tens of mrad between frames — so a target one frame late or early would fail this."""
    from grasp_pipeline.settings import load_settings

    tol = load_settings(["motion"]).motion.settle_position_tol_rad
    root, _ = recorded_dataset
    ds = _load(root)
    state, action = _columns(ds, "observation.state"), _columns(ds, "action")
    for ep in ds.meta.episodes:
        a, b = ep["dataset_from_index"], ep["dataset_to_index"]
        q, target = state[a:b, :7], action[a:b, :7]
        assert np.max(np.abs(q[1:] - target[:-1])) <= tol
        assert np.max(np.abs(np.diff(q, axis=0))) > 5 * tol          # the arm really moved
        assert np.max(np.abs(q[:-1] - target[:-1])) > tol            # i's state is not i's action


def test_ray_backend_writes_the_same_dataset(datasets):
    (local, s_local), (ray, s_ray) = datasets["local"], datasets["ray"]
    assert s_ray["backend"] == "ray" and s_ray["status"] == "complete"
    assert _outcomes(local) == _outcomes(ray)
    a, b = _load(local), _load(ray)
    for key in ("observation.state", "observation.ee_pose", "action", "action.ee_delta",
                "episode_index", "frame_index", "task_index"):
        assert np.array_equal(_columns(a, key), _columns(b, key)), key


def test_rerun_recording_of_every_episode_reads_back(recorded_dataset):
    """``--rerun DIR``: one readable recording per episode, named after the episode's scene seed."""
    from grasp_pipeline.report.rerun_summary import summarize_recording

    recs = recorded_dataset[0].parent / "recs"
    names = sorted(p.name for p in recs.glob("*.rrd"))
    assert names == sorted(f"episode_{i:05d}_scene_{scene_seed(SEED, i)}.rrd" for i in range(EPISODES))
    for p in recs.glob("*.rrd"):
        summary = summarize_recording(p)
        assert summary["/world/objects"].logs >= 1


def test_record_without_lerobot_refuses_before_simulating(tmp_path):
    code = ("import sys; sys.modules['lerobot'] = None\n"
            "from grasp_pipeline.cli import main\n"
            "sys.exit(main(['record', '--episodes', '1', '--out', 'ds']))")
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         timeout=300)
    assert res.returncode != 0 and "Traceback" not in res.stderr, res.stderr[-2000:]
    assert "pip install 'grasp-pipeline[dataset]'" in res.stderr
    assert not (tmp_path / "ds").exists()


def test_record_refuses_a_used_output_folder(tmp_path):
    (tmp_path / "ds").mkdir()
    (tmp_path / "ds" / "keep.txt").write_text("mine")
    code = ("import sys\nfrom grasp_pipeline.cli import main\n"
            "sys.exit(main(['record', '--episodes', '1', '--out', 'ds']))")
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         timeout=300)
    assert res.returncode != 0 and "not an empty folder" in res.stderr
    assert (tmp_path / "ds" / "keep.txt").read_text() == "mine"
