"""Parameter set of the run's video: ``config/video.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import ConfigError

#: Largest video image side [px].
MAX_VIDEO_PX = 1920


@dataclass(frozen=True)
class VideoConfig:
    """The MP4 of a run: rendered by its own third-person view at ``video_fps`` (simulated
    time) and ``video_width_px`` x ``video_height_px``, independent of the eye-in-hand
    camera (which renders only when perception looks)."""

    video_fps: float = 10.0
    video_width_px: int = 320
    video_height_px: int = 240

    def validate(self) -> None:
        if not 0.0 < self.video_fps <= 120.0:
            raise ConfigError(f"video_fps must be in (0, 120], got {self.video_fps}")
        for name in ("video_width_px", "video_height_px"):
            v = getattr(self, name)
            # even sides: the H.264 encoder's 4:2:0 chroma needs them
            if not (16 <= v <= MAX_VIDEO_PX and v % 2 == 0):
                raise ConfigError(f"{name} must be an even number in 16..{MAX_VIDEO_PX}, got {v}")


#: Largest JPEG quality of the recorded camera images.
MAX_JPEG_QUALITY = 100


@dataclass(frozen=True)
class RerunConfig:
    """What a Rerun recording (``--rerun``) keeps, and how often (simulated time).

    The robot's state (TCP pose, executed path, finger gap) is sampled at
    ``rerun_state_rate_hz``; camera images and point clouds are logged at most
    ``rerun_frame_rate_hz`` (plus the frame at each key stage: end of the rough view, each
    scan probe, end of the scan, each new look); boxes and perception times every frame.
    A cloud keeps at most ``rerun_max_object_points`` / ``rerun_max_environment_points``
    (fixed stride); RGB is stored as JPEG of ``rerun_jpeg_quality`` (0: raw pixels); a
    planned path is drawn through at most ``rerun_plan_samples`` points."""

    rerun_state_rate_hz: float = 20.0
    rerun_frame_rate_hz: float = 2.0
    rerun_max_object_points: int = 20000
    rerun_max_environment_points: int = 20000
    rerun_jpeg_quality: int = 85
    rerun_plan_samples: int = 60

    def validate(self) -> None:
        for name in ("rerun_state_rate_hz", "rerun_frame_rate_hz"):
            v = getattr(self, name)
            if not 0.0 < v <= 1000.0:
                raise ConfigError(f"{name} must be in (0, 1000] Hz, got {v}")
        for name in ("rerun_max_object_points", "rerun_max_environment_points"):
            if getattr(self, name) < 0:
                raise ConfigError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not 0 <= self.rerun_jpeg_quality <= MAX_JPEG_QUALITY:
            raise ConfigError(f"rerun_jpeg_quality must be in 0..{MAX_JPEG_QUALITY} (0: raw RGB), "
                              f"got {self.rerun_jpeg_quality}")
        if self.rerun_plan_samples < 2:
            raise ConfigError(f"rerun_plan_samples must be >= 2, got {self.rerun_plan_samples}")
