"""Parameter set of the learning environment and its reference policy: ``config/env.yaml``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import Range, check_ranges, count, duration_s, require


@dataclass(frozen=True)
class PickEnvConfig:
    """The episode rules of ``grasp_pipeline/PickPlace-v0``, the reference policy's choices and
    the size of the worker jobs of ``record`` and ``eval`` (see ``env.yaml``)."""

    time_limit_s: float = 60.0
    rest_speed_mps: float = 0.02
    rest_angular_speed_rad_s: float = 0.5
    unique_target: bool = True
    reference_scan: bool = True
    reference_attempts: int = 2
    reference_wait_s: float = 2.0
    episodes_per_job: int = 4

    RANGES: ClassVar[Mapping[str, Range]] = {
        "time_limit_s": duration_s(),
        "rest_speed_mps": Range(0.0, 1.0, lo_open=True, unit=" m/s"),
        "rest_angular_speed_rad_s": Range(0.0, 10.0, lo_open=True, unit=" rad/s"),
        "reference_attempts": count(1, 20),
        "reference_wait_s": duration_s(60.0, zero=True),
        "episodes_per_job": count(1, 1000),
    }

    def validate(self) -> None:
        check_ranges(self, "env")


@dataclass(frozen=True)
class TrainConfig:
    """``grasp-pipeline train``: the ACT policy and its optimisation (see ``train.yaml``)."""

    steps: int = 2000
    batch_size: int = 8
    optimizer_lr: float = 1.0e-5
    optimizer_weight_decay: float = 1.0e-4
    chunk_size: int = 30
    n_action_steps: int = 30
    dim_model: int = 512
    dim_feedforward: int = 3200
    n_heads: int = 8
    n_encoder_layers: int = 4
    n_decoder_layers: int = 1
    latent_dim: int = 32
    use_vae: bool = True
    kl_weight: float = 10.0
    vision_backbone: str = "resnet18"
    torch_threads: int = 0
    dataloader_workers: int = 0
    log_every_steps: int = 50

    RANGES: ClassVar[Mapping[str, Range]] = {
        "steps": count(1, 10_000_000), "batch_size": count(1, 4096),
        "optimizer_lr": Range(0.0, 1.0, lo_open=True), "optimizer_weight_decay": Range(0.0, 1.0),
        "chunk_size": count(1, 1000), "n_action_steps": count(1, 1000),
        "dim_model": count(1, 8192), "dim_feedforward": count(1, 65536), "n_heads": count(1, 128),
        "n_encoder_layers": count(1, 64), "n_decoder_layers": count(1, 64),
        "latent_dim": count(1, 4096), "kl_weight": Range(0.0, 1e6),
        "torch_threads": count(0, 1024), "dataloader_workers": count(0, 256),
        "log_every_steps": count(1, 1_000_000),
    }

    def validate(self) -> None:
        check_ranges(self, "train")
        require(self.n_action_steps <= self.chunk_size, "train", "n_action_steps", self.n_action_steps,
                f"at most chunk_size = {self.chunk_size}")
        require(self.dim_model % self.n_heads == 0, "train", "dim_model", self.dim_model,
                f"a multiple of n_heads = {self.n_heads}")
        require(self.vision_backbone.startswith("resnet"), "train", "vision_backbone",
                self.vision_backbone, "a torchvision ResNet (resnet18, resnet34, ...)")
