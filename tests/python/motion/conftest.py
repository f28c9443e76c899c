"""Shared fixtures of the motion-layer tests (robot model pieces are built once per module)."""

import numpy as np
import pytest

from grasp_pipeline.motion.config import load_motion_config
from grasp_pipeline.motion.motion_planner import MotionPlanner


@pytest.fixture(scope="module")
def motion_config():
    return load_motion_config()


@pytest.fixture(scope="module")
def planner(motion_config):
    return MotionPlanner(motion_config)


@pytest.fixture()
def rng():
    return np.random.default_rng(1234)


def _table_cloud(rng, n=60000, z=0.2, x=(0.25, 1.0), y=(-0.6, 0.6)):
    """Synthetic perceived table top: points on z = 0.2 m with 1 mm noise."""
    return np.c_[rng.uniform(*x, n), rng.uniform(*y, n), z + rng.normal(0.0, 0.001, n)]


def _box_cloud(lo, hi, step=0.005):
    """Synthetic perceived box: the surface points of an axis-aligned box."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    axes = [np.arange(lo[k], hi[k] + 1e-9, step) for k in range(3)]
    g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    on = np.any(np.isclose(g, lo, atol=step / 2) | np.isclose(g, g.max(axis=0), atol=step / 2), axis=1)
    return g[on]


@pytest.fixture()
def table_cloud():
    return _table_cloud


@pytest.fixture()
def box_cloud():
    return _box_cloud
