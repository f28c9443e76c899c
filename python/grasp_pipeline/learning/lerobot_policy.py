"""A policy saved by LeRobot (``save_pretrained`` of the policy and its pre/post-processors),
acting in the environment: observation -> LeRobot batch -> pre-processor -> ``select_action``
-> post-processor -> action.

The batch is what LeRobot's own evaluation feeds a policy: images channel first, float in
[0, 1], with a batch dimension; vectors float32 with a batch dimension; the task sentence under
``task``. Only the policy's input features are passed.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def policy_batch(obs: dict, task: str, keys) -> dict:
    """The LeRobot batch of one observation (see the module doc)."""
    import torch

    batch = {}
    for key in keys:
        v = np.asarray(obs[key])
        t = torch.from_numpy(np.ascontiguousarray(v))
        if v.ndim == 3:  # an image (H, W, C): uint8 RGB or float32 depth
            t = t.permute(2, 0, 1).float()
            if v.dtype == np.uint8:
                t = t / 255.0
        batch[key] = t.float().unsqueeze(0)
    batch["task"] = [task]
    return batch


class LeRobotPolicy:
    """The policy at ``path`` on ``device`` (``cpu`` or ``cuda``)."""

    def __init__(self, path, device: str = "cpu") -> None:
        import torch
        from lerobot.policies.factory import get_policy_class, make_pre_post_processors

        from .compatibility import policy_config

        self.path = Path(path)
        cfg = policy_config(self.path)
        cfg.device = device
        self.policy = get_policy_class(cfg.type).from_pretrained(str(self.path), config=cfg)
        self.policy.to(device).eval()
        self.pre, self.post = make_pre_post_processors(
            cfg, pretrained_path=str(self.path),
            preprocessor_overrides={"device_processor": {"device": device}})
        self.keys = list(cfg.input_features)
        self.name = f"{cfg.type}:{self.path}"
        self._torch = torch

    def reset(self) -> None:
        self.policy.reset()

    def act(self, obs: dict, task: str) -> np.ndarray:
        with self._torch.inference_mode():
            action = self.policy.select_action(self.pre(policy_batch(obs, task, self.keys)))
            action = self.post(action)
        return np.asarray(action.detach().cpu().numpy(), dtype=np.float32).reshape(-1)
