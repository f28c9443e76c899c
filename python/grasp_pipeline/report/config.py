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
