"""The learning loop end to end, through the installed console scripts in a clean environment:
the environment's spaces are the recorded dataset's features; a recorded episode's actions,
replayed open loop in the environment, reach the same outcome through the same states; a tiny
ACT policy trained a few steps on the 2-episode dataset (:mod:`recorded`) is evaluated for one
episode by ``grasp-pipeline eval`` and by LeRobot's own ``lerobot-eval`` (no success asserted:
this proves the plumbing); bad input is refused before anything runs."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from recorded import IMAGE_PX, ONE_OBJECT, clean_env, run_cli

SIZE = ["--image-size", str(IMAGE_PX)]


def _load(root: Path):
    from lerobot.datasets.lerobot_dataset import LeRobotDataset

    return LeRobotDataset("grasp_pipeline/picks", root=root)


def _env(**kw):
    from grasp_pipeline.learning.pick_env import PickPlaceEnv

    return PickPlaceEnv("sparse", image_size=IMAGE_PX, overrides=(None, ONE_OBJECT), **kw)


def test_spaces_equal_the_recorded_datasets_features(recorded_dataset):
    root, _ = recorded_dataset
    feats = json.loads((root / "meta/info.json").read_text())["features"]
    env = _env()
    obs_space = env.observation_space.spaces
    assert set(obs_space) == {k for k in feats if k.startswith("observation.")}
    for key, space in obs_space.items():
        assert tuple(space.shape) == tuple(feats[key]["shape"]), key
        want = np.uint8 if feats[key]["dtype"] in ("video", "image") else np.dtype(feats[key]["dtype"])
        assert space.dtype == want, key
    assert tuple(env.action_space.shape) == tuple(feats["action"]["shape"]) == (8,)
    obs, info = env.reset(seed=7)
    assert env.observation_space.contains(obs) and info["task"] == env.task
    env.close()


def test_replayed_actions_reach_the_recorded_outcome_through_the_recorded_states(recorded_dataset):
    """Open loop, same scene seed: every state within the executor's tolerance of the recorded
    one (``motion.settle_position_tol_rad``) and the same outcome at the same step."""
    from grasp_pipeline.settings import load_settings

    tol = load_settings(["motion"]).motion.settle_position_tol_rad
    root, _ = recorded_dataset
    ds = _load(root)
    outcomes = [json.loads(x) for x in (root / "meta/grasp_pipeline_episodes.jsonl").read_text().splitlines()]
    env = _env()
    for k, o in enumerate(outcomes):
        ep = ds.meta.episodes[k]
        rows = range(ep["dataset_from_index"], ep["dataset_to_index"])
        state = np.stack([np.asarray(ds.hf_dataset[i]["observation.state"]) for i in rows])
        action = np.stack([np.asarray(ds.hf_dataset[i]["action"]) for i in rows])
        obs, info = env.reset(seed=o["scene_seed"])
        assert info["task"] == o["task"] and info["target"] == o["object"]
        worst, ended = 0.0, []
        for i, a in enumerate(action):
            worst = max(worst, float(np.max(np.abs(obs["observation.state"] - state[i]))))
            obs, _r, terminated, truncated, _info = env.step(a)
            if terminated or truncated:
                ended.append((i, terminated))
        assert worst <= tol
        if o["success"]:  # the recording ended when the environment said the target rests in the tray
            assert ended == [(len(action) - 1, True)]
        else:
            assert not any(t for _, t in ended)
    env.close()


def test_a_tiny_trained_policy_runs_in_eval(trained_policy, tmp_path):
    pol, summary = trained_policy
    assert summary["status"] == "complete" and summary["steps"] == 3 and summary["episodes"] >= 1
    assert {"config.json", "model.safetensors", "policy_preprocessor.json", "train_summary.json"} <= \
        {p.name for p in pol.iterdir()}
    res = run_cli(["--log-level", "WARNING", "eval", "--policy", str(pol), "--episodes", "1", "--seed", "11",
                   "--max-steps", "15", "--no-progress", "--out", "ev", *SIZE, "--set", ONE_OBJECT[0]], tmp_path)
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr[-3000:]
    report = json.loads((tmp_path / "ev/eval.json").read_text())
    assert report["status"] == "complete" and report["episodes_finished"] == 1
    (ep,) = report["episodes"]
    assert ep["steps"] == 15 and ep["success"] is False and ep["failed_stage"] == "TIME_LIMIT"
    assert ep["task"].startswith("pick up the ") and "the target is" in ep["failure_reason"]
    assert report["ci95"][0] == 0.0 and 0.0 < report["ci95"][1] < 1.0
    assert (tmp_path / "ev" / ep["video"]).stat().st_size > 0
    assert "success rate" in (tmp_path / "ev/summary.md").read_text()


def test_lerobot_eval_runs_the_environment_through_the_plugin(trained_policy, tmp_path):
    """LeRobot's own evaluation command with this package as its environment plugin."""
    exe = Path(sys.executable).parent / "lerobot-eval"
    assert exe.exists(), f"{exe} is missing (make setup installs lerobot)"
    args = [str(exe), "--env.discover_packages_path=grasp_pipeline.learning.lerobot_plugin",
            "--env.type=grasp_pipeline", f"--env.image_size={IMAGE_PX}", "--env.episode_length=5",
            f"--policy.path={trained_policy[0]}", "--eval.n_episodes=1", "--eval.batch_size=1",
            "--policy.device=cpu", "--output_dir=le"]
    res = subprocess.run(args, cwd=tmp_path, env=clean_env(tmp_path), capture_output=True, text=True,
                         timeout=900, stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stderr[-3000:]
    info = json.loads((tmp_path / "le/eval_info.json").read_text())
    assert info["overall"]["n_episodes"] == 1


def test_eval_refuses_a_policy_that_does_not_fit_the_environment(trained_policy, tmp_path):
    """One line naming the mismatched input and its shapes, before any simulation."""
    from grasp_pipeline.exceptions import InputError
    from grasp_pipeline.learning.eval_command import evaluate

    with pytest.raises(InputError) as refused:
        evaluate(str(trained_policy[0]), episodes=1, out=tmp_path / "ev")   # 256 px by default
    line = str(refused.value)
    assert "\n" not in line and f"(3, {IMAGE_PX}, {IMAGE_PX})" in line and "(3, 256, 256)" in line
    assert line.startswith("--policy: the policy's input observation.images.") and f"--image-size {IMAGE_PX}" in line
    assert not (tmp_path / "ev" / "eval.json").exists()
