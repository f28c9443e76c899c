"""Parameter set of the demonstration datasets: ``config/record.yaml``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

from ..config_ranges import CELL_COORDINATE_M, Range, check_ranges, count, length_m, require

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

    RANGES: ClassVar[Mapping[str, Range]] = {
        "record_fps_hz": count(1, 120, " Hz"),
        "image_width_px": count(16, MAX_IMAGE_PX, " px"),
        "image_height_px": count(16, MAX_IMAGE_PX, " px"),
        "scene_lookat_m": CELL_COORDINATE_M,
        "scene_distance_m": length_m(5.0),
        "scene_azimuth_deg": Range(-360.0, 360.0, unit=" deg"),
        "scene_elevation_deg": Range(-90.0, 90.0, unit=" deg"),
        "depth_max_m": length_m(10.0),
        "video_file_size_mb": Range(0.0, 10_000.0, lo_open=True, unit=" MB"),
    }

    def validate(self) -> None:
        check_ranges(self, "record")
        for name in ("image_width_px", "image_height_px"):
            v = getattr(self, name)
            # even sides: the video encoders' 4:2:0 chroma needs them
            require(v % 2 == 0, "record", name, v, "an even number of pixels")
            require(not self.use_videos or v >= MIN_VIDEO_IMAGE_PX, "record", name, v,
                    f"at least {MIN_VIDEO_IMAGE_PX} px for video datasets (the AV1 encoder fails "
                    "on smaller frames), or record.use_videos=false")
        require(len(self.scene_lookat_m) == 3, "record", "scene_lookat_m", self.scene_lookat_m,
                "3 values (x, y, z)")
        require("{object}" in self.task_template, "record", "task_template", self.task_template,
                "a sentence containing {object}")
        require("/" in self.repo_id, "record", "repo_id", self.repo_id, "'owner/name'")
