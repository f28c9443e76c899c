"""``grasp-pipeline train``: a small LeRobot policy (ACT) trained from scratch on a ``record``
dataset, saved as LeRobot saves policies (``save_pretrained`` of the policy and of its pre- and
post-processors) so that ``grasp-pipeline eval --policy DIR`` (and ``lerobot-eval``) load it.

``train --dataset DIR --out DIR [--steps N] [--batch-size B] [--seed S] [--device cpu|cuda]
[--image-size PX] [--fps N] [--config FILE] [--set train.NAME=VALUE]``

The policy's inputs are the environment's wrist and scene images and ``observation.state``, its
output ``action`` (``train.yaml``: the ACT sizes; ``pretrained_backbone_weights`` none: nothing
is downloaded). The dataset must have been recorded with the options the environment will run
with (``--image-size``, ``--fps``; checked before training). Its successful episodes are used.
The policy and ``train_summary.json`` (dataset, episodes, frames, steps, time, losses) are
written to a staging folder next to ``--out`` and moved in with one rename; on Ctrl-C / SIGTERM
the policy trained so far is saved, with ``"status": "interrupted"``.
"""

from __future__ import annotations

import json
import logging
import math
import os
import random
import time
from pathlib import Path
from typing import Optional

from ..exceptions import InputError

log = logging.getLogger(__name__)

SUMMARY_FILE = "train_summary.json"
#: The environment's observations the policy takes as inputs.
POLICY_INPUTS = ("observation.images.wrist", "observation.images.scene", "observation.state")


def _settings(overrides: tuple, fps: Optional[int], image_size: Optional[int]):
    from ..dataset.record_settings import record_overrides
    from ..settings import load_settings

    config_file, sets = record_overrides(overrides, fps, image_size)
    return load_settings(["record", "train"], config_file, list(sets))


def check_out(out: Path) -> Path:
    out = Path(out)
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise InputError(f"--out {out} exists and is not an empty folder: choose a new folder")
    return out


def successful_episodes(root: Path) -> list[int]:
    """Indices of the dataset's successful episodes (all, without ``record``'s outcome list)."""
    from ..dataset.lerobot_writer import OUTCOMES_FILE

    path = Path(root) / OUTCOMES_FILE
    if not path.is_file():
        return []
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return [int(r["episode_index"]) for r in rows if r.get("success")]


def act_config(meta, cfg, device: str):
    """LeRobot's ``ACTConfig`` for the dataset's features (inputs :data:`POLICY_INPUTS`)."""
    from lerobot.configs.types import FeatureType, PolicyFeature
    from lerobot.datasets.utils import dataset_to_policy_features
    from lerobot.policies.act.configuration_act import ACTConfig

    feats = dataset_to_policy_features(meta.features)
    inputs = {k: feats[k] for k in POLICY_INPUTS}
    output = {"action": PolicyFeature(FeatureType.ACTION, tuple(feats["action"].shape))}
    return ACTConfig(input_features=inputs, output_features=output, device=device,
                     pretrained_backbone_weights=None, push_to_hub=False,
                     chunk_size=cfg.chunk_size, n_action_steps=cfg.n_action_steps,
                     vision_backbone=cfg.vision_backbone, dim_model=cfg.dim_model,
                     dim_feedforward=cfg.dim_feedforward, n_heads=cfg.n_heads,
                     n_encoder_layers=cfg.n_encoder_layers, n_decoder_layers=cfg.n_decoder_layers,
                     latent_dim=cfg.latent_dim, use_vae=cfg.use_vae, kl_weight=cfg.kl_weight,
                     optimizer_lr=cfg.optimizer_lr, optimizer_lr_backbone=cfg.optimizer_lr,
                     optimizer_weight_decay=cfg.optimizer_weight_decay)


def check_inputs(dataset, out, settings, device: str):
    """(LeRobot metadata, episodes to train on, output folder); :class:`InputError` first."""
    from .compatibility import check_dataset
    from .spaces import observation_features

    if device not in ("cpu", "cuda"):
        raise InputError(f"--device must be cpu or cuda, got {device!r}")
    out = check_out(out)
    env_feats = {k: v for k, v in observation_features(settings.record).items() if k in POLICY_INPUTS}
    meta = check_dataset(dataset, env_feats, settings.record.record_fps_hz)
    episodes = successful_episodes(Path(dataset)) or list(range(meta.total_episodes))
    if not episodes:
        raise InputError(f"--dataset {dataset} holds no episodes")
    if device == "cuda":
        import torch

        if not torch.cuda.is_available():
            raise InputError("--device cuda: torch finds no CUDA device here (use --device cpu)")
    return meta, episodes, out


