"""``train`` interrupted keeps the policy trained so far, saved as LeRobot saves policies."""

from __future__ import annotations

import json

from recorded import IMAGE_PX, TINY_ACT


def test_interrupted_training_saves_the_policy_trained_so_far(recorded_dataset, tmp_path, monkeypatch):
    from grasp_pipeline.learning import train_command
    from grasp_pipeline.learning.compatibility import policy_config

    real_step, calls = train_command._Training.step, []

    def step(self, batch):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real_step(self, batch)

    monkeypatch.setattr(train_command._Training, "step", step)
    sets = tuple(TINY_ACT[1::2])
    summary = train_command.train_policy(recorded_dataset[0], tmp_path / "pol", steps=10, batch_size=2,
                                         image_size=IMAGE_PX, overrides=(None, sets))
    assert summary["status"] == "interrupted" and summary["steps"] == 2 and summary["steps_requested"] == 10
    saved = json.loads((tmp_path / "pol/train_summary.json").read_text())
    assert saved["status"] == "interrupted" and saved["steps"] == 2
    assert policy_config(tmp_path / "pol").type == "act"
    assert not list(tmp_path.glob(".pol.*"))
