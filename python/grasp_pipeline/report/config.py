"""Parameter set of the run's video: ``config/video.yaml``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import RATE_HZ, Range, check_ranges, count, require

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

    RANGES: ClassVar[Mapping[str, Range]] = {
        "video_fps": Range(0.0, 120.0, lo_open=True, unit=" Hz"),
        "video_width_px": count(16, MAX_VIDEO_PX, " px"),
        "video_height_px": count(16, MAX_VIDEO_PX, " px"),
    }

    def validate(self) -> None:
        check_ranges(self, "video")
        for name in ("video_width_px", "video_height_px"):
            v = getattr(self, name)
            # even sides: the H.264 encoder's 4:2:0 chroma needs them
            require(v % 2 == 0, "video", name, v, f"an even number in 16..{MAX_VIDEO_PX}")


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

    RANGES: ClassVar[Mapping[str, Range]] = {
        "rerun_state_rate_hz": RATE_HZ,
        "rerun_frame_rate_hz": RATE_HZ,
        "rerun_max_object_points": count(0, 10_000_000),
        "rerun_max_environment_points": count(0, 10_000_000),
        "rerun_jpeg_quality": count(0, MAX_JPEG_QUALITY, " (0: raw RGB)"),
        "rerun_plan_samples": count(2, 10_000),
    }

    def validate(self) -> None:
        check_ranges(self, "rerun")
