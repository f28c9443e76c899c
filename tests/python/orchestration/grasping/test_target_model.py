"""The target's solid model: seen points, filled columns, normals."""

import numpy as np

from grasp_pipeline.orchestration.grasping.target_model import target_model
from grasp_pipeline.orchestration.scene.scene_cloud import SceneCloud

CELL = 0.005


def _grid(x0, x1, y0, y1, z, step=0.002):
    x, y = np.meshgrid(np.arange(x0, x1, step), np.arange(y0, y1, step), indexing="ij")
    return np.column_stack([x.ravel(), y.ravel(), np.full(x.size, z)])


def test_a_column_stops_at_what_lies_under_it_even_just_beside_the_target_points():
    """A target's column is filled down to the highest other point seen under it in its cell —
    also when that point lies beside the target's points (outside their extent, in the same
    cell) — and down to the table where nothing is under it."""
    top = _grid(0.0005, 0.0296, 0.0005, 0.0296, 0.10)  # x up to 0.0295: cells 0..5
    under = _grid(0.0297, 0.0300, 0.0005, 0.0296, 0.04, step=0.0002)  # cell 5 in x, beside the top
    far = _grid(0.5, 0.52, 0.5, 0.52, 0.02)
    pts = np.vstack([top, under, far])
    owner = np.r_[np.full(len(top), 1), np.full(len(under) + len(far), 2)]
    cloud = SceneCloud(pts, owner, np.array([0.0, 0.0, 1.0]), 0.0, 0.005)
    model = target_model(cloud, 1, np.array([0.0, 0.0, 1.0]), CELL, 100000)
    filled = model.points[~model.seen]
    col5 = np.floor(filled[:, 0] / CELL) == 5
    assert np.any(col5) and np.any(~col5)
    assert filled[col5, 2].min() > 0.04  # stopped above what lies under it
    assert filled[~col5, 2].min() < CELL  # the other columns reach the table
