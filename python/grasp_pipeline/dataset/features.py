"""The dataset's LeRobot features (keys, dtypes, shapes, names) and one frame's values.

Keys follow LeRobot's conventions: ``observation.images.<camera>`` (RGB, as video streams or
PNG images), ``observation.state``, ``action``; ours besides: ``observation.depth.<camera>``
(with ``--depth``), ``observation.ee_pose``, ``action.ee_delta``, and per frame the
episode's outcome (``next.done``/``next.success`` on the last frame as LeRobot's simulation
datasets mark it; ``episode.success`` and ``episode.failed_stage`` on every frame).
"""

from __future__ import annotations

import numpy as np

from .camera_views import CAMERAS
from .config import RecordConfig
from .episode import ACTION_NAMES, EE_DELTA_NAMES, EE_POSE_NAMES, STATE_NAMES, Episode

_IMAGE_NAMES = ["height", "width", "channels"]


def _vector(names: tuple) -> dict:
    return {"dtype": "float32", "shape": (len(names),), "names": list(names)}


def _flag() -> dict:
    return {"dtype": "bool", "shape": (1,), "names": None}


def dataset_features(config: RecordConfig, depth: bool = False) -> dict:
    """The features dict of ``LeRobotDataset.create``."""
    h, w = config.image_height_px, config.image_width_px
    image = "video" if config.use_videos else "image"
    out = {f"observation.images.{c}": {"dtype": image, "shape": (h, w, 3), "names": list(_IMAGE_NAMES)}
           for c in CAMERAS}
    if depth:
        out.update({f"observation.depth.{c}": {"dtype": "float32", "shape": (h, w, 1),
                                                "names": list(_IMAGE_NAMES)} for c in CAMERAS})
    out["observation.state"] = _vector(STATE_NAMES)
    out["observation.ee_pose"] = _vector(EE_POSE_NAMES)
    out["action"] = _vector(ACTION_NAMES)
    out["action.ee_delta"] = _vector(EE_DELTA_NAMES)
    out["next.done"] = _flag()
    out["next.success"] = _flag()
    out["episode.success"] = _flag()
    out["episode.failed_stage"] = {"dtype": "string", "shape": (1,), "names": None}
    return out


def frame_values(ep: Episode, i: int, depth: bool = False) -> dict:
    """Frame ``i`` of ``ep`` as ``LeRobotDataset.add_frame`` takes it (with its task)."""
    last = i == ep.length - 1
    frame = {f"observation.images.{c}": ep.images[c][i] for c in CAMERAS}
    if depth:
        frame.update({f"observation.depth.{c}": ep.depths[c][i][..., None] for c in CAMERAS})
    frame.update({
        "observation.state": ep.state[i], "observation.ee_pose": ep.ee_pose[i],
        "action": ep.action[i], "action.ee_delta": ep.action_ee_delta[i],
        "next.done": np.array([last]), "next.success": np.array([last and ep.success]),
        "episode.success": np.array([ep.success]), "episode.failed_stage": ep.failed_stage,
        "task": ep.task})
    return frame
