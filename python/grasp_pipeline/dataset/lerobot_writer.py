"""Writing episodes as a LeRobot dataset (format v3.0) through LeRobot's own writer.

LeRobot is an optional extra (``pip install 'grasp-pipeline[dataset]'``); :func:`require_lerobot`
checks for it before anything is simulated. :class:`LeRobotWriter` wraps
``LeRobotDataset.create`` → ``add_frame`` … ``save_episode`` → ``finalize``; besides LeRobot's
files it writes ``meta/grasp_pipeline_episodes.jsonl`` (per episode: task, success, failed
stage, message, target object, scene seed and attempt).
"""

from __future__ import annotations

import json
import logging
import os
from pathlib import Path

from ..exceptions import GraspPipelineError
from .config import RecordConfig
from .episode import Episode
from .features import dataset_features, frame_values

log = logging.getLogger(__name__)

#: Our per-episode outcome file, inside the dataset's ``meta`` folder.
OUTCOMES_FILE = "meta/grasp_pipeline_episodes.jsonl"
#: SVT-AV1 (the AV1 encoder) logs a banner per video to stderr; errors only (1) unless set.
SVT_LOG_LEVEL = "1"
#: The LeRobot release this writer is written and tested against.
LEROBOT_VERSION = "0.4.4"
INSTALL_HINT = ("pip install 'grasp-pipeline[dataset]' (or, in a checkout: pip install '.[dataset]'); "
                "see the README's 'Datasets' section for a CPU/CI install")


class DatasetUnavailable(GraspPipelineError):
    """LeRobot (the optional extra ``dataset``) is not installed or cannot be imported."""


def require_lerobot():
    """LeRobot's dataset class, or :class:`DatasetUnavailable` saying how to install it."""
    try:
        from lerobot.datasets.lerobot_dataset import LeRobotDataset
    except ImportError as exc:
        raise DatasetUnavailable(f"record needs LeRobot {LEROBOT_VERSION} ({exc}): {INSTALL_HINT}") from exc
    except Exception as exc:  # a broken install (e.g. a torch/torchvision mismatch)
        raise DatasetUnavailable(f"LeRobot cannot be imported ({type(exc).__name__}: {exc}): "
                                 f"{INSTALL_HINT}") from exc
    return LeRobotDataset


class LeRobotWriter:
    """One dataset at ``root`` (which must not exist yet); :meth:`add` episodes, then :meth:`close`."""

    def __init__(self, root: Path, config: RecordConfig, depth: bool = False) -> None:
        LeRobotDataset = require_lerobot()
        os.environ.setdefault("SVT_LOG", SVT_LOG_LEVEL)
        self.root, self.depth = Path(root), depth
        self.dataset = LeRobotDataset.create(
            repo_id=config.repo_id, fps=int(config.record_fps_hz), root=self.root,
            features=dataset_features(config, depth), robot_type=config.robot_type,
            use_videos=config.use_videos, vcodec=config.video_codec)
        self.outcomes: list[dict] = []

    def add(self, episode: Episode, extra: dict) -> None:
        """Append one episode (all its frames); ``extra``: outcome fields to list with it."""
        for i in range(episode.length):
            self.dataset.add_frame(frame_values(episode, i, self.depth))
        self.dataset.save_episode(parallel_encoding=False)  # (one process: the workers use the cores)
        self.outcomes.append({"episode_index": len(self.outcomes), **episode.outcome(), **extra})

    def close(self) -> None:
        """Finish the files (LeRobot's ``finalize``) and write the outcome list."""
        self.dataset.finalize()
        path = self.root / OUTCOMES_FILE
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("".join(json.dumps(o) + "\n" for o in self.outcomes))
