"""Bad input for eval and train is refused with one line that says what is wrong."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest

from grasp_pipeline.exceptions import InputError
from grasp_pipeline.learning.compatibility import check_dataset, check_policy_features, policy_config
from recorded import IMAGE_PX


def _spaces(side: int = 64):
    from grasp_pipeline.config import build_config
    from grasp_pipeline.dataset.config import RecordConfig
    from grasp_pipeline.learning.spaces import action_space, observation_space

    cfg = build_config(RecordConfig, {"image_width_px": side, "image_height_px": side})
    return observation_space(cfg), action_space(cfg)


def _cfg(inputs: dict, action=(8,)):
    feat = lambda s: SimpleNamespace(shape=s)  # noqa: E731
    return SimpleNamespace(input_features={k: feat(s) for k, s in inputs.items()},
                           output_features={"action": feat(action)})


def test_policy_inputs_must_be_observations_of_the_environment_with_their_shapes():
    obs, act = _spaces(64)
    check_policy_features(_cfg({"observation.images.wrist": (3, 64, 64), "observation.state": (8,)}), obs, act)
    with pytest.raises(InputError, match=r"observation\.images\.top \(3, 64, 64\) is not an observation"):
        check_policy_features(_cfg({"observation.images.top": (3, 64, 64)}), obs, act)
    with pytest.raises(InputError, match=r"is \(3, 128, 128\), the environment gives \(3, 64, 64\) "
                                         r"\(images of 128 px: --image-size 128\)"):
        check_policy_features(_cfg({"observation.images.scene": (3, 128, 128)}), obs, act)
    with pytest.raises(InputError, match=r"observation\.state is \(14,\)"):
        check_policy_features(_cfg({"observation.state": (14,)}), obs, act)
    with pytest.raises(InputError, match=r"action is \(14,\), the environment's is \(8,\)"):
        check_policy_features(_cfg({"observation.state": (8,)}, action=(14,)), obs, act)


def test_a_policy_folder_must_exist_and_hold_a_lerobot_policy(tmp_path):
    with pytest.raises(InputError, match="no such folder"):
        policy_config(tmp_path / "nope")
    with pytest.raises(InputError, match="missing config.json, model.safetensors"):
        policy_config(tmp_path)
    for name in ("config.json", "model.safetensors", "policy_preprocessor.json", "policy_postprocessor.json"):
        (tmp_path / name).write_text("{}")
    with pytest.raises(InputError, match="config.json is not a LeRobot policy config"):
        policy_config(tmp_path)


def test_a_dataset_must_be_a_complete_lerobot_dataset_recorded_with_the_same_options(recorded_dataset, tmp_path):
    from grasp_pipeline.dataset.dataset_folder import MARKER

    obs, _ = _spaces(IMAGE_PX)
    feats = {k: {"shape": s.shape} for k, s in obs.spaces.items()}
    root, _ = recorded_dataset
    assert check_dataset(root, feats, 15).total_episodes == 2
    with pytest.raises(InputError, match="no such folder"):
        check_dataset(tmp_path / "nope", feats, 15)
    with pytest.raises(InputError, match="not a LeRobot dataset"):
        check_dataset(tmp_path, feats, 15)
    (tmp_path / MARKER).write_text(json.dumps({"reason": "stopped while writing"}))
    with pytest.raises(InputError, match="incomplete record output .stopped while writing"):
        check_dataset(tmp_path, feats, 15)
    other, _ = _spaces(128)
    with pytest.raises(InputError, match=rf"recorded with observation\.images\.\w+ \({IMAGE_PX}, {IMAGE_PX}, 3\), "
                                         rf"the environment gives \(128, 128, 3\).*--image-size {IMAGE_PX}"):
        check_dataset(root, {k: {"shape": s.shape} for k, s in other.spaces.items()}, 15)
    with pytest.raises(InputError, match="recorded at 15 fps, the environment runs at 30: use --fps 15"):
        check_dataset(root, feats, 30)


def test_train_and_eval_refuse_bad_input_before_any_work(recorded_dataset, tmp_path):
    from grasp_pipeline.learning.eval_command import evaluate
    from grasp_pipeline.learning.train_command import train_policy

    root, _ = recorded_dataset
    with pytest.raises(InputError, match=rf"recorded with observation.images.\w+ \({IMAGE_PX}, {IMAGE_PX}, 3\)"):
        train_policy(root, tmp_path / "pol", steps=1)              # 256 px by default: recorded at 64
    with pytest.raises(InputError, match="protocol must be one of sparse, packed, pile, got 'heap'"):
        evaluate("reference", protocol="heap", out=tmp_path / "ev")
    with pytest.raises(InputError, match="--policy .*: no such folder"):
        evaluate(str(tmp_path / "nope"), out=tmp_path / "ev2")
    (tmp_path / "used").mkdir()
    (tmp_path / "used" / "mine.txt").write_text("x")
    with pytest.raises(InputError, match="not an empty folder"):
        evaluate("reference", out=tmp_path / "used")
    assert not (tmp_path / "pol").exists() and not (tmp_path / "ev" / "eval.json").exists()
    assert not (tmp_path / "ev2" / "eval.json").exists()


def test_eval_without_gymnasium_refuses_with_the_install_command(tmp_path):
    import os
    import subprocess
    import sys
    from pathlib import Path

    import grasp_pipeline

    # the child imports the package this test imports (its folder first on the path)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(grasp_pipeline.__file__).parents[1]),
                                                         os.environ.get("PYTHONPATH", "")])}
    code = ("import sys; sys.modules['gymnasium'] = None\n"
            "from grasp_pipeline.cli import main\n"
            "sys.exit(main(['eval', '--policy', 'reference', '--out', 'ev']))")
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         timeout=300, env=env)
    assert res.returncode == 2 and "Traceback" not in res.stderr, res.stderr[-2000:]
    assert "pip install 'grasp-pipeline[learning]'" in res.stderr and not (tmp_path / "ev").exists()
