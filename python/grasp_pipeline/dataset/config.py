"""Parameter set of the demonstration datasets: ``config/record.yaml``."""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import ConfigError

#: Largest recorded image side [px].
MAX_IMAGE_PX = 1024
#: Smallest image side of video datasets [px]: LeRobot's AV1 encoder (SVT-AV1) kills the
#: process (SIGFPE) on frames of 24 px and less.
MIN_VIDEO_IMAGE_PX = 32


@dataclass(frozen=True)
class RecordConfig:
    """What ``grasp-pipeline record`` samples and how it writes it (see ``record.yaml``)."""

    record_fps_hz: int = 15
    image_width_px: int = 256
    image_height_px: int = 256
    scene_lookat_m: tuple[float, ...] = (0.45, 0.2, 0.25)
    scene_distance_m: float = 1.4
    scene_azimuth_deg: float = 120.0
    scene_elevation_deg: float = -35.0
    depth_max_m: float = 3.0
    render_shadows: bool = False
    render_reflections: bool = False
    use_videos: bool = True
    video_codec: str = "libsvtav1"
    video_file_size_mb: float = 20.0
    repo_id: str = "grasp_pipeline/picks"
    robot_type: str = "franka_panda"
    task_template: str = "pick up the {object} and put it in the tray"

    def validate(self) -> None:
        if not 1 <= self.record_fps_hz <= 120:
            raise ConfigError(f"record_fps_hz must be an integer in 1..120, got {self.record_fps_hz}")
        for name in ("image_width_px", "image_height_px"):
            v = getattr(self, name)
            # even sides: the video encoders' 4:2:0 chroma needs them
            if not (16 <= v <= MAX_IMAGE_PX and v % 2 == 0):
                raise ConfigError(f"{name} must be an even number in 16..{MAX_IMAGE_PX}, got {v}")
            if self.use_videos and v < MIN_VIDEO_IMAGE_PX:
                raise ConfigError(f"{name} must be at least {MIN_VIDEO_IMAGE_PX} px for video datasets "
                                  f"(the AV1 encoder fails on smaller frames), got {v}; or set "
                                  "record.use_videos=false")
        if not self.video_file_size_mb > 0:
            raise ConfigError(f"video_file_size_mb must be > 0, got {self.video_file_size_mb}")
        if len(self.scene_lookat_m) != 3:
            raise ConfigError(f"scene_lookat_m must have 3 values, got {self.scene_lookat_m}")
        if self.scene_distance_m <= 0 or self.depth_max_m <= 0:
            raise ConfigError("scene_distance_m and depth_max_m must be > 0")
        if "{object}" not in self.task_template:
            raise ConfigError(f"task_template must contain {{object}}, got {self.task_template!r}")
        if "/" not in self.repo_id:
            raise ConfigError(f"repo_id must look like 'owner/name', got {self.repo_id!r}")