class _Training:
    """The policy, its processors, the optimiser and the data (built from the checked inputs)."""

    def __init__(self, root: Path, meta, episodes: list[int], cfg, device: str, seed: int) -> None:
        import torch
        from lerobot.datasets.lerobot_dataset import LeRobotDataset
        from lerobot.policies.act.modeling_act import ACTPolicy
        from lerobot.policies.factory import make_pre_post_processors

        random.seed(seed)
        torch.manual_seed(seed)
        if cfg.torch_threads:
            torch.set_num_threads(cfg.torch_threads)
        self.cfg, self.device = cfg, device
        self.policy_cfg = act_config(meta, cfg, device)
        delta = {"action": [i / meta.fps for i in self.policy_cfg.action_delta_indices]}
        self.dataset = LeRobotDataset(meta.repo_id, root=root, episodes=episodes, delta_timestamps=delta)
        self.policy = ACTPolicy(self.policy_cfg).to(device)
        self.pre, self.post = make_pre_post_processors(self.policy_cfg, dataset_stats=meta.stats)
        self.optimizer = self.policy_cfg.get_optimizer_preset().build(self.policy.get_optim_params())
        gen = torch.Generator().manual_seed(seed)
        self.loader = torch.utils.data.DataLoader(
            self.dataset, batch_size=cfg.batch_size, shuffle=True, generator=gen, drop_last=True,
            num_workers=cfg.dataloader_workers)

    def batches(self):
        while True:
            yield from self.loader

    def step(self, batch) -> float:
        import torch

        self.policy.train()
        loss, _ = self.policy.forward(self.pre(batch))
        loss.backward()
        torch.nn.utils.clip_grad_norm_(self.policy.parameters(), 10.0)
        self.optimizer.step()
        self.optimizer.zero_grad()
        return float(loss.item())

    def save(self, folder: Path) -> None:
        self.policy.save_pretrained(folder)
        self.pre.save_pretrained(folder)
        self.post.save_pretrained(folder)


def _optimise(tr: _Training, steps: int, batch_size: int) -> tuple[list, int, bool]:
    """Run the steps; (logged losses [(step, loss)], steps done, interrupted)."""
    if len(tr.dataset) < batch_size:
        raise InputError(f"the dataset has {len(tr.dataset)} frames, fewer than --batch-size {batch_size}")
    losses, done, every = [], 0, tr.cfg.log_every_steps
    batches = tr.batches()
    try:
        for done in range(1, steps + 1):
            loss = tr.step(next(batches))
            if not math.isfinite(loss):
                raise FloatingPointError(f"the loss became {loss} at step {done}")
            if done % every == 0 or done == steps or done == 1:
                losses.append((done, loss))
                log.info("step %d/%d: loss %.4f", done, steps, loss)
    except KeyboardInterrupt:
        log.error("interrupted at step %d: saving the policy trained so far", done)
        return losses, max(done - 1, 0), True
    return losses, done, False


def train_policy(dataset, out, steps: Optional[int] = None, batch_size: Optional[int] = None,
                 seed: int = 0, device: str = "cpu", fps: Optional[int] = None,
                 image_size: Optional[int] = None, overrides: tuple = (None, ())) -> dict:
    """Train and save (see the module doc); returns the summary."""
    from ..app.run_command import sigterm_as_interrupt
    from ..dataset import dataset_folder as df
    from ..report.serialize import write_json

    settings = _settings(overrides, fps, image_size)
    cfg = settings.train
    steps, batch_size = int(steps or cfg.steps), int(batch_size or cfg.batch_size)
    if steps < 1 or batch_size < 1:
        raise InputError("--steps and --batch-size must be >= 1")
    meta, episodes, out = check_inputs(dataset, out, settings, device)
    t0 = time.perf_counter()
    with sigterm_as_interrupt():
        tr = _Training(Path(dataset), meta, episodes, cfg, device, seed)
        losses, done, interrupted = _optimise(tr, steps, batch_size)
    summary = {"status": "interrupted" if interrupted else "complete", "policy": "act",
               "dataset": str(dataset), "episodes": len(episodes), "frames": len(tr.dataset),
               "steps_requested": steps, "steps": done, "batch_size": batch_size, "seed": seed,
               "device": device, "wall_s": round(time.perf_counter() - t0, 3),
               "final_loss": losses[-1][1] if losses else None, "losses": losses,
               "parameters": sum(p.numel() for p in tr.policy.parameters()),
               "image_size": list(meta.features[POLICY_INPUTS[0]]["shape"][:2]), "fps": meta.fps}
    staging = Path(out).parent / f".{Path(out).name}.writing"
    df.discard(staging)
    tr.save(staging)
    write_json(staging / SUMMARY_FILE, summary)
    os.rename(staging, out)
    return summary


def train_main(args) -> int:
    """The ``train`` sub-command; exit code 0 when complete, 130 when interrupted."""
    from ..report.serialize import dumps

    summary = train_policy(args.dataset, args.out, steps=args.steps, batch_size=args.batch_size,
                           seed=args.seed, device=args.device, fps=args.fps, image_size=args.image_size,
                           overrides=(args.config, args.sets))
    print(dumps({k: v for k, v in summary.items() if k != "losses"}, sort_keys=True))
    return 0 if summary["status"] == "complete" else 130
