"""Parameter set of the learning environment and its reference policy: ``config/env.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import ConfigError


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

    def validate(self) -> None:
        if not self.time_limit_s > 0:
            raise ConfigError(f"time_limit_s must be > 0, got {self.time_limit_s}")
        if not (self.rest_speed_mps > 0 and self.rest_angular_speed_rad_s > 0):
            raise ConfigError("rest_speed_mps and rest_angular_speed_rad_s must be > 0")
        if self.reference_attempts < 1 or self.episodes_per_job < 1:
            raise ConfigError("reference_attempts and episodes_per_job must be >= 1")
        if self.reference_wait_s < 0:
            raise ConfigError(f"reference_wait_s must be >= 0, got {self.reference_wait_s}")


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

    def validate(self) -> None:
        ints = ("steps", "batch_size", "chunk_size", "n_action_steps", "dim_model", "dim_feedforward",
                "n_heads", "n_encoder_layers", "n_decoder_layers", "latent_dim", "log_every_steps")
        bad = [n for n in ints if getattr(self, n) < 1]
        if bad:
            raise ConfigError(f"train: {', '.join(bad)} must be >= 1")
        if self.n_action_steps > self.chunk_size:
            raise ConfigError(f"train: n_action_steps ({self.n_action_steps}) must not exceed "
                              f"chunk_size ({self.chunk_size})")
        if self.dim_model % self.n_heads:
            raise ConfigError(f"train: dim_model ({self.dim_model}) must be a multiple of n_heads ({self.n_heads})")
        if not self.optimizer_lr > 0 or self.optimizer_weight_decay < 0:
            raise ConfigError("train: optimizer_lr must be > 0 and optimizer_weight_decay >= 0")
        if self.torch_threads < 0 or self.dataloader_workers < 0:
            raise ConfigError("train: torch_threads and dataloader_workers must be >= 0")
        if not self.vision_backbone.startswith("resnet"):
            raise ConfigError(f"train: vision_backbone must be a torchvision ResNet, got {self.vision_backbone!r}")
