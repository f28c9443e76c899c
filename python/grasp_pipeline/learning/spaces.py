"""Gymnasium spaces made from the dataset's features: the environment's observation and
action spaces are the ``observation.*`` and ``action`` features of a ``record`` dataset
(:func:`grasp_pipeline.dataset.features.dataset_features`) — same keys, shapes and dtypes."""

from __future__ import annotations

import numpy as np

from ..dataset.config import RecordConfig
from ..dataset.features import dataset_features
from .interface import ACTION, ACTION_HIGH, ACTION_LOW


def observation_features(config: RecordConfig, depth: bool = False) -> dict:
    """The dataset's ``observation.*`` features (key -> LeRobot feature dict)."""
    return {k: v for k, v in dataset_features(config, depth).items() if k.startswith("observation.")}


def _box(feature: dict, depth_max_m: float):
    from gymnasium import spaces

    shape = tuple(int(s) for s in feature["shape"])
    if feature["dtype"] in ("video", "image"):
        return spaces.Box(0, 255, shape=shape, dtype=np.uint8)
    if len(shape) == 3:  # a depth image [m]
        return spaces.Box(0.0, float(depth_max_m), shape=shape, dtype=np.float32)
    return spaces.Box(-np.inf, np.inf, shape=shape, dtype=np.dtype(feature["dtype"]))


def observation_space(config: RecordConfig, depth: bool = False):
    """``spaces.Dict`` of the observation features."""
    from gymnasium import spaces

    return spaces.Dict({k: _box(f, config.depth_max_m)
                        for k, f in observation_features(config, depth).items()})


def action_space(config: RecordConfig):
    """``spaces.Box`` of the ``action`` feature, bounded by the joint limits and the gripper's
    opening."""
    from gymnasium import spaces

    shape = tuple(dataset_features(config)[ACTION]["shape"])
    assert shape == ACTION_LOW.shape, (shape, ACTION_LOW.shape)
    return spaces.Box(ACTION_LOW, ACTION_HIGH, shape=shape, dtype=np.float32)
